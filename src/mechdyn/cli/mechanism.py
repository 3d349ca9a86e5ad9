"""``mechdyn mechanism``: kinematics and inverse dynamics of a planar mechanism over one revolution."""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.cli.common import AnalysisOutput, Table, add_common_options, column_unit, run_analysis
from mechdyn.errors import ModelFileError, ModelWarning
from mechdyn.io.modelfile import ModelSource
from mechdyn.mechanism.dynamics import inverse_dynamics
from mechdyn.mechanism.model import GearJoint
from mechdyn.mechanism.plots import (
    plot_frames,
    plot_inertia_forces,
    plot_joint_forces,
    plot_output_motion,
    plot_shaking_polar,
    plot_torque,
    plot_trajectory,
)
from mechdyn.mechanism.schema import MechanismSpec

__all__ = ["register"]

UNITS = {
    "stroke_m": "m",
    "bdc_deg": "deg",
    "tdc_deg": "deg",
    "return_stroke_deg": "deg",
    "working_stroke_deg": "deg",
    "inertia_force_max_N": "N",
    "inertia_force_max_deg": "deg",
    "inertia_force_min_N": "N",
    "inertia_force_min_deg": "deg",
    "inertia_force_fluctuation_N": "N",
    "driving_torque_max_Nm": "N·m",
    "driving_torque_min_Nm": "N·m",
    "driving_torque_peak_Nm": "N·m",
    "driving_torque_rms_Nm": "N·m",
    "shaking_force_max_N": "N",
    "shaking_moment_range_Nm": "N·m",
    "shaking_force_x_range_N": "N",
    "shaking_force_y_range_N": "N",
    "tooth_force_max_N": "N",
    "power_balance_residual_relative": "",
}


def _mechanism_command(args: argparse.Namespace) -> int:
    def analyse(model: Any, source: ModelSource) -> AnalysisOutput:
        if not isinstance(model, MechanismSpec):
            raise ModelFileError(
                source.path,
                "[model] → type",
                f'{source.model_type!r} is not a mechanism model; this command needs type = "mechanism"',
            )
        n = args.angles or model.n_angles
        d = inverse_dynamics(model.mechanism, n)
        summary = d.summary()
        moment = d.shaking_moment()
        summary["shaking_moment_range_Nm"] = float(moment.max() - moment.min())
        peaks = {
            j.name: float(np.linalg.norm(d.joint_load(j.name, j.bodies[1])[:, :2], axis=1).max())
            for j in model.mechanism.joints
        }
        summary["joint_force_peak_N"] = peaks
        F = d.shaking_force
        summary["shaking_force_x_range_N"] = float(np.ptp(F[:, 0]))
        summary["shaking_force_y_range_N"] = float(np.ptp(F[:, 1]))
        gears = [j.name for j in model.mechanism.joints if isinstance(j, GearJoint)]
        if gears:  # the mesh force on gear 2: tangential and, by the pressure angle, normal
            from mechdyn.mechanism.pitch import report

            summary["tooth_force_max_N"] = max(peaks[g] for g in gears)
            summary["gear_pairs"] = {
                j.name: report(model.mechanism.gear_laws[j.name], j.pressure_angle)
                for j in model.mechanism.joints
                if isinstance(j, GearJoint)
            }
            for name, rep in summary["gear_pairs"].items():
                if not rep["convex"]:
                    warnings.warn(
                        f"gear pair {name!r}: a pitch curve is concave; its teeth would be undercut",
                        ModelWarning,
                        stacklevel=2,
                    )
        summary["n_angles"] = n
        frame = d.to_frame()
        if args.csv:
            path = Path(args.csv)
            path.parent.mkdir(parents=True, exist_ok=True)
            frame.to_csv(path, index=False, float_format="%.10g")
        gear_rows = [
            [
                n,
                r["centre_distance_m"] * 1e3,
                r["mean_ratio"],
                r["convex"],
                r["pressure_angle_min_deg"],
                r["pressure_angle_max_deg"],
            ]
            for n, r in summary.get("gear_pairs", {}).items()
        ]
        tables = [
            Table(
                "summary",
                ["quantity", "value", "unit"],
                [[k, v, UNITS.get(k, "")] for k, v in summary.items() if k in UNITS],
            ),
            Table(
                "joint forces (largest over the cycle)",
                ["joint", "force [N]"],
                [[k, v] for k, v in peaks.items()],
            ),
        ]
        if gear_rows:
            tables.append(
                Table(
                    "gear pairs",
                    ["pair", "centre distance [mm]", "mean ratio", "convex", "φ min [deg]", "φ max [deg]"],
                    gear_rows,
                )
            )
        arrays = {name: (frame[name].to_numpy(), column_unit(name)) for name in frame.columns}
        plots = {
            "output_motion.png": lambda: plot_output_motion(d),
            "inertia_forces.png": lambda: plot_inertia_forces(d),
            "driving_torque.png": lambda: plot_torque(d),
            "frames.png": lambda: plot_frames(d),
        }
        plots["joint_forces.png"] = lambda: plot_joint_forces(d)
        plots["shaking_force_polar.png"] = lambda: plot_shaking_polar(d)
        if model.trace:
            plots["trajectory.png"] = lambda: plot_trajectory(d, list(model.trace), model.field_velocity)
        if d.output_position is None:
            plots.pop("output_motion.png")
        return AnalysisOutput("mechanism", {"n_angles": n, "csv": args.csv}, summary, arrays, tables, plots)

    return run_analysis(args, analyse)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("mechanism", help="kinematics and inverse dynamics of a planar mechanism")
    add_common_options(p)
    p.add_argument("--csv", metavar="FILE", help="write the per-angle table (columns named with their units)")
    p.add_argument("--angles", type=int, help="crank angles per revolution (default: the file's, else 360)")
    p.set_defaults(func=_mechanism_command)
