"""Torques that drive or load a disk in a time simulation.

Every input has the same small interface: ``disk`` (the disk it acts on), ``torque(t, speed)`` (N·m on
that disk at time t in s and the disk's speed in rad/s, positive in the drivetrain's global sense) and
``breakpoints`` (the times, s, where the torque jumps or kinks: the integrator stops and restarts there so
that no step straddles them). Motors are those of :mod:`mechdyn.drive.motor` (Kloss's induction motor,
a tabulated torque–speed curve); :class:`MotorTorque` puts one on a disk.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from mechdyn.checks import check_array
from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = [
    "BrakeStop",
    "ConstantTorque",
    "HarmonicTorque",
    "MotorTorque",
    "RampTorque",
    "StepTorque",
    "TabulatedTorque",
    "TorqueInput",
]


class TorqueInput(Protocol):
    """What a torque input provides (see the module docstring)."""

    disk: str

    def torque(self, t: float, speed: float) -> float:
        """Torque on the disk, N·m, at time ``t`` (s) and disk speed ``speed`` (rad/s)."""

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Times where the torque jumps or kinks, s."""


def _disk(owner: str, disk: Any) -> str:
    if not isinstance(disk, str) or not disk.strip():
        raise ModelError(f"{disk!r} must name one disk", element=owner, field="disk")
    return disk.strip()


@dataclass(frozen=True)
class ConstantTorque:
    """A constant torque on a disk.

    Parameters
    ----------
    disk : str
        The disk it acts on.
    value : float or quantity
        N·m (e.g. ``"250 N*m"``), positive in the global sense of rotation.
    """

    disk: str
    value: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "disk", _disk("constant torque", self.disk))
        object.__setattr__(self, "value", si_field(self.disk, "torque", self.value, "N*m"))

    def torque(self, t: float, speed: float) -> float:
        """The torque, N·m, whatever the time (s) and speed (rad/s).

        Parameters
        ----------
        t : float
            Time, s.
        speed : float
            Disk speed, rad/s.
        """
        return self.value

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """None: the torque never changes (s)."""
        return ()


@dataclass(frozen=True)
class HarmonicTorque:
    """A harmonic torque about a mean: T(t) = mean + amplitude · cos(2π f t + phase).

    Parameters
    ----------
    disk : str
        The disk it acts on.
    amplitude : float or quantity
        N·m.
    frequency : float or quantity
        f, Hz (e.g. ``"50 Hz"``), not negative.
    phase : float or quantity
        Phase at t = 0, rad (e.g. ``"90 deg"``).
    mean : float or quantity
        Mean torque, N·m (default 0).

    Notes
    -----
    θ(t) = Re[Θ e^{iωt}] for the complex amplitude ``amplitude · e^{i phase}``: the convention of
    :func:`mechdyn.drivetrain.frf`, whose steady state a long run under this torque reaches.
    """

    disk: str
    amplitude: float
    frequency: float
    phase: float = 0.0
    mean: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "disk", _disk("harmonic torque", self.disk))
        for f, unit in (("amplitude", "N*m"), ("mean", "N*m"), ("phase", "rad")):
            object.__setattr__(self, f, si_field(self.disk, f, getattr(self, f), unit))
        object.__setattr__(
            self, "frequency", si_field(self.disk, "frequency", self.frequency, "Hz", nonnegative=True)
        )

    def torque(self, t: float, speed: float) -> float:
        """mean + amplitude · cos(2π f t + phase), N·m.

        Parameters
        ----------
        t : float
            Time, s.
        speed : float
            Disk speed, rad/s (unused).
        """
        return self.mean + self.amplitude * math.cos(2.0 * math.pi * self.frequency * t + self.phase)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """None (s): the torque is smooth."""
        return ()


@dataclass(frozen=True)
class StepTorque:
    """A torque that steps from ``before`` to ``after`` at time ``time``.

    Parameters
    ----------
    disk : str
        The disk it acts on.
    after : float or quantity
        Torque from ``time`` on, N·m.
    time : float or quantity
        The instant of the step, s.
    before : float or quantity
        Torque before the step, N·m (default 0).
    """

    disk: str
    after: float
    time: float
    before: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "disk", _disk("step torque", self.disk))
        object.__setattr__(self, "after", si_field(self.disk, "after", self.after, "N*m"))
        object.__setattr__(self, "before", si_field(self.disk, "before", self.before, "N*m"))
        object.__setattr__(self, "time", si_field(self.disk, "time", self.time, "s", nonnegative=True))

    def torque(self, t: float, speed: float) -> float:
        """``before`` for t < ``time``, ``after`` from then on, N·m.

        Parameters
        ----------
        t : float
            Time, s.
        speed : float
            Disk speed, rad/s (unused).
        """
        return self.after if t >= self.time else self.before

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The step's time, s."""
        return (self.time,)


@dataclass(frozen=True)
class RampTorque:
    """A torque rising (or falling) linearly from ``initial`` at ``start`` to ``final`` at ``end``.

    Parameters
    ----------
    disk : str
        The disk it acts on.
    final : float or quantity
        Torque from ``end`` on, N·m.
    start, end : float or quantity
        Times the ramp begins and ends, s, start < end.
    initial : float or quantity
        Torque up to ``start``, N·m (default 0).
    """

    disk: str
    final: float
    start: float
    end: float
    initial: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "disk", _disk("ramp torque", self.disk))
        for f in ("final", "initial"):
            object.__setattr__(self, f, si_field(self.disk, f, getattr(self, f), "N*m"))
        for f in ("start", "end"):
            object.__setattr__(self, f, si_field(self.disk, f, getattr(self, f), "s", nonnegative=True))
        if not self.end > self.start:
            raise ModelError(
                f"the ramp ends at {self.end:g} s, not after its start at {self.start:g} s; give end > start",
                element=self.disk,
                field="end",
            )

    def torque(self, t: float, speed: float) -> float:
        """The ramp's torque at time ``t``, N·m.

        Parameters
        ----------
        t : float
            Time, s.
        speed : float
            Disk speed, rad/s (unused).
        """
        if t <= self.start:
            return self.initial
        if t >= self.end:
            return self.final
        return self.initial + (self.final - self.initial) * (t - self.start) / (self.end - self.start)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The ramp's start and end, s."""
        return (self.start, self.end)


@dataclass(frozen=True)
class TabulatedTorque:
    """A torque given over time, interpolated linearly; before the first and after the last time the
    end values hold.

    Parameters
    ----------
    disk : str
        The disk it acts on.
    times : ndarray
        Increasing times, s, at least two.
    torques : ndarray
        Torque at each time, N·m.
    """

    disk: str
    times: np.ndarray
    torques: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "disk", _disk("tabulated torque", self.disk))
        t = check_array(self.disk, "times", self.times, "s")
        m = check_array(self.disk, "torques", self.torques, "N*m")
        if t.ndim != 1 or t.shape != m.shape or t.size < 2:
            raise ModelError(
                f"times ({t.size}) and torques ({m.size}) must be two rows of the same length, at least 2",
                element=self.disk,
                field="times",
            )
        if np.any(np.diff(t) <= 0):
            raise ModelError("the times must increase point by point", element=self.disk, field="times")
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "torques", m)

    @classmethod
    def from_table(cls, disk: str, rows: Sequence[tuple[Any, Any]]) -> TabulatedTorque:
        """A tabulated torque from rows of quantities, ``[("0 s", "0 N*m"), ("0.2 s", "1.2 kN*m")]``.

        Parameters
        ----------
        disk : str
            The disk it acts on.
        rows : sequence of (time, torque)
            Time (s or any time unit) and torque (N·m or any torque unit) per point.
        """
        t = [si_field(disk, "times", a, "s") for a, _ in rows]
        m = [si_field(disk, "torques", b, "N*m") for _, b in rows]
        return cls(disk, np.array(t), np.array(m))

    def torque(self, t: float, speed: float) -> float:
        """The interpolated torque at time ``t``, N·m.

        Parameters
        ----------
        t : float
            Time, s.
        speed : float
            Disk speed, rad/s (unused).
        """
        return float(np.interp(t, self.times, self.torques))

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The table's times, s (the torque kinks there)."""
        return tuple(float(x) for x in self.times)


@dataclass(frozen=True)
class MotorTorque:
    """A motor of :mod:`mechdyn.drive.motor` on a disk, through an optional loss-free ratio.

    The motor shaft turns at ``ratio`` × ``direction`` × the disk's speed and gives the disk
    ``ratio`` × ``direction`` × its torque at that speed: the motor's torque–speed curve read at the
    disk's speed (the rotor's inertia belongs to the drivetrain's disk; it is not added here).

    Parameters
    ----------
    disk : str
        The disk it drives.
    motor : InductionMotor or TorqueSpeedCurve
        Anything with ``torque(speed)`` (N·m at a shaft speed in rad/s).
    ratio : float
        Motor speed over disk speed, dimensionless, positive (default 1: the motor on the disk).
    direction : {1, -1}
        The motor drives the disk in the global positive sense (1) or the negative one (−1).
    """

    disk: str
    motor: Any
    ratio: float = 1.0
    direction: int = 1

    def __post_init__(self) -> None:
        object.__setattr__(self, "disk", _disk("motor", self.disk))
        if not callable(getattr(self.motor, "torque", None)):
            raise ModelError(
                f"{type(self.motor).__name__} has no torque(speed); give an InductionMotor or a "
                "TorqueSpeedCurve of mechdyn.drive",
                element=self.disk,
                field="motor",
            )
        object.__setattr__(self, "ratio", si_field(self.disk, "ratio", self.ratio, "", positive=True))
        if self.direction not in (1, -1):
            raise ModelError(f"{self.direction!r} must be 1 or -1", element=self.disk, field="direction")

    def torque(self, t: float, speed: float) -> float:
        """The motor's torque on the disk at the disk's speed, N·m.

        Parameters
        ----------
        t : float
            Time, s (unused).
        speed : float
            Disk speed, rad/s.
        """
        scale = self.ratio * self.direction
        return scale * float(self.motor.torque(float(scale * speed)))

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """None (s): the motor's torque follows the speed smoothly."""
        return ()


@dataclass(frozen=True)
class BrakeStop:
    """An emergency stop: ``drive`` acts until ``time``; from then on its torque is removed and a brake
    torque ``brake`` opposes the disk's rotation.

    The brake is dry friction, smoothed below ``hold_speed``: the torque is −brake · tanh(ω / ω_hold),
    so that the stopped train is held, not chattering, and the torque has no kink for the integrator
    to stumble on (the usual smoothing of Coulomb friction, e.g. Andersson, Söderberg & Björklund,
    "Friction models for sliding dry, boundary and mixed lubricated contacts", Tribology
    International 40 (2007) 580–587).

    Parameters
    ----------
    drive : TorqueInput
        The input that is switched off (its disk is the brake's).
    time : float or quantity
        The instant of the stop, s.
    brake : float or quantity
        Brake torque, N·m, not negative (0: the drive is only switched off).
    hold_speed : float or quantity
        ω_hold, rad/s, positive: the speed below which the brake torque falls smoothly to zero.
    """

    drive: Any
    time: float
    brake: float = 0.0
    hold_speed: float = 0.01

    def __post_init__(self) -> None:
        disk = getattr(self.drive, "disk", None)
        if not callable(getattr(self.drive, "torque", None)) or not isinstance(disk, str):
            raise ModelError(
                f"{self.drive!r} is not a torque input; give e.g. a MotorTorque",
                element="emergency stop",
                field="drive",
            )
        object.__setattr__(self, "time", si_field(disk, "time", self.time, "s", nonnegative=True))
        object.__setattr__(self, "brake", si_field(disk, "brake", self.brake, "N*m", nonnegative=True))
        object.__setattr__(
            self, "hold_speed", si_field(disk, "hold_speed", self.hold_speed, "rad/s", positive=True)
        )

    @property
    def disk(self) -> str:
        """The disk of the drive and the brake."""
        return str(self.drive.disk)

    def torque(self, t: float, speed: float) -> float:
        """The drive's torque before ``time``, the brake's after, N·m.

        Parameters
        ----------
        t : float
            Time, s.
        speed : float
            Disk speed, rad/s.
        """
        if t < self.time:
            return float(self.drive.torque(t, speed))
        return -self.brake * math.tanh(speed / self.hold_speed)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The drive's breakpoints before the stop, and the stop, s."""
        return (*(b for b in self.drive.breakpoints if b < self.time), self.time)
