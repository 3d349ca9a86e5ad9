"""The measurement's figures that more than one place draws: the FRF overlay of a test against its
model, before and after updating (the run's report through :meth:`TestCorrelation.plot_frf
<mechdyn.measurement.TestCorrelation.plot_frf>`, and the dashboard's page of a stored run, from the
FRFs recomputed from what the run recorded)."""

from __future__ import annotations

from typing import Any

import numpy as np

from mechdyn.measurement.data import MeasuredFRF

__all__ = ["FRF_OVERLAY_CAPTION", "OVERLAY_CHANNELS", "overlay_channels", "plot_frf_overlay"]

OVERLAY_CHANNELS = 4
"""FRFs overlaid at most: the driving points first, then the strongest."""

FRF_OVERLAY_CAPTION = "FRF overlay: measured, model before updating, model after updating"
"""The overlay's caption in words, as a page that shows it names it."""

_FRF_UNITS = {"receptance": "m/N", "mobility": "m/(s·N)", "accelerance": "m/(s²·N)"}


def overlay_channels(measured: MeasuredFRF, limit: int = OVERLAY_CHANNELS) -> list[tuple[int, int]]:
    """The FRFs to overlay: driving points (output = reference) first, then by peak magnitude.

    Parameters
    ----------
    measured : MeasuredFRF
        The measurement.
    limit : int
        At most this many (a count, at least 1).

    Returns
    -------
    list of (int, int)
        (output, reference) indices into ``measured.H``'s last two axes.
    """
    if limit < 1:
        raise ValueError(f"overlay_channels: limit={limit!r}; give at least 1 FRF to overlay")
    peak = np.abs(measured.H).max(axis=0)
    order = sorted(
        ((o, r) for o in range(peak.shape[0]) for r in range(peak.shape[1])),
        key=lambda c: (measured.outputs[c[0]] != measured.references[c[1]], -peak[c]),
    )
    return order[:limit]


def plot_frf_overlay(
    measured: MeasuredFRF,
    model: MeasuredFRF,
    updated: MeasuredFRF | None = None,
    band_hz: tuple[float, float] | None = None,
) -> Any:
    """Measured FRFs against a model's at the same points, before and (when given) after updating:
    magnitude on a log scale, one panel per FRF, the driving points first, then the strongest, at
    most :data:`OVERLAY_CHANNELS` (Ewins, *Modal Testing*, 2nd ed., 2000, §8.2: the overlay of
    measured and predicted FRFs as the first check of a model against a test).

    Parameters
    ----------
    measured : MeasuredFRF
        The measured FRFs, SI (m/N, m/(s·N) or m/(s²·N) as its ``kind`` says).
    model : MeasuredFRF
        The model's FRFs at the same outputs, references and lines (before updating), SI.
    updated : MeasuredFRF, optional
        The updated model's, likewise.
    band_hz : (float, float), optional
        The identification band, Hz, shaded.

    Returns
    -------
    matplotlib Axes
        The first panel.

    Raises
    ------
    ValueError
        When a model's FRFs are not at the measured lines, outputs and references.
    """
    import matplotlib.pyplot as plt

    from mechdyn.plotting import legend

    for what, frf in (("model", model), ("updated", updated)):
        if frf is not None and frf.H.shape != measured.H.shape:
            raise ValueError(
                f"plot_frf_overlay: {what} FRFs of shape {frf.H.shape} against measured ones of shape "
                f"{measured.H.shape}; give the model's FRFs at the measured lines, outputs and references"
            )
    channels = overlay_channels(measured)
    n = len(channels)
    cols = 2 if n > 1 else 1
    rows = -(-n // cols)
    _, axes = plt.subplots(rows, cols, figsize=(6 * cols, 3.2 * rows), squeeze=False, sharex=True)
    f = measured.frequencies_hz
    unit = _FRF_UNITS[measured.kind]
    for ax, (o, r) in zip(axes.flat, channels, strict=False):
        ax.semilogy(f, np.abs(measured.H[:, o, r]), color="0.3", lw=1.0, label="measured")
        ax.semilogy(f, np.abs(model.H[:, o, r]), "--", color="C0", lw=1.0, label="model")
        if updated is not None:
            ax.semilogy(f, np.abs(updated.H[:, o, r]), color="C1", lw=1.0, label="updated model")
        if band_hz is not None:
            ax.axvspan(band_hz[0], band_hz[1], color="0.93", zorder=0)
        (po, do), (pr, dr) = measured.outputs[o], measured.references[r]
        ax.set_title(f"{po}:{do} / {pr}:{dr}", fontsize="small")
        ax.set_ylabel(f"|H| ({unit})")
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("frequency (Hz)")
    legend(axes[0, 0], fontsize="small")
    return axes[0, 0]
