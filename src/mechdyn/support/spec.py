"""What a support model file describes, read and not yet computed: the machine on its support or
mounts (:class:`SupportSpec`), what shakes it (a mechanism, a drive, periodic loads or rotors), and
each mount as estimated from its drawing (:class:`PlacedEstimate`). The file's tables and their
reading are :mod:`mechdyn.support.schema`."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np

from mechdyn.errors import ModelFileError
from mechdyn.support.analysis_table import AnalysisTable
from mechdyn.support.excitation import PeriodicLoad, Placement
from mechdyn.support.model import MountedMachine

__all__ = ["DriveExcitation", "MechanismExcitation", "PlacedEstimate", "SupportSpec"]


@dataclass(frozen=True)
class MechanismExcitation:
    """A mechanism that shakes the machine, read from its own model file; nothing computed yet.

    Attributes
    ----------
    mechanism : mechdyn.mechanism.Mechanism
    angles : int
        Crank positions over one revolution for its inverse dynamics.
    placement : Placement
        Where the mechanism's plane sits in the machine.
    path : str
        The mechanism model file.
    """

    mechanism: Any
    angles: int
    placement: Placement
    path: str

    def dynamics(self) -> Any:
        """The mechanism's inverse dynamics over one revolution (a ``DynamicsResult``)."""
        from mechdyn.mechanism.dynamics import inverse_dynamics

        return inverse_dynamics(self.mechanism, self.angles)


@dataclass(frozen=True)
class DriveExcitation:
    """A mechanism driven by its motor that shakes the machine, read from a drive model file; nothing
    computed yet.

    The load is the shaking force and moment at the drive's periodic steady state (the real,
    fluctuating crank speed θ̇(θ) with the motor, flywheel and forming force), sampled uniformly in
    time over the drive's period (:meth:`PeriodicLoad.from_drive`). The support's start-up starts
    the machine from rest under that periodic load, as for a mechanism at constant speed: the
    mechanism is taken to be in its steady state already (the drive's own run-up from rest is
    ``mechdyn drive``'s start-up, and is not what loads the mounts here).

    Attributes
    ----------
    drive : mechdyn.drive.Drive
        Motor, gearing, flywheel and the mechanism with its forming force.
    angles : int
        Crank positions over one revolution of the drive's steady state.
    placement : Placement
        Where the mechanism's plane sits in the machine.
    path : str
        The drive model file.
    support_path : str
        The support model file that names it (for errors).
    """

    drive: Any
    angles: int
    placement: Placement
    path: str
    support_path: str = ""

    @property
    def mechanism(self) -> Any:
        """The driven mechanism, with its forming force (a ``Mechanism``)."""
        return self.drive.mechanism

    @cached_property
    def result(self) -> Any:
        """The drive's steady state and its loads at the real speed (a ``DriveResult``, no start-up).

        Raises
        ------
        mechdyn.errors.ModelFileError
            When the motor cannot keep the mechanism turning (a :class:`mechdyn.drive.StallError`, its
            cause), naming the support file and the drive file.
        """
        from mechdyn.drive.forward import StallError
        from mechdyn.drive.result import drive_analysis

        try:
            return drive_analysis(self.drive, self.angles, startup=False)
        except StallError as exc:
            raise ModelFileError(
                self.support_path or self.path,
                "[excitation] → mechanism",
                f"the drive of {self.path} stalls, so it has no periodic steady state to load the machine "
                f"with: {exc}",
                self.path,
            ) from exc

    def dynamics(self) -> Any:
        """The mechanism's inverse dynamics at the drive's real speed over one revolution (a
        ``DynamicsResult``, rows in the crank angle from the datum, times not equally spaced)."""
        return self.result.loads

    def load(self) -> PeriodicLoad:
        """The load on the machine, uniform in time over the drive's period."""
        return PeriodicLoad.from_drive(self.result, self.placement)

    def summary(self) -> dict[str, Any]:
        """The mechanism's figures at the real speed, with the drive's speed, fluctuation and duty."""
        d = self.result.summary()
        keep = (
            "crank_speed_mean_rad_s",
            "crank_speed_max_rad_s",
            "crank_speed_min_rad_s",
            "speed_fluctuation_ratio",
            "period_s",
            "strokes_per_minute_rpm",
            "motor_torque_rms_Nm",
            "motor_torque_rms_to_rated_ratio",
            "process_energy_per_stroke_J",
            "flywheel_inertia_kg_m2",
            "shaking_force_max_constant_speed_N",
        )
        return self.dynamics().summary() | {k: d[k] for k in keep if k in d}


@dataclass(frozen=True)
class PlacedEstimate:
    """A mount estimated from its drawing, standing under the machine.

    Attributes
    ----------
    estimate : MountEstimate
        The pad, bolted joint, wedge, foot or isolator (:mod:`mechdyn.mounts`).
    lateral_stiffness : float or None
        Across the axis, N/m, when the row gives it (else the estimate's own).
    calibrate : bool
        Apply the stored calibration of the estimate when the analysis has a results database.
    damping_from_loss_factor : bool
        The row gives no damping: it follows from the estimate's loss factor.
    source : str
        The mount file, or the support file's row for an inline estimate.
    """

    estimate: Any
    lateral_stiffness: float | None
    calibrate: bool
    damping_from_loss_factor: bool
    source: str

    def axes(self, estimate: Any = None) -> np.ndarray:
        """(shear, shear, compression) stiffness along the mount's local axes, N/m."""
        e = self.estimate if estimate is None else estimate
        lat = self.lateral_stiffness if self.lateral_stiffness is not None else e.lateral_stiffness
        return np.array([lat, lat, e.stiffness], dtype=float)


@dataclass(frozen=True)
class SupportSpec:
    """A machine on its supports as read from a file, with its load and analysis settings.

    Loading the file computes nothing: when the load comes from a mechanism, its inverse dynamics
    runs the first time :attr:`load` or :attr:`dynamics` is asked for.
    """

    name: str
    machine: MountedMachine
    excitation: PeriodicLoad | MechanismExcitation | DriveExcitation
    settings: AnalysisTable
    estimates: dict[str, PlacedEstimate] = field(default_factory=dict)
    speed_range: tuple[float, float] | None = None
    """The first rotor's speeds to sweep, rad/s, when the load is unbalanced rotors and the file gives
    them (else the sweep's default, 0 to 1.2 times the running speed)."""
    foundation: Any = None
    """The foundation block on soil under the mounts (a :class:`mechdyn.support.foundation.Foundation`),
    or None: the mounts stand on rigid ground."""
    floor_points: Any = None
    """The block's points whose vibration is judged, m (None: the mounts' feet)."""

    def sweep_speeds(self) -> np.ndarray | None:
        """The speeds of the unbalance sweep, rad/s: :data:`~mechdyn.support.sweep.DEFAULT_SPEED_STEPS`
        over :attr:`speed_range`, or None for the sweep's default."""
        if self.speed_range is None:
            return None
        from mechdyn.support.sweep import DEFAULT_SPEED_STEPS

        return np.linspace(*self.speed_range, DEFAULT_SPEED_STEPS)

    def calibrated(self, store: Any) -> tuple[MountedMachine, dict[str, Any]]:
        """The machine with the stored calibrations applied to the mounts that ask for them.

        Parameters
        ----------
        store : ResultStore
            Where ``mechdyn mount`` kept the calibrations (by the mount file's name).

        Returns
        -------
        machine : MountedMachine
        applied : dict
            For each calibrated mount: the calibration, its provenance, the stiffness before and after.

        Notes
        -----
        A damping that came from the loss factor scales with the stiffness (c = η k / ω, ω kept).
        """
        wanted = {n: e for n, e in self.estimates.items() if e.calibrate}
        if not wanted:
            return self.machine, {}
        from mechdyn.mounts.calibration import apply, load_calibration

        mounts, applied = [], {}
        for m in self.machine.mounts:
            e = wanted.get(m.name)
            if e is None:
                mounts.append(m)
                continue
            cal = load_calibration(store, e.estimate.name)
            new = apply(cal, e.estimate)
            k = e.axes(new)
            ratio = np.divide(k, m.stiffness, out=np.ones(3), where=m.stiffness > 0)
            c = m.damping * ratio if e.damping_from_loss_factor else m.damping
            mounts.append(replace(m, stiffness=k, damping=c))
            applied[m.name] = cal.as_dict() | {
                "provenance": cal.provenance,
                "stiffness_before_N_per_m": [float(v) for v in m.stiffness],
                "stiffness_after_N_per_m": [float(v) for v in k],
            }
        return replace(self.machine, mounts=tuple(mounts)), applied

    @property
    def mechanism_path(self) -> str | None:
        """The mechanism (or drive) model file the load comes from (None for samples or harmonics)."""
        e = self.excitation
        return e.path if isinstance(e, MechanismExcitation | DriveExcitation) else None

    @cached_property
    def dynamics(self) -> Any:
        """The mechanism's ``DynamicsResult`` when the load comes from one (at the drive's real speed
        for a drive), else None."""
        e = self.excitation
        return e.dynamics() if isinstance(e, MechanismExcitation | DriveExcitation) else None

    @cached_property
    def load(self) -> PeriodicLoad:
        """The periodic load on the machine."""
        e = self.excitation
        if isinstance(e, MechanismExcitation):
            return PeriodicLoad.from_mechanism(self.dynamics, e.placement)
        if isinstance(e, DriveExcitation):
            return e.load()
        return e

    def excitation_summary(self) -> dict[str, Any] | None:
        """The summary of the mechanism (or drive) that makes the load, else None."""
        e = self.excitation
        if isinstance(e, DriveExcitation):
            return e.summary()
        return self.dynamics.summary() if self.dynamics is not None else None
