"""Plots of a driven mechanism: crank speed, motor duty, torque into the crank, shaking force, start-up."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from mechdyn.plotting import legend, new_axes
from mechdyn.units import convert

if TYPE_CHECKING:
    from mechdyn.drive.forward import StartUp, SteadyState
    from mechdyn.drive.inertia import ReducedMechanism

__all__ = ["plot_motor", "plot_shaking", "plot_speed", "plot_startup", "plot_torque"]


class DriveCurves(Protocol):
    """What the figures read of a drive analysis (:class:`.result.DriveResult`): the result is passed
    as it is.

    Attributes
    ----------
    drive : Drive
        Motor, gearing, flywheel and mechanism (its name, the motor's rated torque).
    reduced : ReducedMechanism
        The mechanism reduced to its crank (the constant-speed torque).
    steady : SteadyState
        One revolution of the steady state: angles turned (rad), speeds (rad/s), crank torque (N·m).
    startup : StartUp or None
        The run-up from rest: times (s), speeds (rad/s).
    motor_torque, mechanism_torque : ndarray
        (N,) motor shaft torque and torque into the crank, N·m.
    motor_power : ndarray
        (N,) motor shaft power, W.
    _columns : dict of str → ndarray
        The per-sample columns, SI units by their names (the shaking forces, N).
    """

    @property
    def drive(self) -> Any: ...
    @property
    def reduced(self) -> ReducedMechanism: ...
    @property
    def steady(self) -> SteadyState: ...
    @property
    def startup(self) -> StartUp | None: ...
    @property
    def motor_torque(self) -> np.ndarray: ...
    @property
    def motor_power(self) -> np.ndarray: ...
    @property
    def mechanism_torque(self) -> np.ndarray: ...
    @property
    def _columns(self) -> dict[str, np.ndarray]: ...


def _turned_deg(r: DriveCurves) -> np.ndarray:
    return np.degrees(r.steady.turned)


def plot_speed(r: DriveCurves, ax: Any = None) -> Any:
    """Crank speed over one revolution of the steady state, rpm, with its mean.

    Parameters
    ----------
    r : DriveResult
        The drive analysis (or anything with what :class:`DriveCurves` names).
    ax : matplotlib Axes, optional
        Where to draw.
    """
    ax = new_axes(ax)
    w = convert(r.steady.speed, "rad/s", "rpm")
    ax.plot(_turned_deg(r), w, lw=1.2, label="crank speed")
    ax.axhline(float(convert(r.steady.mean_speed, "rad/s", "rpm")), color="k", ls="--", lw=0.8, label="mean")
    ax.set_xlabel("crank angle turned from the datum (deg)")
    ax.set_ylabel("crank speed (rpm)")
    ax.set_title(f"{r.drive.name}: speed fluctuation δ = {r.steady.fluctuation:.4f}")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_motor(r: DriveCurves, ax: Any = None) -> Any:
    """Motor torque (N·m) and power (kW) over one revolution, with the rated torque where known.

    Parameters
    ----------
    r : DriveResult
        The drive analysis (or anything with what :class:`DriveCurves` names).
    ax : matplotlib Axes, optional
        Where to draw.
    """
    ax = new_axes(ax)
    x = _turned_deg(r)
    ax.plot(x, r.motor_torque, lw=1.2, label="motor torque")
    rated = getattr(r.drive.motor, "rated_torque", None)
    if rated:
        ax.axhline(rated, color="k", ls="--", lw=0.8, label="rated torque")
    ax.set_xlabel("crank angle turned from the datum (deg)")
    ax.set_ylabel("motor torque (N·m)")
    twin = ax.twinx()
    twin.plot(x, convert(r.motor_power, "W", "kW"), lw=1, color="tab:red", label="motor power")
    twin.set_ylabel("motor power (kW)")
    ax.set_title(f"{r.drive.name}: motor duty")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize="small")
    twin.legend(loc="upper right", fontsize="small")
    return ax


def plot_torque(r: DriveCurves, ax: Any = None) -> Any:
    """Torque into the crank at the real speed against the constant-speed driving torque, kN·m.

    Parameters
    ----------
    r : DriveResult
        The drive analysis (or anything with what :class:`DriveCurves` names).
    ax : matplotlib Axes, optional
        Where to draw.
    """
    ax = new_axes(ax)
    x = _turned_deg(r)
    k = float(convert(1.0, "N*m", "kN*m"))
    ax.plot(x, r.mechanism_torque * k, lw=1.2, label="into the crank, real speed")
    Tc = r.reduced.constant_speed_torque(r.steady.mean_speed)[::2]
    ax.plot(x, Tc * k, lw=1, ls="--", label="constant mean speed")
    ax.plot(x, r.steady.crank_torque * k, lw=1, label="motor, at the crank")
    ax.set_xlabel("crank angle turned from the datum (deg)")
    ax.set_ylabel("torque (kN·m)")
    ax.set_title(f"{r.drive.name}: crank torque")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_shaking(r: DriveCurves, force_unit: str | None = None, ax: Any = None) -> Any:
    """Magnitude of the shaking force at the real speed and at the constant mean speed.

    Parameters
    ----------
    r : DriveResult
        The drive analysis (or anything with what :class:`DriveCurves` names).
    force_unit : str, optional
        Display unit of force (default kN).
    ax : matplotlib Axes, optional
        Where to draw.
    """
    ax = new_axes(ax)
    unit = force_unit or "kN"
    frame = r._columns
    x = np.degrees(r.steady.turned)
    real = np.hypot(frame["shaking_force_x_N"], frame["shaking_force_y_N"])
    const = np.hypot(frame["shaking_force_constant_speed_x_N"], frame["shaking_force_constant_speed_y_N"])
    ax.plot(x, convert(real, "N", unit), lw=1.2, label="real speed")
    ax.plot(x, convert(const, "N", unit), lw=1, ls="--", label="constant mean speed")
    ax.set_xlabel("crank angle turned from the datum (deg)")
    ax.set_ylabel(f"shaking force ({unit})")
    ax.set_title(f"{r.drive.name}: shaking force")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_startup(r: DriveCurves, ax: Any = None) -> Any:
    """Crank speed during the run-up from rest, rpm, with the moment the work is engaged.

    Parameters
    ----------
    r : DriveResult
        The drive analysis, with a start-up (or anything with what :class:`DriveCurves` names).
    ax : matplotlib Axes, optional
        Where to draw.
    """
    ax = new_axes(ax)
    s = r.startup
    assert s is not None
    ax.plot(s.time, convert(s.speed, "rad/s", "rpm"), lw=1)
    ax.axvline(s.engaged_at, color="k", ls="--", lw=0.8, label="work engaged")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("crank speed (rpm)")
    ax.set_title(f"{r.drive.name}: start-up from rest")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax
