"""Plots of speed sweeps and Floquet stability of geared drivetrains (matplotlib, imported lazily)."""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np

from mechdyn.plotting import legend

__all__ = ["plot_floquet", "plot_speed_sweep", "plot_stability_chart", "plot_sweep_dte"]


# -- what each figure reads (the results are passed as they are: these only name what is drawn) -------
class BranchCurves(Protocol):
    """What the sweep's figure reads of a branch followed by continuation
    (:class:`.continuation.ContinuedBranch`).

    Attributes
    ----------
    speeds : ndarray
        (n,) reference speeds along the branch, rad/s.
    dynamic_factor : ndarray
        (n, J) K_v of every mesh, dimensionless (NaN where unloaded).
    stable : ndarray
        (n,) True where the orbit is stable.
    fold_indices : ndarray
        The points that are folds, indices.
    """

    @property
    def speeds(self) -> np.ndarray: ...
    @property
    def dynamic_factor(self) -> np.ndarray: ...
    @property
    def stable(self) -> np.ndarray: ...
    @property
    def fold_indices(self) -> np.ndarray: ...


class SweepCurves(Protocol):
    """What :func:`plot_speed_sweep` and :func:`plot_sweep_dte` read of a speed sweep
    (:class:`.sweep_result.SpeedSweepResult`).

    Attributes
    ----------
    speeds : ndarray
        (n_s,) reference speeds Ω, rad/s.
    reference : str
        The disk whose speed is Ω.
    mesh_names : tuple of str
        The meshes, the columns of the (n_s, J) arrays.
    force_max, force_amplitude : ndarray
        (n_s, J) largest and half peak-to-peak mesh force, N.
    dynamic_factor, iso_dynamic_factor : ndarray
        (n_s, J) computed and ISO 6336-1 K_v, dimensionless (NaN where not given).
    dte_amplitude : ndarray
        (n_s, J) half peak-to-peak dynamic transmission error, m.
    stable : ndarray
        (n_s,) True where the periodic solution is stable.
    iso_resonance_speed : ndarray or None
        (J,) the reference speed at which ISO's pair alone resonates, rad/s.
    period_multiple : ndarray or None
        (n_s,) 1, or 2 where the orbit shown is period-doubled.
    down : SweepCurves or None
        The down sweep over the same speeds.
    branches : tuple of BranchCurves
        The branches followed by continuation.
    """

    @property
    def speeds(self) -> np.ndarray: ...
    @property
    def reference(self) -> str: ...
    @property
    def mesh_names(self) -> tuple[str, ...]: ...
    @property
    def force_max(self) -> np.ndarray: ...
    @property
    def force_amplitude(self) -> np.ndarray: ...
    @property
    def dynamic_factor(self) -> np.ndarray: ...
    @property
    def iso_dynamic_factor(self) -> np.ndarray: ...
    @property
    def dte_amplitude(self) -> np.ndarray: ...
    @property
    def stable(self) -> np.ndarray: ...
    @property
    def iso_resonance_speed(self) -> np.ndarray | None: ...
    @property
    def period_multiple(self) -> np.ndarray | None: ...
    @property
    def down(self) -> SweepCurves | None: ...
    @property
    def branches(self) -> tuple[BranchCurves, ...]: ...

    def resonances(self) -> dict[str, list[float]]:
        """Per mesh, the speeds of the peaks of its force amplitude, rad/s."""
        ...

    def train_resonances(self) -> dict[str, list[tuple[int, int, float, float]]]:
        """Per mesh, (mode number, order, frequency in Hz, reference speed in rad/s) where an order
        of its frequency meets a natural frequency of the train."""
        ...


class FloquetCurve(Protocol):
    """What :func:`plot_floquet` reads of a Floquet analysis (:class:`.floquet.FloquetResult`).

    Attributes
    ----------
    speeds : ndarray
        (n_s,) reference speeds Ω, rad/s.
    spectral_radius : ndarray
        (n_s,) ρ, the largest multiplier modulus, dimensionless.
    reference : str
        The disk whose speed is Ω.
    """

    @property
    def speeds(self) -> np.ndarray: ...
    @property
    def spectral_radius(self) -> np.ndarray: ...
    @property
    def reference(self) -> str: ...

    def unstable_ranges(self) -> list[tuple[float, float]]:
        """The speed ranges (from, to) where ρ > 1, rad/s."""
        ...


class ChartRegions(Protocol):
    """What :func:`plot_stability_chart` reads of a stability chart (:class:`.floquet.StabilityChart`).

    Attributes
    ----------
    speeds : ndarray
        (n_s,) reference speeds Ω, rad/s.
    amplitudes : ndarray
        (n_e,) stiffness variations ε of the mesh, dimensionless.
    unstable : ndarray
        (n_e, n_s) True where ρ > 1.
    reference : str
        The disk whose speed is Ω.
    mesh : str
        The mesh whose stiffness varies.
    """

    @property
    def speeds(self) -> np.ndarray: ...
    @property
    def amplitudes(self) -> np.ndarray: ...
    @property
    def unstable(self) -> np.ndarray: ...
    @property
    def reference(self) -> str: ...
    @property
    def mesh(self) -> str: ...

    def critical_speeds(self, orders: int = 2) -> np.ndarray:
        """The speeds where the mesh frequency is 2 f_n / k, k = 1 … ``orders``, rad/s."""
        ...


def _rpm(speeds: np.ndarray) -> np.ndarray:
    from mechdyn.units import convert

    return np.asarray(convert(speeds, "rad/s", "rpm"))


def plot_speed_sweep(result: SweepCurves, ax: Any = None, **display_units: Any) -> Any:
    """Dynamic factor K_v of every mesh over the reference speed (rpm), ISO 6336-1 K_v dashed where
    given (labelled as the pair alone, with its own resonance speed), the peaks marked, and the speeds
    where a mesh order meets a train mode drawn as grey lines labelled with the mode and the order.

    Parameters
    ----------
    result : SpeedSweepResult
        The sweep (or anything with what :class:`SweepCurves` names).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    **display_units : str
        Accepted for the result protocol; K_v is dimensionless.

    Returns
    -------
    matplotlib.axes.Axes
    """
    from mechdyn.plotting import new_axes

    ax = new_axes(ax)
    rpm = _rpm(result.speeds)
    kv = result.dynamic_factor
    loaded = np.isfinite(kv).any(axis=0)
    res = result.resonances()
    swept_down = result.down is not None and not np.array_equal(result.down.force_max, result.force_max)
    for j, name in enumerate(result.mesh_names):
        if loaded[j]:
            line = _branch(
                ax,
                rpm,
                kv[:, j],
                result.stable,
                label=f"{name}: K_v (periodic steady state{', swept up' if swept_down else ''})",
                doubled=_doubled(result),
            )
            for s in res[name]:
                ax.axvline(float(_rpm(np.array([s]))[0]), color=line.get_color(), lw=0.6, ls=":")
            down = result.down
            if (
                down is not None
                and down is not result
                and not np.array_equal(down.force_max, result.force_max)
            ):
                _branch(
                    ax,
                    _rpm(down.speeds),
                    down.dynamic_factor[:, j],
                    down.stable,
                    doubled=_doubled(down),
                    color=line.get_color(),
                    alpha=0.5,
                    label=f"{name}: K_v swept down",
                )
            _continued(ax, result, j, line.get_color())
        else:
            ax.plot(rpm, result.force_amplitude[:, j], label=f"{name}: force amplitude (N), no load")
        iso = result.iso_dynamic_factor[:, j]
        if np.isfinite(iso).any():
            at = result.iso_resonance_speed[j] if result.iso_resonance_speed is not None else np.nan
            where = f", resonant at {float(_rpm(np.array([at]))[0]):.0f} rpm" if np.isfinite(at) else ""
            ax.plot(rpm, iso, ls="--", label=f"{name}: ISO 6336-1 K_v, the pair alone{where}")
    drawn: set[float] = set()
    for found in result.train_resonances().values():
        for mode, order, _f, speed in found:
            x = round(float(_rpm(np.array([speed]))[0]), 1)
            if x in drawn:
                continue
            drawn.add(x)
            ax.axvline(x, color="0.6", lw=0.8, ls="--", zorder=0)
            ax.annotate(
                f"mode {mode} × {order}",
                (x, 0.0),
                xycoords=("data", "axes fraction"),
                xytext=(2, 3),
                textcoords="offset points",
                rotation=90,
                va="bottom",
                fontsize="x-small",
                color="0.4",
            )
    ax.set_xlabel(f"speed of disk {result.reference!r} (rpm)")
    ax.set_ylabel("dynamic factor K_v (max / static mesh force)")
    ax.set_title("dynamic mesh force over speed")
    ax.legend(fontsize="small", loc="upper left")
    return ax


def _continued(ax: Any, result: SweepCurves, j: int, color: Any) -> None:
    """The branches followed by continuation (:attr:`SpeedSweepResult.branches`, the down sweep's
    too): K_v of mesh ``j`` dashed where the orbit is unstable (between the folds), thin where it is
    stable, the folds marked by crosses; labelled once."""
    branches = result.branches + (result.down.branches if result.down is not None else ())
    labelled = False
    for branch in branches:
        kv = branch.dynamic_factor[:, j]
        if not np.isfinite(kv).any():
            continue
        x = _rpm(branch.speeds)
        stable = np.asarray(branch.stable, bool)
        unstable = ~stable
        near = unstable.copy()  # the unstable stretch with its ends, so that the curve joins
        near[1:] |= unstable[:-1]
        near[:-1] |= unstable[1:]
        ax.plot(x, np.where(stable, kv, np.nan), color=color, lw=0.8)
        ax.plot(
            x,
            np.where(near, kv, np.nan),
            color=color,
            lw=1.0,
            ls="--",
            label=None
            if labelled
            else f"{result.mesh_names[j]}: branch through the folds (dashed: unstable)",
        )
        folds = branch.fold_indices
        if folds.size:
            ax.plot(
                x[folds],
                kv[folds],
                "x",
                color=color,
                ms=6,
                label=None if labelled else f"{result.mesh_names[j]}: folds (the jump band's edges)",
            )
        labelled = True


def _doubled(result: SweepCurves) -> np.ndarray | None:
    return None if result.period_multiple is None else np.asarray(result.period_multiple) == 2


def _branch(ax: Any, x: np.ndarray, y: np.ndarray, stable: np.ndarray, **kw: Any) -> Any:
    """A curve solid where its periodic solution is stable and dashed where it is not (a steady
    state a machine does not reach), in one colour; the solid line (for the legend) is returned."""
    stable = np.asarray(stable, bool)
    doubled = kw.pop("doubled", None)
    (line,) = ax.plot(x, np.where(stable, y, np.nan), **kw)
    if doubled is not None and np.any(doubled):
        mark = {k: v for k, v in kw.items() if k not in ("label", "color")}
        ax.plot(x[doubled], y[doubled], "o", ms=3, color=line.get_color(), **mark)
        line.set_label(f"{line.get_label()} (dots: period doubled)")
    if not stable.all():
        near = stable.copy()  # the unstable stretches with their stable ends, so that the curve joins
        near[1:] &= ~stable[:-1]
        near[:-1] &= ~stable[1:]
        shown = ~stable | near
        kw = {k: v for k, v in kw.items() if k != "label"}
        kw["color"] = line.get_color()
        ax.plot(x, np.where(shown, y, np.nan), ls="--", **kw)
        line.set_label(f"{line.get_label()} (dashed: unstable, not reached)")
    return line


def plot_sweep_dte(result: SweepCurves, ax: Any = None, **display_units: Any) -> Any:
    """Amplitude of the dynamic transmission error of every mesh over speed (rpm).

    Parameters
    ----------
    result : SpeedSweepResult
        The sweep (or anything with what :class:`SweepCurves` names).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    **display_units : str
        ``length_unit`` (e.g. ``"um"``) for the DTE; default: the unit its size reads best in.

    Returns
    -------
    matplotlib.axes.Axes
    """
    from mechdyn.plotting import display_unit, new_axes
    from mechdyn.units import convert

    ax = new_axes(ax)
    unit = display_units.get("length_unit")
    if unit:
        shown, factor = unit, float(convert(1.0, "m", unit))
    else:
        shown, factor = display_unit(result.dte_amplitude, "m")
    for j, name in enumerate(result.mesh_names):
        ax.plot(_rpm(result.speeds), result.dte_amplitude[:, j] * factor, label=name)
    ax.set_xlabel(f"speed of disk {result.reference!r} (rpm)")
    ax.set_ylabel(f"DTE amplitude ({shown})")
    ax.set_title("dynamic transmission error along the line of action")
    legend(ax, fontsize="small")
    return ax


def plot_floquet(result: FloquetCurve, ax: Any = None) -> Any:
    """Largest Floquet multiplier modulus ρ over speed (rpm), unstable ranges shaded.

    Parameters
    ----------
    result : FloquetResult
        The Floquet analysis (or anything with what :class:`FloquetCurve` names).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from mechdyn.plotting import new_axes

    ax = new_axes(ax)
    rpm = _rpm(result.speeds)
    ax.plot(rpm, result.spectral_radius, label="ρ, largest multiplier modulus")
    ax.axhline(1.0, color="0.5", ls="--", lw=0.8)
    for a, b in result.unstable_ranges():
        ax.axvspan(float(_rpm(np.array([a]))[0]), float(_rpm(np.array([b]))[0]), color="C3", alpha=0.25)
    ax.set_xlabel(f"speed of disk {result.reference!r} (rpm)")
    ax.set_ylabel("spectral radius of the monodromy matrix")
    ax.set_title("parametric stability (Floquet): unstable where ρ > 1")
    legend(ax, fontsize="small")
    return ax


def plot_stability_chart(chart: ChartRegions, ax: Any = None) -> Any:
    """Unstable regions (ρ > 1) over speed (rpm) and stiffness variation ε, with the speeds where the
    mesh frequency is 2 f_n / k marked.

    Parameters
    ----------
    chart : StabilityChart
        The chart (or anything with what :class:`ChartRegions` names).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from mechdyn.plotting import new_axes

    ax = new_axes(ax)
    rpm = _rpm(chart.speeds)
    ax.contourf(
        rpm, chart.amplitudes, chart.unstable.astype(float), levels=[0.5, 1.5], colors=["C3"], alpha=0.5
    )
    for s in chart.critical_speeds(2):
        if chart.speeds.min() <= s <= chart.speeds.max():
            ax.axvline(float(_rpm(np.array([s]))[0]), color="0.4", lw=0.6, ls=":")
    ax.set_xlabel(f"speed of disk {chart.reference} (rpm)")
    ax.set_ylabel(f"stiffness variation ε of mesh {chart.mesh}")
    ax.set_title("stability chart: shaded where the vibration grows (ρ > 1)")
    return ax
