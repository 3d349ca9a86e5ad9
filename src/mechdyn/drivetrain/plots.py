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


def plot_mode_shapes(result: ModalResult, modes: Sequence[int] | None = None, ax: Any = None) -> Any:
    """Unit-scaled flexible mode shapes (disk angle against disk); ``modes`` are 1-based."""
    ax = new_axes(ax)
    modes = list(modes) if modes is not None else list(range(1, min(6, len(result.omega)) + 1))
    x = np.arange(len(result.disk_names))
    for m in modes:
        f = result.frequencies_hz[m - 1]
        el, share = result.dominant_element(m - 1)
        ax.plot(
            x,
            result.unit_shapes[:, m - 1],
            marker="o",
            label=f"mode {m}: {f:.4g} Hz ({el} {100 * share:.0f} %)",
        )
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_xticks(x, result.disk_names)
    ax.set_xlabel("disk")
    ax.set_ylabel("angle (largest = 1)")
    ax.set_title(f"{result.drivetrain.name}: mode shapes")
    if modes:
        ax.legend(fontsize="small")
    return ax


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
