"""Plots of a time simulation of a geared drivetrain: speeds, mesh forces, dynamic transmission error."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from mechdyn.plotting import display_unit, legend, new_axes
from mechdyn.units import SHOWN_UNITS, convert

if TYPE_CHECKING:
    from mechdyn.gear_dynamics.system import GearSystem

__all__ = ["plot_dte", "plot_mesh_forces", "plot_speeds"]


class LostContact(Protocol):
    """What the figures read of an interval of lost contact (:class:`.result.ContactLoss`).

    Attributes
    ----------
    mesh : str
        The mesh.
    start : float
        When the loaded flanks parted, s.
    end : float or None
        When they closed again, s; None if still open at the end of the run.
    """

    @property
    def mesh(self) -> str: ...
    @property
    def start(self) -> float: ...
    @property
    def end(self) -> float | None: ...


class TimeHistories(Protocol):
    """What the figures read of a time simulation (:class:`.result.SimulationResult`): the result is
    passed as it is.

    Attributes
    ----------
    system : GearSystem
        The simulated system (its drivetrain's name, its meshes and their backlash).
    time : ndarray
        (N,) sample times, s.
    speeds : ndarray
        (n_dofs, N) disk speeds, rad/s, rows as :attr:`disk_names`.
    mesh_forces : ndarray
        (n_meshes, N) mesh forces along the line of action, N.
    dte : ndarray
        (n_meshes, N) dynamic transmission error, m.
    static_mesh_forces : ndarray or None
        (n_meshes,) quasi-static mesh forces, N.
    contact_losses : sequence of LostContact
        The intervals of lost drive-side contact.
    disk_names, mesh_names : tuple of str
        The rows of :attr:`speeds` and of the mesh arrays.
    """

    @property
    def system(self) -> GearSystem: ...
    @property
    def time(self) -> np.ndarray: ...
    @property
    def speeds(self) -> np.ndarray: ...
    @property
    def mesh_forces(self) -> np.ndarray: ...
    @property
    def dte(self) -> np.ndarray: ...
    @property
    def static_mesh_forces(self) -> np.ndarray | None: ...
    @property
    def contact_losses(self) -> Sequence[LostContact]: ...
    @property
    def disk_names(self) -> tuple[str, ...]: ...
    @property
    def mesh_names(self) -> tuple[str, ...]: ...


def _unit(values: Any, si: str, unit: str | None) -> tuple[str, float]:
    if unit:
        return SHOWN_UNITS.get(unit, unit), float(convert(1.0, si, unit))
    return display_unit(values, si)


def _losses(result: TimeHistories, ax: Any, mesh: str | None = None) -> None:
    """Shade the intervals of lost drive-side contact."""
    end = float(result.time[-1])
    labelled = False
    for c in result.contact_losses:
        if mesh is not None and c.mesh != mesh:
            continue
        ax.axvspan(c.start, end if c.end is None else c.end, color="0.85", lw=0,
                   label=None if labelled else "contact lost")  # fmt: skip
        labelled = True


def plot_speeds(result: TimeHistories, ax: Any = None) -> Any:
    """Speed of every disk over time, rpm.

    Parameters
    ----------
    result : SimulationResult
        The simulation (or anything with what :class:`TimeHistories` names).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax)
    for i, d in enumerate(result.disk_names):
        ax.plot(result.time, convert(result.speeds[i], "rad/s", "rpm"), label=d)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("speed (rpm)")
    ax.set_title(f"{result.system.drivetrain.name}: disk speeds")
    legend(ax, fontsize="small", ncol=2)
    return ax


def plot_mesh_forces(result: TimeHistories, unit: str | None = None, ax: Any = None) -> Any:
    """Mesh forces along the lines of action over time, with the quasi-static forces dashed and the
    contact losses shaded.

    Parameters
    ----------
    result : SimulationResult
        The simulation (or anything with what :class:`TimeHistories` names).
    unit : str, optional
        Force unit of the axis (e.g. ``"kN"``; default: the one the peak reads best in).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax)
    shown, factor = _unit(result.mesh_forces, "N", unit)
    _losses(result, ax)
    for j, n in enumerate(result.mesh_names):
        (line,) = ax.plot(result.time, result.mesh_forces[j] * factor, label=n)
        if result.static_mesh_forces is not None:
            ax.axhline(result.static_mesh_forces[j] * factor, color=line.get_color(), ls="--", lw=0.8)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"mesh force ({shown})")
    ax.set_title(f"{result.system.drivetrain.name}: mesh forces (dashed: quasi-static)")
    legend(ax, fontsize="small")
    return ax


def plot_dte(result: TimeHistories, unit: str | None = None, ax: Any = None) -> Any:
    """Dynamic transmission error δ − e of every mesh over time, with its backlash band.

    Parameters
    ----------
    result : SimulationResult
        The simulation (or anything with what :class:`TimeHistories` names).
    unit : str, optional
        Length unit of the axis (e.g. ``"um"``; default: the one the peak reads best in).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax)
    shown, factor = _unit(result.dte if result.dte.size else np.zeros(1), "m", unit)
    _losses(result, ax)
    for j, mesh in enumerate(result.system.meshes):
        (line,) = ax.plot(result.time, result.dte[j] * factor, label=mesh.name)
        if mesh.backlash is not None:
            ax.axhline(0.0, color=line.get_color(), ls=":", lw=0.8)
            ax.axhline(-mesh.backlash * factor, color=line.get_color(), ls=":", lw=0.8)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"dynamic transmission error ({shown})")
    ax.set_title(f"{result.system.drivetrain.name}: dynamic transmission error (dotted: backlash)")
    legend(ax, fontsize="small")
    return ax
