"""Everything ``mechdyn support`` reports, as one result: steady state, start-up, modes.

:func:`support_analysis` runs the exact periodic steady state, the start-up from rest, the modes and
the stiffness/damping influence study on one machine and load, and checks the start-up against the
steady state; :class:`SupportAnalysis` holds them with the result protocol.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Result, Table
from mechdyn.support.assessment import VibrationVerdicts, vibration_verdicts
from mechdyn.support.excitation import PeriodicLoad
from mechdyn.support.model import MountedMachine
from mechdyn.support.modes import SupportModes, elastic_centre, modes
from mechdyn.support.response import SupportResponse, periodic_response, startup_response
from mechdyn.support.sweep import UnbalanceSweep, unbalance_sweep
from mechdyn.support.verdicts import SEPARATION_MARGIN

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["SupportAnalysis", "support_analysis"]


@dataclass(frozen=True, repr=False)  # the short repr of Result
class SupportAnalysis(Result):
    """A machine on its supports under a periodic load: every view of it.

    Attributes
    ----------
    steady : SupportResponse
        Exact periodic steady state (frequency domain), one period.
    startup : SupportResponse
        From rest, ``cycles`` periods by time integration.
    modes : SupportModes
    method : str
        The start-up integrator.
    mounts : dict
        The mounts estimated from their drawings (:func:`mounts_from_drawing`).
    excitation : dict
        The summary of the mechanism whose shaking is the load, when it is one (its stroke, its
        inertia-force extremes...), so that a study can hold the mechanism to them.
    unbalance : UnbalanceSweep or None
        When the load is unbalanced rotors: the floor force and the isolation over their speed range.
    machine_group : int or None
        ISO 20816-3 machine group of the vibration verdict (1 or 2; None: 2, said to be the default).
    foundation : str
        ISO 20816-3 foundation class: ``auto`` (from the modes), ``rigid`` or ``flexible``.
    points : tuple of (x, y, z) or None
        Points of the frame whose vibration is judged, m (None: the mounts' tops).
    separation_margin : float
        A mode closer than this ratio to an exciting harmonic is flagged.
    """

    steady: SupportResponse
    startup: SupportResponse
    modes: SupportModes
    method: str
    mounts: dict[str, dict[str, Any]] = field(default_factory=dict)
    excitation: dict[str, Any] = field(default_factory=dict)
    unbalance: UnbalanceSweep | None = None
    machine_group: int | None = None
    foundation: str = "auto"
    points: tuple[tuple[float, ...], ...] | None = None
    separation_margin: float = SEPARATION_MARGIN

    @cached_property
    def verdicts(self) -> VibrationVerdicts:
        """The frame's vibration (ISO 20816-3), the mounts' isolation (VDI 2062), the floor, and the modes
        against the running speed's harmonics (:func:`mechdyn.support.assessment.vibration_verdicts`)."""
        return vibration_verdicts(
            self.machine,
            self.load,
            machine_group=self.machine_group,
            foundation=self.foundation,
            points=self.points,
            margin=self.separation_margin,
        )

    @property
    def machine(self) -> MountedMachine:
        return self.steady.machine

    @property
    def load(self) -> PeriodicLoad:
        return self.steady.load

    @cached_property
    def startup_deviation(self) -> float:
        """Largest distance of the last start-up period from the steady state, over its range."""
        s = self.startup
        last = s.time >= s.time[-1] - self.load.period
        z_ss = periodic_response(self.machine, self.load, time=s.time[last]).vertical_displacement
        span = float(np.ptp(self.steady.vertical_displacement)) or 1.0
        return float(np.abs(s.vertical_displacement[last] - z_ss).max() / span)

    def summary(self) -> dict[str, Any]:
        """The steady state's figures, the modes, the start-up and its deviation, and the verdicts
        (:attr:`verdicts`)."""
        machine, md, startup = self.machine, self.modes, self.startup
        out = self.steady.summary() | {
            "dofs": list(machine.dofs),
            "machine_mass_kg": machine.body.mass,
            "period_s": self.load.period,
            "natural_frequencies_hz": [float(f) for f in md.frequencies_hz],
            "mode_dominant_coordinate": md.dominant,
            "mode_decoupling": [float(v) for v in md.decoupling],
            "static_deflection_m": {
                m.name: float(v) for m, v in zip(machine.mounts, machine.static_deflection, strict=True)
            },
            "startup_cycles": round(startup.time[-1] / self.load.period),
            "startup_method": self.method,
            "startup_displacement_max_m": float(startup.vertical_displacement.max()),
            "startup_displacement_min_m": float(startup.vertical_displacement.min()),
            "startup_last_cycle_deviation_relative": self.startup_deviation,
            "force_balance_residual_N": float(np.abs(self.steady.force_balance_residual).max()),
        }
        if self.mounts:
            out["mounts_from_drawing"] = self.mounts
        if self.excitation:
            out["excitation"] = self.excitation
        ec = elastic_centre(machine)
        if ec is not None:
            out["elastic_centre_m"] = [float(v) for v in ec[0]]
            out["elastic_centre_residual"] = ec[1]
        if self.unbalance is not None:
            out |= self.unbalance.summary()
        return out | self.verdicts.summary()

    def to_frame(self) -> pd.DataFrame:
        """The steady state over one period (see :meth:`SupportResponse.to_frame`)."""
        return self.steady.to_frame()

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        out = super().arrays() | {
            "startup_time_s": (self.startup.time, "s"),
            "startup_z_m": (self.startup.vertical_displacement, "m"),
        }
        if self.unbalance is not None:
            out |= {f"sweep_{k}": v for k, v in self.unbalance.arrays().items()}
        return out

    def tables(self, **display_units: str) -> list[Table]:
        """Steady state, modes, (several mounts) the mounts, the verdicts (the frame's vibration by ISO
        20816-3, the isolation by harmonic by VDI 2062 with the floor's verdict, the modes against the
        running speed's harmonics: each verdict a sentence under its table), (rotors) the unbalance
        over speed, and the machine and its mounts as assembled.

        Forces and displacements are shown in the units a designer reads them in
        (:func:`mechdyn.units.readable`: kN or MN, mm or µm), or in ``force_unit`` (e.g.
        ``"tonf"``) and ``length_unit`` where given.
        """
        from mechdyn.units import convert, readable, readable_unit

        fu = display_units.get("force_unit")
        lu = display_units.get("length_unit") or "mm"
        s = self.summary()
        machine = self.machine

        def row(label: str, key: str, unit: str) -> list[Any]:
            chosen = fu if unit == "N" else display_units.get("length_unit")
            if chosen:
                return [label, convert(s[key], unit, chosen), chosen]
            return [label, *readable(s[key], unit)]

        steady = Table(
            "steady state (frequency domain)",
            ["quantity", "value", "unit"],
            [
                row("exciting (inertia) force max", "inertia_force_max_N", "N"),
                row("exciting (inertia) force min", "inertia_force_min_N", "N"),
                row("exciting force range", "inertia_force_range_N", "N"),
                row("transmitted force max", "transmitted_force_max_N", "N"),
                row("transmitted force min", "transmitted_force_min_N", "N"),
                row("transmitted force range", "transmitted_force_range_N", "N"),
                row("bed displacement max", "displacement_max_m", "m"),
                row("bed displacement min", "displacement_min_m", "m"),
                [
                    "start-up: last cycle off the steady state",
                    s["startup_last_cycle_deviation_relative"],
                    "of the range",
                ],
            ],
        )
        modes_table = Table(
            "modes",
            ["mode", "f [Hz]", "dominant", *[f"{d} [%]" for d in machine.dofs]],
            [
                [r["mode"], r["frequency_hz"], r["dominant"], *[r[f"{d}_percent"] for d in machine.dofs]]
                for r in self.modes.table()
            ],
        )
        tables = [steady, modes_table]
        if len(machine.mounts) > 1:
            static = [float(-f[2]) for f in machine.static_mount_forces]
            peaks = [s["mount_force_peak_N"][m.name] for m in machine.mounts]
            force, shown = (
                (fu, fu) if fu else readable_unit(max(map(abs, [*static, *peaks]), default=0.0), "N")
            )
            tables.append(
                Table(
                    "mounts",
                    [
                        "mount",
                        f"static force [{shown}]",
                        f"static deflection [{lu}]",
                        f"dynamic force peak [{shown}]",
                    ],
                    [
                        [m.name, convert(f, "N", force), convert(float(dz), "m", lu), convert(p, "N", force)]
                        for m, f, dz, p in zip(
                            machine.mounts, static, machine.static_deflection, peaks, strict=True
                        )
                    ],
                )
            )
        tables += self.verdicts.tables(**display_units)
        if self.unbalance is not None:
            tables += self.unbalance.tables(**display_units)
        from mechdyn.support.summary import model_tables

        return [*tables, *model_tables(machine, self.mounts)]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """Bed displacement (start-up and steady state), forces, F_T against F, modes; with several
        mounts also the mount forces and the mode shapes; with rotors the forces over their speeds."""
        from mechdyn.support import plots as sp

        out = {
            "displacement.png": lambda: sp.plot_displacement(self.startup, self.steady),
            "forces.png": lambda: sp.plot_forces(self.steady, force_unit=display_units.get("force_unit")),
            "transmitted_vs_exciting.png": lambda: sp.plot_transmitted_vs_exciting(self.steady),
        }
        if len(self.modes.omega) > 1:  # one degree of freedom: a single full bar would say nothing
            out["modes.png"] = lambda: sp.plot_modes(self.modes)
        if len(self.machine.mounts) > 1:
            out["mount_forces.png"] = lambda: sp.plot_mount_forces(self.steady)
            out["mode_shapes.png"] = lambda: sp.plot_mode_shapes(self.modes)
        if self.unbalance is not None:
            out |= self.unbalance.plots(**display_units)
        return out


def support_analysis(
    machine: MountedMachine,
    load: PeriodicLoad,
    *,
    cycles: int = 5,
    method: str = "exact",
    mounts: dict[str, dict[str, Any]] | None = None,
    excitation: dict[str, Any] | None = None,
    speeds: Any = None,
    machine_group: int | None = None,
    foundation: str = "auto",
    points: Any = None,
    separation_margin: float = SEPARATION_MARGIN,
) -> SupportAnalysis:
    """Steady state, start-up from rest, modes and, for unbalanced rotors, the sweep over their speeds.

    Parameters
    ----------
    machine : MountedMachine
    load : PeriodicLoad
    cycles : int
        Start-up periods to integrate.
    method : str
        Start-up integrator (:func:`mechdyn.support.startup_response`).
    mounts : dict, optional
        What the mounts estimated from their drawings are (:func:`mounts_from_drawing`), reported.
    excitation : dict, optional
        The summary of the mechanism that makes the load, reported.
    speeds : array_like or quantity, optional
        For a load of unbalanced rotors (:meth:`PeriodicLoad.from_unbalance`): the first rotor's speeds
        to sweep, rad/s (:func:`mechdyn.support.unbalance_sweep`; by default 0 to 1.2 times its running
        speed). Ignored for other loads.
    machine_group : {1, 2}, optional
        ISO 20816-3 machine group of the vibration verdict (Table A.1: 1, 300 kW to 50 MW; Table A.2:
        2, 15 kW to 300 kW); by default 2, the stricter, and the verdict says so.
    foundation : {"auto", "rigid", "flexible"}
        ISO 20816-3 foundation class; ``auto``: from the modes (§ 5.4).
    points : sequence of (x, y, z), optional
        Points of the frame whose vibration velocity is judged, m (default: the mounts' tops).
    separation_margin : float
        Flag a mode closer than this ratio to an exciting harmonic (default 0.2: ±20 %).

    Returns
    -------
    SupportAnalysis
    """
    sweep = unbalance_sweep(machine, load, speeds) if load.rotors else None  # first: it checks the rotors
    pts = None if points is None else tuple(tuple(float(x) for x in p) for p in points)
    # the verdicts' settings are checked now, not when the result is first read
    verdicts = vibration_verdicts(
        machine,
        load,
        machine_group=machine_group,
        foundation=foundation,
        points=pts,
        margin=separation_margin,
    )
    steady = periodic_response(machine, load)
    startup = startup_response(machine, load, cycles, method=method)
    out = SupportAnalysis(
        steady,
        startup,
        modes(machine),
        startup.method,
        dict(mounts or {}),
        dict(excitation or {}),
        sweep,
        None if machine_group is None else int(machine_group),
        foundation,
        pts,
        float(separation_margin),
    )
    out.__dict__["verdicts"] = verdicts  # the cached property, computed once
    return out


def mounts_from_drawing(
    machine: MountedMachine, estimates: Mapping[str, Any], applied: Mapping[str, Any] | None = None
) -> dict[str, dict[str, Any]]:
    """For each mount estimated from its drawing: its type, file, stiffness, loss factor, calibration.

    Parameters
    ----------
    machine : MountedMachine
        The machine as analysed (calibrated where asked).
    estimates : mapping of mount name → PlacedEstimate
    applied : mapping of mount name → dict, optional
        The stored calibrations applied (:meth:`SupportSpec.calibrated`).
    """
    out = {}
    for m in machine.mounts:
        e = estimates.get(m.name)
        if e is None:
            continue
        out[m.name] = {
            "estimate": type(e.estimate).__name__,
            "source": e.source,
            "stiffness_N_per_m": [float(v) for v in m.stiffness],
            "damping_N_s_per_m": [float(v) for v in m.damping],
            "loss_factor": float(e.estimate.loss_factor),
            "calibration": (applied or {}).get(m.name, "as drawn"),
        }
    return out
