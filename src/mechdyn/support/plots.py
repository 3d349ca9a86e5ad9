"""Plots of a machine on its supports: bed displacement, exciting and transmitted forces, mount
forces, mode shapes, and a rotating unbalance's floor force over speed."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from mechdyn.plotting import display_unit, legend, new_axes, overlaid
from mechdyn.units import convert

if TYPE_CHECKING:
    from mechdyn.support.excitation import PeriodicLoad
    from mechdyn.support.model import MountedMachine

__all__ = [
    "plot_displacement",
    "plot_forces",
    "plot_mode_shapes",
    "plot_modes",
    "plot_mount_forces",
    "plot_transmitted_vs_exciting",
    "plot_unbalance_sweep",
]


# -- what the figures read ------------------------------------------------------------------------------


class ResponseCurves(Protocol):
    """What the response figures read of a response over time (a
    :class:`~mechdyn.support.response.ResponseCurves`): the machine, its load, and the curves in SI
    (s, m, N)."""

    @property
    def machine(self) -> MountedMachine: ...
    @property
    def load(self) -> PeriodicLoad: ...
    @property
    def kind(self) -> str: ...
    @property
    def time(self) -> np.ndarray: ...
    @property
    def vertical_displacement(self) -> np.ndarray: ...
    @property
    def exciting_force(self) -> np.ndarray: ...
    @property
    def transmitted_force(self) -> np.ndarray: ...
    @property
    def mount_forces(self) -> np.ndarray: ...


class ModeShapes(Protocol):
    """What the mode figures read of a machine's modes (a :class:`~mechdyn.support.modes.SupportModes`):
    the machine, the frequencies (Hz), the shapes (m, rad per unit modal amplitude), each mode's
    kinetic-energy shares and dominant coordinate."""

    @property
    def machine(self) -> MountedMachine: ...
    @property
    def frequencies_hz(self) -> np.ndarray: ...
    @property
    def shapes(self) -> np.ndarray: ...
    @property
    def kinetic_energy(self) -> np.ndarray: ...
    @property
    def dominant(self) -> list[str]: ...


class SpeedCurves(Protocol):
    """What the unbalance figure reads of a sweep over speed (an
    :class:`~mechdyn.support.sweep.UnbalanceSweep`): the speeds (rad/s), the forces (N), the
    transmissibility, the running speed and the speeds that meet a natural frequency."""

    @property
    def machine(self) -> MountedMachine: ...
    @property
    def speed(self) -> np.ndarray: ...
    @property
    def unbalance_force(self) -> np.ndarray: ...
    @property
    def floor_force(self) -> np.ndarray: ...
    @property
    def transmissibility(self) -> np.ndarray: ...
    @property
    def running_speed(self) -> float: ...
    @property
    def resonance_speeds(self) -> np.ndarray: ...


# -- the figures ----------------------------------------------------------------------------------------


def _force_scale(values: np.ndarray, force_unit: str | None) -> tuple[float, str]:
    """(newtons per unit shown, the unit shown) of a force axis: ``force_unit`` where given, else the
    unit the largest force reads best in, as the tables choose it (:func:`mechdyn.plotting.display_unit`)."""
    if force_unit is None:
        shown, factor = display_unit(values, "N")
        return 1.0 / factor, shown
    return float(convert(1.0, force_unit, "N")), force_unit


def _abscissa(r: ResponseCurves) -> tuple[np.ndarray, str]:
    """Crank (or rotors' shaft) angle when the load has one and the response is one steady period."""
    a = r.load.angle
    if a is not None and r.kind == "steady state" and a.size == r.time.size:
        if r.load.rotors:
            return np.degrees(a), "shaft angle (deg)"
        return np.degrees(a), "crank angle from the datum (deg)"
    return r.time, "time (s)"


def plot_displacement(startup: ResponseCurves, steady: ResponseCurves, ax: Any = None) -> Any:
    """Bed displacement z(t): the start-up from rest and the steady state repeated over it, mm."""
    ax = new_axes(ax, figsize=(8.0, 4.0))
    ax.plot(startup.time, convert(startup.vertical_displacement, "m", "mm"), lw=1, label="start-up from rest")
    T = steady.load.period
    cycles = round(startup.time[-1] / T)
    t = np.concatenate([steady.time + k * T for k in range(cycles)])
    z = np.tile(steady.vertical_displacement, cycles)
    ax.plot(t, convert(z, "m", "mm"), lw=1, ls="--", color="k", label="steady state (frequency domain)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("bed displacement z (mm)")
    ax.set_title(f"{steady.machine.name}: bed displacement")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_forces(r: ResponseCurves, ax: Any = None, force_unit: str | None = None) -> Any:
    """Exciting (inertia) force F and transmitted force F_T over one period."""
    ax = new_axes(ax)
    scale, unit = _force_scale(r.exciting_force, force_unit)
    x, label = _abscissa(r)
    ax.plot(x, r.exciting_force / scale, label="exciting force F (on the machine)")
    ax.plot(x, r.transmitted_force / scale, ls="--", label="transmitted force F_T (to the floor)")
    ax.set_xlabel(label)
    ax.set_ylabel(f"vertical force ({unit})")
    ax.set_title(f"{r.machine.name}: exciting and transmitted force, steady state")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_transmitted_vs_exciting(r: ResponseCurves, ax: Any = None, force_unit: str | None = None) -> Any:
    """F_T against F over one period: a line of slope 1 means quasi-static transmission."""
    ax = new_axes(ax, figsize=(5.5, 5.0))
    scale, unit = _force_scale(r.exciting_force, force_unit)
    F, FT = r.exciting_force / scale, r.transmitted_force / scale
    ax.plot(F, FT, lw=1.5)
    lim = [min(F.min(), FT.min()), max(F.max(), FT.max())]
    ax.plot(lim, lim, color="0.5", ls=":", lw=1, label="F_T = F")
    ax.set_xlabel(f"exciting force F ({unit})")
    ax.set_ylabel(f"transmitted force F_T ({unit})")
    ax.set_title(f"{r.machine.name}: transmitted against exciting force")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_mount_forces(r: ResponseCurves, ax: Any = None, force_unit: str | None = None) -> Any:
    """Vertical force of each mount on the floor over one period (dynamic part)."""
    ax = new_axes(ax)
    scale, unit = _force_scale(r.mount_forces[..., 2], force_unit)
    x, label = _abscissa(r)
    forces = {m.name: r.mount_forces[:, i, 2] / scale for i, m in enumerate(r.machine.mounts)}
    for name, f in overlaid(forces):  # symmetric mounts carry one force: drawn once, named together
        ax.plot(x, f, lw=1.2, label=name)
    ax.set_xlabel(label)
    ax.set_ylabel(f"vertical mount force, dynamic part ({unit})")
    ax.set_title(f"{r.machine.name}: mount forces on the floor, steady state, without the weight")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_modes(m: ModeShapes, ax: Any = None) -> Any:
    """Each mode's kinetic energy shares by coordinate (stacked bars), frequencies on the axis."""
    ax = new_axes(ax, figsize=(7.0, 4.0))
    shares = 100 * m.kinetic_energy.T
    bottom = np.zeros(shares.shape[0])
    labels = [f"{k + 1}\n{f:.3g} Hz" for k, f in enumerate(m.frequencies_hz)]
    x = np.arange(shares.shape[0])
    for j, d in enumerate(m.machine.dofs):
        ax.bar(x, shares[:, j], bottom=bottom, label=d)
        bottom += shares[:, j]
    ax.set_xticks(x, labels)
    ax.set_ylim(0, 100)
    ax.set_ylabel("kinetic energy share (%)")
    ax.set_xlabel("mode")
    ax.set_title(f"{m.machine.name}: modes and their coupling")
    ax.legend(
        fontsize="small", ncols=min(6, len(m.machine.dofs)), loc="upper center", bbox_to_anchor=(0.5, -0.2)
    )
    return ax


def plot_mode_shapes(m: ModeShapes) -> Any:
    """Each mode drawn on the machine's outline: side view (x–z) above, top view (x–y) below.

    The outline is the box over the mounts up to twice the height of the centre of mass; the mode
    is scaled so that its largest corner displacement is a tenth of the box.
    """
    import matplotlib.pyplot as plt

    from mechdyn.support.model import Mount

    mach = m.machine
    pos = np.array([mt.position for mt in mach.mounts])
    g = mach.body.center_of_mass
    lo = np.minimum(pos.min(axis=0), g) - 0.5
    hi = np.maximum(pos.max(axis=0), g) + 0.5
    hi[2] = max(hi[2], 2 * g[2] - lo[2])
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    T = np.array([mach.mount_transform(Mount("c", c, (0.0, 0.0, 0.0))) for c in corners])  # (8, 3, n)
    size = float(np.max(hi - lo))
    n = len(m.frequencies_hz)
    fig, axes = plt.subplots(2, n, figsize=(2.4 * n + 0.6, 5.2), layout="constrained", squeeze=False)
    # corner k is (x, y, z) = (lo or hi by the bits 4, 2, 1 of k)
    side = [0, 1, 5, 4, 0]  # corner order around the face y = lo (x, z)
    top = [0, 2, 6, 4, 0]  # around the face z = lo (x, y)
    for k in range(n):
        u = T @ m.shapes[:, k]  # (8, 3)
        u *= 0.1 * size / max(np.abs(u).max(), 1e-300)
        moved = corners + u
        for row, (face, (i, j)) in enumerate(((side, (0, 2)), (top, (0, 1)))):
            ax = axes[row, k]
            ax.plot(corners[face, i], corners[face, j], color="0.6", lw=1, ls=":")
            ax.plot(moved[face, i], moved[face, j], color="C0", lw=1.5)
            ax.plot(pos[:, i], pos[:, j], "k^", ms=5)
            ax.set_aspect("equal", adjustable="datalim")
            ax.set_xticks([])
            ax.set_yticks([])
            if k == 0:
                ax.set_ylabel("side (x–z)" if row == 0 else "top (x–y)")
        axes[0, k].set_title(f"{k + 1}: {m.frequencies_hz[k]:.3g} Hz\n{m.dominant[k]}", fontsize="small")
    fig.suptitle(f"{mach.name}: mode shapes")
    return axes[0, 0]


def plot_unbalance_sweep(sweep: SpeedCurves, force_unit: str | None = None) -> Any:
    """A rotating unbalance over speed: its force and the floor force above, the transmissibility
    below (log scale), the running speed and the speeds that meet a natural frequency marked.

    Parameters
    ----------
    sweep : UnbalanceSweep or SpeedCurves
        The sweep (:func:`mechdyn.support.unbalance_sweep`).
    force_unit : str, optional
        The unit the forces are shown in (by default N, or kN from 1 kN).
    """
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter

    rpm = convert(sweep.speed, "rad/s", "rpm")
    scale, unit = _force_scale(np.concatenate([sweep.unbalance_force, sweep.floor_force]), force_unit)
    _, (top, low) = plt.subplots(2, 1, sharex=True, figsize=(8.0, 6.0), layout="constrained")
    top.plot(rpm, sweep.unbalance_force / scale, label="unbalance force U Ω² (on the machine)")
    top.plot(rpm, sweep.floor_force / scale, ls="--", label="floor force (through the mounts)")
    top.set_ylabel(f"largest force in a period ({unit})")
    top.set_title(f"{sweep.machine.name}: unbalance over speed")
    low.semilogy(rpm, sweep.transmissibility, color="C2", label="transmissibility")
    # plain numbers on the log axis: the saved figures show no mathtext (mechdyn.plotting.plain_text)
    low.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    # between the decades only 2 and 5 are labelled, so that the labels do not overprint
    low.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:g}" if f"{v:.0e}"[0] in "25" else ""))
    low.axhline(1.0, color="0.5", ls=":", lw=1, label="T = 1 (below: isolates)")
    low.set_ylabel("floor force / unbalance force")
    low.set_xlabel("speed of the first rotor (rpm)")
    running = convert(sweep.running_speed, "rad/s", "rpm")
    for ax in (top, low):
        ax.axvline(running, color="k", lw=1, label=f"running speed {running:.6g} rpm" if ax is top else None)
        for s, f, _ in sweep.resonance_speeds:
            at = convert(s, "rad/s", "rpm")
            if rpm[0] <= at <= rpm[-1]:
                ax.axvline(at, color="C3", ls=":", lw=1)
                if ax is top:
                    ax.annotate(
                        f"{f:.3g} Hz",
                        (at, 1.0),
                        xycoords=("data", "axes fraction"),
                        xytext=(2, -12),
                        textcoords="offset points",
                        fontsize="small",
                        color="C3",
                    )
        ax.grid(alpha=0.3)
        legend(ax, fontsize="small")
    return top
