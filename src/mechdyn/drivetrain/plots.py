"""Plots of drivetrain results: mode shapes, Campbell diagram, frequency response."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol

import numpy as np

from mechdyn.drivetrain.elements import Disk, Element, ElementBlocks
from mechdyn.plotting import legend, new_axes
from mechdyn.units import convert

__all__ = ["plot_campbell", "plot_frf", "plot_frf_loads", "plot_mode_shapes"]


class _DrawnModel(Protocol):
    """What the figures read of the model: its name (titles) and its elements with their blocks."""

    @property
    def name(self) -> str: ...
    @property
    def element_blocks(self) -> tuple[tuple[Element | Disk, ElementBlocks], ...]: ...


class ModeShapes(Protocol):
    """What :func:`plot_mode_shapes` reads of the modes (:class:`.modal.ModalResult`): the result is
    passed as it is.

    Attributes
    ----------
    drivetrain : Drivetrain
        The model (its name; its elements, whose ratios break the lines and whose inner nodes are
        drawn between their disks).
    disk_names : tuple of str
        The rows of the shapes: the disks, then the nodes inside divided shafts.
    omega : ndarray
        (n_modes,) natural circular frequencies of the flexible modes, rad/s.
    frequencies_hz : ndarray
        (n_modes,) the same in Hz.
    unit_shapes : ndarray
        (n_dofs, n_modes) the mode shapes, largest angle +1 (rad per rad).
    rigid_gears : bool
        Whether the meshes were taken as rigid constraints (the title).
    dominant_element : callable
        ``dominant_element(mode)``: the element with the largest share of mode ``mode``'s strain
        energy (0-based) and that share (a fraction).
    """

    @property
    def drivetrain(self) -> _DrawnModel: ...
    @property
    def disk_names(self) -> tuple[str, ...]: ...
    @property
    def omega(self) -> np.ndarray: ...
    @property
    def frequencies_hz(self) -> np.ndarray: ...
    @property
    def unit_shapes(self) -> np.ndarray: ...
    @property
    def rigid_gears(self) -> bool: ...
    def dominant_element(self, mode: int) -> tuple[str, float]: ...


class _Excitation(Protocol):
    """An excitation line of a Campbell diagram (:class:`.campbell.ExcitationLine`)."""

    @property
    def label(self) -> str: ...
    @property
    def kind(self) -> str: ...
    def frequency_hz(self, speed_rad_s: np.ndarray | float) -> np.ndarray: ...


class _NaturalFrequencies(Protocol):
    """The modes of a Campbell diagram: their frequencies (Hz) and the model (its name)."""

    @property
    def frequencies_hz(self) -> np.ndarray: ...
    @property
    def drivetrain(self) -> _DrawnModel: ...


class CampbellChart(Protocol):
    """What :func:`plot_campbell` reads of a Campbell diagram (:class:`.campbell.CampbellResult`): the
    result is passed as it is.

    Attributes
    ----------
    modal : ModalResult
        The modes: natural frequencies (Hz) and the model's name.
    reference : str
        The disk whose speed is the abscissa.
    speed_range : (float, float)
        Reference speeds, rad/s.
    lines : sequence of ExcitationLine
        The excitations: label, kind (``"shaft"`` or ``"mesh"``) and frequency (Hz) at a speed (rad/s).
    crossings : list of dict
        Each crossing's ``frequency_hz`` (Hz) and ``speed_rpm`` (rpm).
    """

    @property
    def modal(self) -> _NaturalFrequencies: ...
    @property
    def reference(self) -> str: ...
    @property
    def speed_range(self) -> tuple[float, float]: ...
    @property
    def lines(self) -> Sequence[_Excitation]: ...
    @property
    def crossings(self) -> list[dict[str, Any]]: ...


class FrequencyCurves(Protocol):
    """What :func:`plot_frf` and :func:`plot_frf_loads` read of a frequency response
    (:class:`.response.FRFResult`): the result is passed as it is.

    Attributes
    ----------
    frequencies_hz : ndarray
        (n_f,) excitation frequencies, Hz.
    disk_names : tuple of str
        The columns of ``angles``.
    angles : ndarray
        (n_f, n_dofs) complex angle amplitudes, rad.
    element_names, element_units : tuple of str
        The columns of ``element_loads`` and their units (``"N*m"``, ``"N"``).
    element_loads : ndarray
        (n_f, n_elements) complex loads, N·m or N.
    natural_frequencies_hz : ndarray
        Natural frequencies, Hz, marked on the curves.
    model_name : str
        For the titles.
    """

    @property
    def frequencies_hz(self) -> np.ndarray: ...
    @property
    def disk_names(self) -> tuple[str, ...]: ...
    @property
    def angles(self) -> np.ndarray: ...
    @property
    def element_names(self) -> tuple[str, ...]: ...
    @property
    def element_units(self) -> tuple[str, ...]: ...
    @property
    def element_loads(self) -> np.ndarray: ...
    @property
    def natural_frequencies_hz(self) -> np.ndarray: ...
    @property
    def model_name(self) -> str: ...


def _hz(f: float) -> str:
    return f"{f:.0f} Hz" if f >= 100 else f"{f:.4g} Hz"


def _dof_order(result: ModeShapes) -> list[int]:
    """The degrees of freedom in the order they are drawn: the disks as given, each divided shaft's
    nodes between its two disks where those are neighbours (else after the disks)."""
    names = list(result.disk_names)
    index = {n: i for i, n in enumerate(names)}
    internal = {n for _, b in result.drivetrain.element_blocks for n in b.internal}
    order = [i for i, n in enumerate(names) if n not in internal]
    for _, b in result.drivetrain.element_blocks:
        if not b.internal:
            continue
        a, z = index[b.disks[0]], index[b.disks[-1]]
        nodes = [index[n] for n in b.internal]
        where = order.index(a)
        if where + 1 < len(order) and order[where + 1] == z:
            order[where + 1 : where + 1] = nodes
        elif where > 0 and order[where - 1] == z:
            order[where:where] = nodes[::-1]
        else:
            order.extend(nodes)
    return order


def _segments(result: ModeShapes, names: Sequence[str]) -> tuple[list[list[int]], dict[int, str]]:
    """The degrees of freedom in drawing order (``names``), split where neighbours are not joined at
    ratio 1 (a gear mesh between them, or nothing): runs to draw as one line, and a label for each
    break (the elements that change the ratio there, e.g. ``mesh 1 (ratio 4.32)``)."""
    drivetrain = result.drivetrain
    at_one: set[frozenset[str]] = set()
    ratio_labels: dict[str, list[str]] = {}
    for e, b in drivetrain.element_blocks:
        if b.internal:  # a divided shaft: its nodes in a row at ratio 1
            at_one.update(frozenset(p) for p in zip(b.disks, b.disks[1:], strict=False))
            continue
        if len(b.disks) != 2:
            continue
        t = e.transmission()
        if t is not None and abs(t - 1.0) < 1e-12:
            at_one.add(frozenset(b.disks))
        elif t is not None and t != 0:
            for d in b.disks:
                ratio_labels.setdefault(d, []).append(f"{e.name} (ratio {1 / abs(t):.3g})")
    runs, breaks = [[0]], {}
    for i in range(1, len(names)):
        if frozenset((names[i - 1], names[i])) in at_one:
            runs[-1].append(i)
        else:
            runs.append([i])
            labels = ratio_labels.get(names[i], []) or ratio_labels.get(names[i - 1], [])
            breaks[i] = ", ".join(dict.fromkeys(labels))
    return runs, breaks


def plot_mode_shapes(result: ModeShapes, modes: Sequence[int] | None = None, ax: Any = None) -> Any:
    """Unit-scaled flexible mode shapes, one panel per mode (disk angle against disk).

    A gear mesh changes the angle by its ratio, so the line breaks there (a dotted separator named
    after the mesh) instead of joining the two disks straight across the ratio.

    Parameters
    ----------
    result : ModalResult
        The modes (or anything with what :class:`ModeShapes` names).
    modes : sequence of int, optional
        Modes to draw, 1-based (default: the lowest six).
    ax : matplotlib.axes.Axes, optional
        Draw every mode on these axes instead of one panel each.

    Returns
    -------
    matplotlib.axes.Axes
        The first panel (its ``figure`` holds them all).
    """
    import matplotlib.pyplot as plt

    modes = list(modes) if modes is not None else list(range(1, min(6, len(result.omega)) + 1))
    which = "rigid gears" if result.rigid_gears else "flexible meshes"
    title = f"{result.drivetrain.name}: mode shapes with {which}"
    if ax is None:
        n = max(len(modes), 1)
        height = 1.2 + 1.5 * n
        fig, axes = plt.subplots(n, 1, figsize=(7.5, height), sharex=True, squeeze=False)
        # fixed margins (inches) rather than a layout engine: the panels' places do not depend on
        # their contents here, and working them out drew the figure twice more than saving it does
        top, bottom, gap = 0.62, 0.55, 0.45
        panel = (height - top - bottom - (n - 1) * gap) / n
        fig.subplots_adjust(
            left=0.8 / 7.5, right=0.98, top=1 - top / height, bottom=bottom / height, hspace=gap / panel
        )
        panels = list(axes[:, 0])
        fig.suptitle(title, fontsize=11)
    else:
        panels = [ax] * max(len(modes), 1)
        ax.set_title(title, fontsize=10)
    order = _dof_order(result)
    names = [result.disk_names[i] for i in order]
    x = np.arange(len(names))
    runs, breaks = _segments(result, names)
    for panel, m in zip(panels, modes, strict=False):
        el, share = result.dominant_element(m - 1)
        label = (
            f"mode {m}: {_hz(result.frequencies_hz[m - 1])}, most strain energy in {el} ({100 * share:.0f} %)"
        )
        shape = result.unit_shapes[order, m - 1]
        color = None
        for run in runs:
            (line,) = panel.plot(
                x[run], shape[run], marker="o", color=color, label=label if color is None else None
            )
            color = line.get_color()
        panel.axhline(0.0, color="0.6", lw=0.8)
        for i in breaks:
            panel.axvline(i - 0.5, color="0.5", lw=0.8, ls=":")
        if ax is None:
            panel.set_title(label, fontsize=9, loc="left")
            panel.set_ylim(-1.15, 1.15)
            panel.set_yticks([-1.0, 0.0, 1.0])
    first = panels[0]
    for i, text in breaks.items():
        if text:
            first.annotate(text, (i - 0.5, 1.0), xycoords=("data", "axes fraction"), xytext=(2, -2),
                           textcoords="offset points", fontsize=7, va="top", color="0.35",
                           bbox={"fc": "white", "ec": "none", "alpha": 0.85, "pad": 1})  # fmt: skip
    internal = {n for _, b in result.drivetrain.element_blocks for n in b.internal}
    panels[-1].set_xticks(x, ["" if n in internal else n for n in names])  # a shaft's nodes unnamed
    panels[-1].set_xlabel("disk")
    for panel in panels:
        panel.set_ylabel("angle")
    if ax is not None and modes:
        legend(ax, fontsize="small")
    return first


def plot_campbell(result: CampbellChart, ax: Any = None, max_frequency_hz: float | None = None) -> Any:
    """Excitation lines against reference speed (rpm), natural frequencies as horizontal lines.

    Parameters
    ----------
    result : CampbellResult
        The diagram (or anything with what :class:`CampbellChart` names).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (default: a new figure).
    max_frequency_hz : float, optional
        Top of the frequency axis, Hz (default: a little above the highest excitation, and at least
        past the lowest natural frequency).

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.
    """
    ax = new_axes(ax, figsize=(9.5, 4.8))
    lo, hi = result.speed_range
    rpm = convert(np.linspace(lo, hi, 2), "rad/s", "rpm")
    omega = np.linspace(lo, hi, 2)
    freqs = result.modal.frequencies_hz
    # up to the highest excitation, and at least past the lowest natural frequency
    top = max_frequency_hz or 1.1 * max(
        [float(line.frequency_hz(hi)) for line in result.lines] + [float(freqs[0]) if freqs.size else 1.0]
    )
    for line in result.lines:
        ax.plot(rpm, line.frequency_hz(omega), ls="-" if line.kind == "shaft" else "--", label=line.label)
    for m, f in enumerate(freqs):
        if f <= top:
            ax.axhline(f, color="0.4", lw=0.8, ls=":")
            ax.annotate(f"mode {m + 1}: {_hz(f)}", (rpm[-1], f), fontsize="x-small", va="bottom", ha="right")
    for c in result.crossings:
        if c["frequency_hz"] <= top:
            ax.plot(c["speed_rpm"], c["frequency_hz"], "ko", ms=5, mfc="none")
    ax.set_xlim(rpm[0], rpm[-1])
    ax.set_ylim(0, top)
    ax.set_xlabel(f"speed of disk {result.reference} (rpm)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(f"{result.modal.drivetrain.name}: Campbell diagram")
    ax.legend(fontsize="x-small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return ax


def _bode(result: FrequencyCurves, curves: dict[str, np.ndarray], unit: str, ax: Any) -> Any:
    """Magnitude (log-log) of each complex curve in ``unit`` and, on a new figure, its phase under it."""
    import matplotlib.pyplot as plt

    from mechdyn.plotting import display_unit

    f = result.frequencies_hz
    if ax is None:
        _, (ax, phase) = plt.subplots(
            2, 1, figsize=(7.0, 6.0), sharex=True, layout="constrained", height_ratios=(2, 1)
        )
    else:  # the caller's axes take the magnitudes alone
        phase = None
    shown, factor = display_unit(np.abs(np.column_stack(list(curves.values()))), unit)
    for label, y in overlaid_complex(curves):
        line = ax.loglog(f, np.abs(y) * factor, label=label)[0]
        if phase is not None:
            phase.semilogx(f, np.degrees(np.unwrap(np.angle(y))), color=line.get_color())
    for fn in result.natural_frequencies_hz:
        if f[0] <= fn <= f[-1]:
            for a in (ax, phase) if phase is not None else (ax,):
                a.axvline(fn, color="0.7", lw=0.8, ls=":")
    legend(ax, fontsize="small")
    if phase is not None:
        phase.set_xlabel("frequency (Hz)")
        phase.set_ylabel("phase (deg)")
    else:
        ax.set_xlabel("frequency (Hz)")
    return ax, shown


def overlaid_complex(curves: dict[str, np.ndarray]) -> list[tuple[str, np.ndarray]]:
    """:func:`mechdyn.plotting.overlaid` for complex curves: equal ones (magnitude and phase) drawn once."""
    from mechdyn.plotting import overlaid

    stacked = {k: np.concatenate([np.real(v), np.imag(v)]) for k, v in curves.items()}
    kept = overlaid(stacked)
    first = {}
    for label, _ in kept:
        first[label] = curves[label.replace(" ≈ ", " = ").split(" = ")[0]]
    return [(label, first[label]) for label, _ in kept]


def plot_frf(result: FrequencyCurves, outputs: Sequence[str] | None = None, ax: Any = None) -> Any:
    """Disk angles per unit excitation against frequency: magnitude (log-log) and phase (deg).

    Parameters
    ----------
    result : FRFResult
        The response (or anything with what :class:`FrequencyCurves` names).
    outputs : sequence of str, optional
        Disks to draw (default: every disk).
    ax : matplotlib.axes.Axes, optional
        Axes for the magnitudes alone (default: a new figure with the phase under them).

    Returns
    -------
    matplotlib.axes.Axes
        The magnitude axes.
    """
    names = [n for n in (outputs or result.disk_names) if n in result.disk_names]
    curves = {f"disk {n}": result.angles[:, result.disk_names.index(n)] for n in names}
    ax, _ = _bode(result, curves, "rad", ax)
    ax.set_ylabel("angle amplitude (rad)")
    ax.set_title(f"{result.model_name}: disk angles in the steady state of the harmonic torques")
    return ax


def plot_frf_loads(result: FrequencyCurves, unit: str = "N*m", ax: Any = None) -> Any:
    """Shaft torques (``unit="N*m"``) or mesh forces (``unit="N"``) against frequency: magnitude
    (log-log, in kN·m or kN where large) and phase (deg), per unit excitation.

    Parameters
    ----------
    result : FRFResult
        The response (or anything with what :class:`FrequencyCurves` names).
    unit : {"N*m", "N"}
        Which loads: those of shafts and grounded springs (N·m), or of flexible meshes (N).
    ax : matplotlib.axes.Axes, optional
        Axes for the magnitudes alone (default: a new figure with the phase under them).

    Returns
    -------
    matplotlib.axes.Axes
        The magnitude axes.
    """
    curves = {
        n: result.element_loads[:, j]
        for j, (n, u) in enumerate(zip(result.element_names, result.element_units, strict=True))
        if u == unit
    }
    ax, shown = _bode(result, curves, unit, ax)
    what = "shaft torque" if unit == "N*m" else "mesh force"
    ax.set_ylabel(f"{what} amplitude ({shown})")
    ax.set_title(f"{result.model_name}: {what}s in the steady state of the harmonic torques")
    return ax
