"""Plots of drivetrain results: mode shapes, Campbell diagram, frequency response."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.plotting import new_axes
from mechdyn.units import convert

if TYPE_CHECKING:
    from mechdyn.drivetrain.campbell import CampbellResult
    from mechdyn.drivetrain.modal import ModalResult
    from mechdyn.drivetrain.response import FRFResult

__all__ = ["plot_campbell", "plot_frf", "plot_mode_shapes"]


def _hz(f: float) -> str:
    return f"{f:.0f} Hz" if f >= 100 else f"{f:.4g} Hz"


def _segments(result: ModalResult) -> tuple[list[list[int]], dict[int, str]]:
    """The disks in order, split where neighbours are not joined at ratio 1 (a gear mesh between
    them, or nothing): runs of disks to draw as one line, and a label for each break (the elements
    that change the ratio there, e.g. ``mesh 1 (ratio 4.32)``)."""
    names = result.disk_names
    drivetrain = result.drivetrain
    at_one: set[frozenset[str]] = set()
    ratio_labels: dict[str, list[str]] = {}
    for e, b in drivetrain.element_blocks:
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


def plot_mode_shapes(result: ModalResult, modes: Sequence[int] | None = None, ax: Any = None) -> Any:
    """Unit-scaled flexible mode shapes, one panel per mode (disk angle against disk).

    A gear mesh changes the angle by its ratio, so the line breaks there (a dotted separator named
    after the mesh) instead of joining the two disks straight across the ratio.

    Parameters
    ----------
    result : ModalResult
        The modes.
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
        fig, axes = plt.subplots(n, 1, figsize=(7.5, 1.2 + 1.5 * n), sharex=True, squeeze=False)
        panels = list(axes[:, 0])
        fig.suptitle(title, fontsize=11)
    else:
        panels = [ax] * max(len(modes), 1)
        ax.set_title(title, fontsize=10)
    x = np.arange(len(result.disk_names))
    runs, breaks = _segments(result)
    for panel, m in zip(panels, modes, strict=False):
        el, share = result.dominant_element(m - 1)
        label = (
            f"mode {m}: {_hz(result.frequencies_hz[m - 1])}, most strain energy in {el} ({100 * share:.0f} %)"
        )
        shape = result.unit_shapes[:, m - 1]
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
    first = panels[0]
    for i, text in breaks.items():
        if text:
            first.annotate(text, (i - 0.5, 1.0), xycoords=("data", "axes fraction"), xytext=(2, -2),
                           textcoords="offset points", fontsize=7, va="top", color="0.35",
                           bbox={"fc": "white", "ec": "none", "alpha": 0.85, "pad": 1})  # fmt: skip
    panels[-1].set_xticks(x, result.disk_names)
    panels[-1].set_xlabel("disk")
    for panel in panels:
        panel.set_ylabel("angle")
    if ax is not None and modes:
        ax.legend(fontsize="small")
    first.figure.tight_layout()
    return first


def plot_campbell(result: CampbellResult, ax: Any = None, max_frequency_hz: float | None = None) -> Any:
    """Excitation lines against reference speed (rpm), natural frequencies as horizontal lines."""
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


def plot_frf(result: FRFResult, outputs: Sequence[str] | None = None, ax: Any = None) -> Any:
    """Magnitude of disk angles (rad per unit excitation) against frequency, log-log."""
    ax = new_axes(ax)
    names = list(outputs) if outputs else list(result.disk_names)
    for n in names:
        ax.loglog(
            result.frequencies_hz, np.abs(result.angles[:, result.disk_names.index(n)]), label=f"disk {n}"
        )
    for f in result.natural_frequencies_hz:
        if result.frequencies_hz[0] <= f <= result.frequencies_hz[-1]:
            ax.axvline(f, color="0.7", lw=0.8, ls=":")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("angle amplitude (rad)")
    ax.set_title(f"{result.model_name}: steady-state response to the harmonic torques")
    ax.legend(fontsize="small")
    return ax
