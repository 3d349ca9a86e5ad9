"""``mechdyn support``: the machine on its supports — modes, steady state, start-up, influence study."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.cli.common import AnalysisOutput, Table, add_common_options, column_unit, run_analysis
from mechdyn.errors import ModelFileError
from mechdyn.io.modelfile import ModelSource
from mechdyn.support.modes import elastic_centre, modes
from mechdyn.support.plots import (
    plot_displacement,
    plot_forces,
    plot_mode_shapes,
    plot_modes,
    plot_mount_forces,
    plot_transmitted_vs_exciting,
)
from mechdyn.support.response import influence, periodic_response, startup_response
from mechdyn.support.schema import SupportSpec

__all__ = ["register"]

TONF = 9806.65  # N per metric tonne-force, for the tables


def _support_command(args: argparse.Namespace) -> int:
    def analyse(spec: Any, source: ModelSource) -> AnalysisOutput:
        if not isinstance(spec, SupportSpec):
            raise ModelFileError(
                source.path,
                "[model] → type",
                f'{source.model_type!r} is not a support model; this command needs type = "support"',
            )
        machine, load, settings = spec.machine, spec.load, spec.settings
        cycles = args.cycles or settings.start_up_cycles
        steady = periodic_response(machine, load)
        startup = startup_response(machine, load, cycles, method=settings.start_up_method)
        md = modes(machine)
        rows = influence(machine, load, settings.stiffness_factors, settings.damping_factors)
        summary = steady.summary()
        # start-up: how far the last integrated period is from the steady state
        last = startup.time >= startup.time[-1] - load.period
        z_ss = periodic_response(machine, load, time=startup.time[last]).vertical_displacement
        span = float(np.ptp(steady.vertical_displacement)) or 1.0
        summary |= {
            "dofs": list(machine.dofs),
            "machine_mass_kg": machine.body.mass,
            "period_s": load.period,
            "natural_frequencies_hz": [float(f) for f in md.natural_frequencies],
            "mode_dominant_coordinate": md.dominant,
            "mode_decoupling": [float(v) for v in md.decoupling],
            "static_deflection_m": {
                m.name: float(v) for m, v in zip(machine.mounts, machine.static_deflection, strict=True)
            },
            "startup_cycles": cycles,
            "startup_method": settings.start_up_method,
            "startup_displacement_max_m": float(startup.vertical_displacement.max()),
            "startup_displacement_min_m": float(startup.vertical_displacement.min()),
            "startup_last_cycle_deviation_relative": float(
                np.abs(startup.vertical_displacement[last] - z_ss).max() / span
            ),
            "force_balance_residual_N": float(np.abs(steady.force_balance_residual).max()),
            "influence": rows,
        }
        ec = elastic_centre(machine)
        if ec is not None:
            summary["elastic_centre_m"] = [float(v) for v in ec[0]]
            summary["elastic_centre_residual"] = ec[1]
        if args.csv:
            path = Path(args.csv)
            path.parent.mkdir(parents=True, exist_ok=True)
            steady.to_frame().to_csv(path, index=False, float_format="%.10g")
        tables = [
            Table(
                "steady state (frequency domain)",
                ["quantity", "value", "unit", "tonf / mm"],
                [
                    [
                        "exciting (inertia) force max",
                        summary["inertia_force_max_N"],
                        "N",
                        summary["inertia_force_max_N"] / TONF,
                    ],
                    [
                        "exciting (inertia) force min",
                        summary["inertia_force_min_N"],
                        "N",
                        summary["inertia_force_min_N"] / TONF,
                    ],
                    [
                        "exciting force range",
                        summary["inertia_force_range_N"],
                        "N",
                        summary["inertia_force_range_N"] / TONF,
                    ],
                    [
                        "transmitted force max",
                        summary["transmitted_force_max_N"],
                        "N",
                        summary["transmitted_force_max_N"] / TONF,
                    ],
                    [
                        "transmitted force min",
                        summary["transmitted_force_min_N"],
                        "N",
                        summary["transmitted_force_min_N"] / TONF,
                    ],
                    [
                        "transmitted force range",
                        summary["transmitted_force_range_N"],
                        "N",
                        summary["transmitted_force_range_N"] / TONF,
                    ],
                    [
                        "bed displacement max",
                        summary["displacement_max_m"],
                        "m",
                        1e3 * summary["displacement_max_m"],
                    ],
                    [
                        "bed displacement min",
                        summary["displacement_min_m"],
                        "m",
                        1e3 * summary["displacement_min_m"],
                    ],
                    [
                        "start-up: last cycle off the steady state",
                        summary["startup_last_cycle_deviation_relative"],
                        "of the range",
                        None,
                    ],
                ],
            ),
            Table(
                "modes",
                ["mode", "f [Hz]", "dominant", *[f"{d} [%]" for d in machine.dofs]],
                [
                    [r["mode"], r["frequency_hz"], r["dominant"], *[r[f"{d}_percent"] for d in machine.dofs]]
                    for r in md.table()
                ],
            ),
            Table(
                "influence of the support (steady state)",
                [
                    "varied",
                    "factor",
                    "F_T range [tonf]",
                    "F_T max [tonf]",
                    "F_T min [tonf]",
                    "z max [mm]",
                    "z min [mm]",
                    "f1 [Hz]",
                ],
                [
                    [
                        r["parameter"],
                        r["factor"],
                        r["transmitted_force_range_N"] / TONF,
                        r["transmitted_force_max_N"] / TONF,
                        r["transmitted_force_min_N"] / TONF,
                        1e3 * r["displacement_max_m"],
                        1e3 * r["displacement_min_m"],
                        r["first_natural_frequency_hz"],
                    ]
                    for r in rows
                ],
            ),
        ]
        if len(machine.mounts) > 1:
            tables.append(
                Table(
                    "mounts",
                    ["mount", "static force [N]", "static deflection [mm]", "dynamic force peak [N]"],
                    [
                        [m.name, float(-f[2]), 1e3 * float(dz), summary["mount_force_peak_N"][m.name]]
                        for m, f, dz in zip(
                            machine.mounts,
                            machine.static_mount_forces,
                            machine.static_deflection,
                            strict=True,
                        )
                    ],
                )
            )
        frame = steady.to_frame()
        arrays = {name: (frame[name].to_numpy(), column_unit(name)) for name in frame.columns}
        arrays["startup_time_s"] = (startup.time, "s")
        arrays["startup_z_m"] = (startup.vertical_displacement, "m")
        plots = {
            "displacement.png": lambda: plot_displacement(startup, steady),
            "forces.png": lambda: plot_forces(steady),
            "transmitted_vs_exciting.png": lambda: plot_transmitted_vs_exciting(steady),
            "modes.png": lambda: plot_modes(md),
        }
        if len(machine.mounts) > 1:
            plots["mount_forces.png"] = lambda: plot_mount_forces(steady)
            plots["mode_shapes.png"] = lambda: plot_mode_shapes(md)
        params = {"cycles": cycles, "csv": args.csv, "mechanism": spec.mechanism_path}
        return AnalysisOutput("support", params, summary, arrays, tables, plots)

    return run_analysis(args, analyse)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "support", help="a machine on its supports: modes, steady state, start-up, floor forces"
    )
    add_common_options(p)
    p.add_argument(
        "--csv", metavar="FILE", help="write the steady-state table (columns named with their units)"
    )
    p.add_argument("--cycles", type=int, help="start-up periods to integrate (default: the file's, else 5)")
    p.set_defaults(func=_support_command)
