"""``mechdyn mount``: a mount's stiffness from the drawing, its FE reference and its calibration."""

from __future__ import annotations

import argparse
from typing import Any

from mechdyn.cli.common import AnalysisOutput, Table, add_common_options, run_analysis
from mechdyn.errors import ModelFileError
from mechdyn.io.modelfile import ModelSource
from mechdyn.mounts.analysis import analyse
from mechdyn.mounts.bolted import BoltedJoint
from mechdyn.mounts.plots import (
    plot_calibration,
    plot_contact_pressure,
    plot_convergence,
    plot_frf_fit,
    plot_pad_curve,
)
from mechdyn.mounts.schema import MountSpec
from mechdyn.store import ResultStore

__all__ = ["register"]


def _rows(d: dict[str, Any], prefix: str = "") -> list[list[Any]]:
    """Flatten the scalar parts of a breakdown into (quantity, value) rows."""
    rows = []
    for k, v in d.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            rows.append([prefix + k, v])
        elif isinstance(v, str):
            rows.append([prefix + k, v])
    return rows


def _mount_command(args: argparse.Namespace) -> int:
    def analyse_file(spec: Any, source: ModelSource) -> AnalysisOutput:
        if not isinstance(spec, MountSpec):
            raise ModelFileError(
                source.path,
                "[model] → type",
                f'{source.model_type!r} is not a mount model; this command needs type = "mount"',
            )
        with ResultStore(args.db) as store:
            report = analyse(spec, store)
        s, mount = report.summary, report.mount
        tables = [
            Table(
                f"{spec.name} ({spec.kind})",
                ["quantity", "value"],
                [["stiffness along the main axis [N/m]", s["stiffness_N_per_m"]]]
                + [[k, v] for k, v in (("adjusts height", s["adjusts_height"]), ("damps", s["damps"]))]
                + _rows(s["breakdown"]),
            )
        ]
        if isinstance(mount, BoltedJoint):
            tables.append(
                Table(
                    "pressure-cone frusta (in series)",
                    ["layer", "material", "t [mm]", "D [mm]", "k [N/m]"],
                    [
                        [
                            f["layer"] + 1,
                            f["material"],
                            1e3 * f["thickness_m"],
                            1e3 * f["diameter_m"],
                            f["stiffness_N_per_m"],
                        ]
                        for f in s["breakdown"]["frusta"]
                    ],
                )
            )
        if "fe_convergence" in s:
            tables.append(
                Table(
                    "finite-element reference (mesh convergence)",
                    ["elements through thickness", "elements", "unknowns", "stiffness [N/m]"],
                    [
                        [r["elements_through_thickness"], r["elements"], r["dofs"], r["stiffness_N_per_m"]]
                        for r in s["fe_convergence"]
                    ],
                )
            )
        if "contact" in s:
            tables.append(
                Table(
                    "contact pressure, base plate on concrete",
                    ["preload [N]", "max [MPa]", "under the washer [MPa]", "above threshold to r [mm]"],
                    [
                        [
                            c["preload_N"],
                            c["pressure_max_Pa"] / 1e6,
                            c["head_pressure_Pa"] / 1e6,
                            None
                            if c["radius_above_threshold_m"] is None
                            else 1e3 * c["radius_above_threshold_m"],
                        ]
                        for c in s["contact"]
                    ],
                )
            )
        if "calibration" in s:
            c = s["calibration"]
            tables.append(Table("calibration", ["quantity", "value"], _rows(c)))
        if "frf_fit" in s:
            tables.append(Table("fit to the measured FRF", ["quantity", "value"], _rows(s["frf_fit"])))
        if "isolation" in s:
            tables.append(Table("isolation on the given load", ["quantity", "value"], _rows(s["isolation"])))
        plots: dict[str, Any] = {}
        pad = getattr(mount, "pad", mount) if spec.kind in ("pad", "damping_pad") else None
        if pad is not None:
            plots["pad_curve.png"] = lambda: plot_pad_curve(pad)
        if report.fe_levels:
            est = mount.member_stiffness() if isinstance(mount, BoltedJoint) else pad.compression_stiffness
            plots["fe_convergence.png"] = lambda: plot_convergence(report.fe_levels, est)
        if report.anchor is not None:
            plots["contact_pressure.png"] = lambda: plot_contact_pressure(
                report.anchor, spec.fe.preloads, spec.fe.pressure_threshold
            )
        if report.calibration is not None and isinstance(mount, BoltedJoint):
            plots["calibration.png"] = lambda: plot_calibration(
                mount, report.calibration.target, report.calibration.value
            )
        if report.frf is not None:
            plots["frf_fit.png"] = lambda: plot_frf_fit(*report.frf)
        return AnalysisOutput("mount", {"kind": spec.kind}, s, {}, tables, plots)

    return run_analysis(args, analyse_file)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("mount", help="a mount's stiffness from the drawing, FE reference and calibration")
    add_common_options(p)
    p.set_defaults(func=_mount_command)
