"""Drivetrain subcommands: ``modal``, ``campbell``, ``frf``."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from mechdyn.cli.common import AnalysisOutput, Table, add_common_options, run_analysis
from mechdyn.drivetrain import Drivetrain, modal
from mechdyn.drivetrain.campbell import campbell
from mechdyn.drivetrain.compare import compare_rigid
from mechdyn.drivetrain.eigen import SOLVERS
from mechdyn.drivetrain.modal import ModalResult
from mechdyn.drivetrain.response import ModalDamping, frf
from mechdyn.drivetrain.schema import settings
from mechdyn.errors import MechdynError, ModelFileError
from mechdyn.io.modelfile import ModelSource
from mechdyn.units import UnitError, to_si

__all__ = ["register"]


def _need_drivetrain(model: Any, source: ModelSource) -> Drivetrain:
    if not isinstance(model, Drivetrain):
        raise ModelFileError(
            source.path,
            "[model] → type",
            f'{source.model_type!r} is not a drivetrain model; this command needs type = "drivetrain"',
        )
    return model


def _modes_json(r: ModalResult) -> list[dict[str, Any]]:
    out = []
    for m, f in enumerate(r.frequencies_hz):
        el, share = r.dominant_element(m)
        out.append(
            {
                "mode": m + 1,
                "frequency_hz": float(f),
                "dominant_element": el,
                "dominant_element_share": share,
                "shape": dict(zip(r.disk_names, r.unit_shapes[:, m].tolist(), strict=True)),
            }
        )
    return out


def _modal_tables(r: ModalResult, title: str) -> list[Table]:
    names, share = r.strain_energy
    rows = []
    for m, f in enumerate(r.frequencies_hz):
        el, es = r.dominant_element(m)
        d = int(np.argmax(r.kinetic_energy[:, m]))
        rows.append([m + 1, f, el, 100 * es, r.disk_names[d], 100 * r.kinetic_energy[d, m]])
    tables = [
        Table(
            f"{title}: natural frequencies ({r.rigid_body_modes} rigid-body mode(s) set aside)",
            [
                "mode",
                "frequency [Hz]",
                "most strain energy in",
                "share [%]",
                "most kinetic energy in",
                "share [%]",
            ],
            rows,
        )
    ]
    modes = range(len(r.omega))
    if modes:  # a model that only turns as a rigid body has no shapes or strain energy to show
        tables.append(
            Table(
                f"{title}: mode shapes (largest disk angle = 1)",
                ["disk", *[f"mode {m + 1}" for m in modes]],
                [[d, *r.unit_shapes[i].tolist()] for i, d in enumerate(r.disk_names)],
            )
        )
        tables.append(
            Table(
                f"{title}: strain energy per element [%]",
                ["element", *[f"mode {m + 1}" for m in modes]],
                [[n, *(100 * share[i]).tolist()] for i, n in enumerate(names)],
            )
        )
    if r.rigid_body_modes:
        tables.append(
            Table(
                f"{title}: rigid-body modes (0 Hz)",
                ["disk", *[f"rigid {k + 1}" for k in range(r.rigid_body_modes)]],
                [[d, *r.rigid_body_shapes[i].tolist()] for i, d in enumerate(r.disk_names)],
            )
        )
    return tables


def _modal_command(args: argparse.Namespace) -> int:
    def analyse(model: Any, source: ModelSource) -> AnalysisOutput:
        dt = _need_drivetrain(model, source)
        r = modal(dt, rigid_gears=args.rigid_gears, n_modes=args.modes, solver=args.solver)
        label = "rigid gears" if args.rigid_gears else "as modelled"
        summary: dict[str, Any] = {
            "frequencies_hz": r.frequencies_hz.tolist(),
            "rigid_body_modes": r.rigid_body_modes,
            "rigid_gears": bool(args.rigid_gears),
            "solver": r.solver,
            "modes": _modes_json(r),
        }
        tables = _modal_tables(r, label)
        arrays = {"frequencies_hz": (r.frequencies_hz, "Hz"), "mode_shapes": (r.shapes, "rad")}
        plots = {"mode_shapes.png": lambda: r.plot()}
        if args.compare_rigid:
            cmp = compare_rigid(dt)
            summary["comparison"] = cmp.rows
            summary["rigid_frequencies_hz"] = cmp.rigid.frequencies_hz.tolist()
            tables.append(
                Table(
                    "flexible meshes against rigid gears (modes paired by shape, MAC)",
                    [
                        "flexible mode",
                        "flexible [Hz]",
                        "rigid mode",
                        "rigid [Hz]",
                        "MAC",
                        "change [%]",
                        "most strain energy in",
                    ],
                    [
                        [
                            c["flexible_mode"],
                            c["flexible_hz"],
                            c["rigid_mode"],
                            c["rigid_hz"],
                            c["mac"],
                            c["change_percent"],
                            c["dominant_element"],
                        ]
                        for c in cmp.rows
                    ],
                )
            )
            arrays["mac"] = (cmp.mac, "")
            plots["mode_shapes_rigid.png"] = lambda: cmp.rigid.plot()
        params = {
            "rigid_gears": args.rigid_gears,
            "compare_rigid": args.compare_rigid,
            "modes": args.modes,
            "solver": args.solver,
        }
        return AnalysisOutput("modal", params, summary, arrays, tables, plots)

    return run_analysis(args, analyse)


def _speed(text: str) -> float:
    try:
        return to_si(text, "rad/s")
    except UnitError as exc:
        raise argparse.ArgumentTypeError(f"speed {text!r}: {exc}") from None


def _frequency(text: str) -> float:
    try:
        return to_si(text, "Hz")
    except UnitError as exc:
        raise argparse.ArgumentTypeError(f"frequency {text!r}: {exc}") from None


def _points(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 2:
        raise argparse.ArgumentTypeError(f"points {text!r}: give a whole number of at least 2")
    return n


def _campbell_command(args: argparse.Namespace) -> int:
    def analyse(model: Any, source: ModelSource) -> AnalysisOutput:
        dt = _need_drivetrain(model, source)
        camp_settings, _ = settings(source, dt)
        speed = args.speed_range or (camp_settings.speed_range if camp_settings else None)
        if speed is None:
            raise MechdynError(
                f"{source.path}: no speed range; add a [campbell] table with speed_range, "
                "or pass --speed-range LOW HIGH (e.g. '0 rpm' '3000 rpm')"
            )
        ref = args.reference or (camp_settings.reference_disk if camp_settings else None)
        kw = {}
        if camp_settings:
            kw = {"shaft_orders": camp_settings.shaft_orders, "mesh_orders": camp_settings.mesh_orders}
        c = campbell(dt, speed, reference=ref, rigid_gears=args.rigid_gears, **kw)
        rpm = [s * 60 / (2 * np.pi) for s in c.speed_range]
        crossings = c.crossings
        summary = {
            "reference_disk": c.reference,
            "speed_range_rpm": rpm,
            "frequencies_hz": c.modal.frequencies_hz.tolist(),
            "rigid_body_modes": c.modal.rigid_body_modes,
            "lines": [{"label": ln.label, "kind": ln.kind, "per_rev": ln.per_rev} for ln in c.lines],
            "crossings": crossings,
        }
        tables = [
            Table(
                f"excitation lines (reference disk {c.reference})",
                ["line", "kind", "cycles per rev", f"at {rpm[1]:.0f} rpm [Hz]"],
                [[ln.label, ln.kind, ln.per_rev, float(ln.frequency_hz(c.speed_range[1]))] for ln in c.lines],
            ),
            Table(
                f"crossings with natural frequencies between {rpm[0]:.0f} and {rpm[1]:.0f} rpm",
                ["line", "mode", "frequency [Hz]", "speed [rpm]"],
                [[x["line"], x["mode"], x["frequency_hz"], x["speed_rpm"]] for x in crossings],
            ),
        ]
        params = {
            "speed_range_rad_s": list(c.speed_range),
            "reference": c.reference,
            "rigid_gears": args.rigid_gears,
        }
        arrays = {"frequencies_hz": (c.modal.frequencies_hz, "Hz")}
        return AnalysisOutput("campbell", params, summary, arrays, tables, {"campbell.png": lambda: c.plot()})

    return run_analysis(args, analyse)


def _frf_command(args: argparse.Namespace) -> int:
    def analyse(model: Any, source: ModelSource) -> AnalysisOutput:
        dt = _need_drivetrain(model, source)
        _, resp = settings(source, dt)
        if resp is None and not args.excite:
            raise MechdynError(f"{source.path}: no excitation; add a [response] table, or pass --excite DISK")
        excitation = {d: 1.0 + 0j for d in args.excite} if args.excite else resp.excitation
        lo, hi = args.frequency_range or (resp.frequency_range if resp else (1.0, 1e4))
        points = args.points or (resp.points if resp else 1000)
        damping = (
            ModalDamping(args.damping)
            if args.damping is not None
            else (resp.damping if resp else ModalDamping())
        )
        outputs = list(resp.outputs) if resp and resp.outputs else list(dt.disk_names)
        f = np.geomspace(lo, hi, points)
        r = frf(dt, f, excitation, damping=damping)
        peaks = {}
        rows = []
        for n in (*outputs, *r.element_names):
            amp, at = r.peak(n)
            unit = "rad" if n in r.disk_names else r.element_units[r.element_names.index(n)]
            peaks[n] = {"peak": amp, "unit": unit, "frequency_hz": at}
            rows.append([("disk " if unit == "rad" else "") + n, amp, unit, at])
        summary = {
            "excitation": {k: {"re": v.real, "im": v.imag} for k, v in excitation.items()},
            "frequency_range_hz": [lo, hi],
            "points": points,
            "damping": repr(damping),
            "natural_frequencies_hz": r.natural_frequencies_hz.tolist(),
            "peaks": peaks,
        }
        tables = [
            Table(
                "largest steady-state amplitudes over the frequency range",
                ["output", "peak", "unit", "at [Hz]"],
                rows,
            )
        ]
        arrays = {
            "frequencies_hz": (f, "Hz"),
            "angles": (r.angles, "rad"),
            "element_loads": (r.element_loads, "N*m | N"),
        }
        params = {
            "frequency_range_hz": [lo, hi],
            "points": points,
            "damping": repr(damping),
            "excitation": list(excitation),
        }
        return AnalysisOutput("frf", params, summary, arrays, tables, {"frf.png": lambda: r.plot(outputs)})

    return run_analysis(args, analyse)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("modal", help="natural frequencies, mode shapes and modal energy of a drivetrain")
    add_common_options(p)
    g = p.add_mutually_exclusive_group()
    g.add_argument("--rigid-gears", action="store_true", help="treat every gear mesh as a rigid constraint")
    g.add_argument(
        "--compare-rigid",
        action="store_true",
        help="also solve with rigid gears and pair the modes by shape (MAC)",
    )
    p.add_argument("--modes", type=int, help="number of lowest flexible modes (default: all)")
    p.add_argument("--solver", choices=SOLVERS, default="auto", help="eigen solver (default: auto)")
    p.set_defaults(func=_modal_command)

    p = sub.add_parser("campbell", help="Campbell (interference) diagram and its crossings")
    add_common_options(p)
    p.add_argument(
        "--speed-range",
        nargs=2,
        type=_speed,
        metavar=("LOW", "HIGH"),
        help="reference speed range, e.g. '0 rpm' '3000 rpm'",
    )
    p.add_argument("--reference", metavar="DISK", help="disk whose speed is the abscissa")
    p.add_argument("--rigid-gears", action="store_true", help="natural frequencies with rigid gears")
    p.set_defaults(func=_campbell_command)

    p = sub.add_parser("frf", help="steady-state response to harmonic torques")
    add_common_options(p)
    p.add_argument(
        "--excite", nargs="+", metavar="DISK", help="unit torque (1 N·m) at these disks, replacing [response]"
    )
    p.add_argument(
        "--frequency-range", nargs=2, type=_frequency, metavar=("LOW", "HIGH"), help="e.g. '10 Hz' '5 kHz'"
    )
    p.add_argument("--points", type=_points, help="number of frequencies (log-spaced), at least 2")
    p.add_argument("--damping", type=float, help="modal damping ratio for every mode, e.g. 0.02")
    p.set_defaults(func=_frf_command)
