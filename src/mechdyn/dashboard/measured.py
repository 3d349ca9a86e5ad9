"""A stored ``modes-from-test`` run's model against its measurement, as its run page shows it: the
FRF overlay (measured, the tested model before updating, the model after updating) drawn by the
report's own code (:func:`mechdyn.measurement.plots.plot_frf_overlay`), and the modes' pairing from
the stored outputs.

The database keeps the measurement file's text and path and the run's outputs, not the FRFs: the
measured ones are read again from the data file the measurement file names (relative to it, as the
run recorded its path), the model's recomputed from the tested model file at the measured points
(H = B (K − ω²M + iωC)⁻¹ Bᵀ, :func:`mechdyn.measurement.correlation.model_frf`), and the updated
model's from the updated values the run stored. A data file that is no longer where the run found it
is said in words on the page.
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from mechdyn.errors import MechdynError

__all__ = [
    "ANALYSIS",
    "PAIR_COLUMNS",
    "MeasuredView",
    "Overlay",
    "OverlayError",
    "files_key",
    "measured_view",
    "overlay_figure",
    "overlay_frfs",
    "pairing",
]

ANALYSIS = "modes-from-test"
"""The analysis whose runs' pages show the model against the measurement."""

PAIR_COLUMNS: tuple[tuple[str, str, str, float], ...] = (
    # heading, unit, stored output (the pairs' table the run keeps, else the summary's list), factor
    ("measured mode", "", "measured_mode", 1.0),
    ("model mode", "", "model_mode", 1.0),
    ("measured", "Hz", "measured_frequency_hz", 1.0),
    ("scatter", "Hz", "measured_scatter_hz", 1.0),
    ("model before", "Hz", "model_frequency_hz", 1.0),
    ("error before", "%", "frequency_error_percent", 1.0),
    ("MAC before", "", "mac_ratio", 1.0),
    ("model after", "Hz", "updated_model_frequency_hz", 1.0),
    ("error after", "%", "updated_frequency_error_percent", 1.0),
    ("MAC after", "", "updated_mac_ratio", 1.0),
    ("measured damping", "%", "measured_damping_ratio", 100.0),
    ("damping error before", "%", "damping_error_percent", 1.0),
    ("damping error after", "%", "updated_damping_error_percent", 1.0),
)
"""The pairing table's columns: each pair's modes, frequencies, errors and MAC before and after
updating, and its damping."""

# the summary's per-pair lists, for a run whose stored arrays lack the pairs' table
_SUMMARY_LISTS = {
    "model_frequency_hz": "model_frequencies_hz",
    "frequency_error_percent": "frequency_error_percent",
    "mac_ratio": "mac",
    "updated_model_frequency_hz": "updated_model_frequencies_hz",
    "updated_frequency_error_percent": "updated_frequency_error_percent",
    "updated_mac_ratio": "updated_mac",
    "damping_error_percent": "damping_error_percent",
    "updated_damping_error_percent": "updated_damping_error_percent",
}


@dataclass(frozen=True)
class MeasuredView:
    """What a stored test's run page shows of the model against the measurement, found without
    drawing anything (the overlay itself is :func:`overlay_figure`, which the page links to).

    Attributes
    ----------
    caption : str
        The overlay's caption in words (what it overlays).
    note : str
        Where the overlay's FRFs come from, or why it is not drawn (the data file not found).
    drawn : bool
        Whether the overlay can be drawn (its data file is where the run recorded it).
    columns : list of (str, str)
        The pairing table's headings and units.
    rows : list of list
        Its rows, one per paired mode, values in the columns' units (None: not stored).
    """

    caption: str
    note: str
    drawn: bool
    columns: list[tuple[str, str]]
    rows: list[list[Any]]


def _measurement(run: Any) -> dict[str, Any]:
    """The ``[measurement]`` table of the stored measurement file (empty where it has none)."""
    try:
        table = tomllib.loads(run.model_text).get("measurement")
    except tomllib.TOMLDecodeError:
        return {}
    return table if isinstance(table, dict) else {}


def _beside(run: Any, relative: Any) -> Path | None:
    """A file the measurement file names, relative to it as the run recorded its path."""
    return Path(run.model_path).parent / relative if isinstance(relative, str) and relative else None


def files_key(run: Any) -> tuple[Any, ...]:
    """What the overlay is drawn from besides the stored run: the data and tested model files' paths
    with their modification times (ns) and sizes (bytes), None for one not there; a page keeps its
    overlay until one of them changes.

    Parameters
    ----------
    run : StoredRun
        A stored ``modes-from-test`` run.
    """
    t = _measurement(run)
    key: list[Any] = []
    for path in (_beside(run, t.get("data")), _beside(run, t.get("model"))):
        try:
            st = os.stat(path) if path is not None else None
        except OSError:
            st = None
        key.append((str(path), st.st_mtime_ns, st.st_size) if st is not None else (str(path), None))
    return tuple(key)


def pairing(run: Any) -> tuple[list[tuple[str, str]], list[list[Any]]]:
    """The paired modes as the run stored them: one row per pair, the columns of
    :data:`PAIR_COLUMNS` that it stored (from its pairs' table, else from its summary's lists).

    Parameters
    ----------
    run : StoredRun
        A stored ``modes-from-test`` run (with its arrays).

    Returns
    -------
    (list of (str, str), list of list)
        The headings with their units, and the rows (numbers in those units; None where a pair has
        no value, a damping error of a model without damping).
    """
    n = run.scalars.get("paired_modes")
    found: dict[str, list[Any]] = {}
    for _heading, _unit, key, factor in PAIR_COLUMNS:
        if key in run.arrays:
            values = np.asarray(run.arrays[key][0], dtype=float) * factor
        elif isinstance(run.scalars.get(_SUMMARY_LISTS.get(key, "")), list):
            values = np.asarray(run.scalars[_SUMMARY_LISTS[key]], dtype=float) * factor
        else:
            continue
        if isinstance(n, int) and values.size != n:
            continue  # not one value per pair: not this table's
        whole = key.endswith("_mode")
        found[key] = [None if not np.isfinite(v) else (int(v) if whole else float(v)) for v in values]
    columns = [(h, u) for h, u, key, _f in PAIR_COLUMNS if key in found]
    size = max((len(v) for v in found.values()), default=0)
    rows = [[found[key][i] for _h, _u, key, _f in PAIR_COLUMNS if key in found] for i in range(size)]
    return columns, rows


def _updated_values(run: Any) -> dict[str, float]:
    """Each updated value the run stored, SI, by its path (``mounts.*.stiffness.z``)."""
    stored = run.scalars.get("updated_values")
    out: dict[str, float] = {}
    if isinstance(stored, dict):
        for name, entry in stored.items():
            value = next(
                (v for k, v in (entry or {}).items() if k == "updated" or k.startswith("updated_")), None
            )
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                out[name] = float(value)
    return out


def _updated_model(tested: Any, values: dict[str, float]) -> Any:
    """The tested model with the updated values set (as the updating set them), loaded."""
    from mechdyn.io.modelfile import load_source
    from mechdyn.measurement.updating import updated_source

    return load_source(updated_source(tested.source, values)).model


class Overlay(NamedTuple):
    """The FRFs of a stored test's overlay, SI (:class:`~mechdyn.measurement.MeasuredFRF` each)."""

    measured: Any  # read again from the data file
    model: Any  # the tested model's, before updating
    updated: Any  # the updated model's (None: the run updated nothing)
    band_hz: tuple[float, float]  # the identification band, Hz
    data_file: str  # the data and tested model files, as the measurement file names them
    model_file: str


class OverlayError(MechdynError):
    """The overlay of a stored test cannot be recomputed (a file it names is not found, or fails)."""


def overlay_frfs(run: Any) -> Overlay:
    """The FRFs a stored test's overlay draws, recomputed from what the run recorded: the measured
    ones read again from the data file its measurement file names (relative to that file's recorded
    path), the tested model's at the measured points, and, where the run updated the model, the
    model's with the updated values it stored (H = B (K − ω²M + iωC)⁻¹ Bᵀ in the measured kind,
    :func:`mechdyn.measurement.correlation.model_frf`; Ewins, *Modal Testing*, 2nd ed., 2000, §2.5).

    Parameters
    ----------
    run : StoredRun
        A stored ``modes-from-test`` run.

    Returns
    -------
    Overlay

    Raises
    ------
    OverlayError
        When the data file is not where the run found it (naming it, where it was looked for and
        what to do), or the files it names do not make the test any more.
    """
    from mechdyn.io.modelfile import ModelSource, load_source
    from mechdyn.measurement.correlation import model_frf

    why = _missing(run)
    if why is not None:
        raise OverlayError(why)
    try:
        parsed = tomllib.loads(run.model_text)
        spec = load_source(ModelSource(run.model_path, run.model_text, run.model_sha256, parsed)).model
        before = model_frf(spec.tested.model, spec.measured, spec.mapping)
        values = _updated_values(run)
        after = None
        if values:
            after = model_frf(_updated_model(spec.tested, values), spec.measured, spec.mapping)
    except (MechdynError, tomllib.TOMLDecodeError) as exc:
        raise OverlayError(f"the files the run names do not make its test now: {exc}") from None
    band = (float(spec.f_min_hz), float(spec.f_max_hz))
    return Overlay(spec.measured, before, after, band, spec.data_file, spec.model_file)


def _data_file(run: Any) -> tuple[str, Path | None]:
    """The data file as the measurement file names it, and where it is looked for."""
    t = _measurement(run)
    return str(t.get("data")), _beside(run, t.get("data"))


def _missing(run: Any) -> str | None:
    """Why the data file is not found, in words; None where it is there."""
    named, data = _data_file(run)
    if data is not None and data.is_file():
        return None
    return (
        f"the measured data file {named!r} is not found at {data} (next to the measurement file "
        f"{run.model_path}, as the run recorded it); serve the dashboard from the folder the run was "
        "made in, or put the data file back there"
    )


def overlay_figure(run: Any) -> Any:
    """The FRF overlay of a stored test, drawn as its report draws it
    (:func:`mechdyn.measurement.plots.plot_frf_overlay`, as a PNG by
    :func:`mechdyn.reports.html.figures_of`) from the FRFs of :func:`overlay_frfs`.

    Parameters
    ----------
    run : StoredRun
        A stored ``modes-from-test`` run.

    Returns
    -------
    mechdyn.reports.html.Figure
        Its caption and base64 PNG.

    Raises
    ------
    OverlayError
        As :func:`overlay_frfs`.
    """
    from mechdyn.measurement.plots import plot_frf_overlay
    from mechdyn.reports.html import figures_of

    o = overlay_frfs(run)
    caption = _caption(o.updated is not None)
    return figures_of(
        {"frf_overlay.png": lambda: plot_frf_overlay(o.measured, o.model, o.updated, band_hz=o.band_hz)},
        {"frf_overlay.png": caption},
    )[0]


def _caption(updated: bool) -> str:
    from mechdyn.measurement.plots import FRF_OVERLAY_CAPTION

    return FRF_OVERLAY_CAPTION if updated else "FRF overlay: measured, model (the run updated nothing)"


def measured_view(run: Any) -> MeasuredView:
    """The model against the measurement for a stored ``modes-from-test`` run's page, from what the
    run stored and whether its data file is there (nothing is read or drawn).

    Parameters
    ----------
    run : StoredRun
        The stored run, with its arrays (:meth:`mechdyn.store.ResultStore.get`).

    Returns
    -------
    MeasuredView
    """
    t = _measurement(run)
    updated = bool(_updated_values(run))
    columns, rows = pairing(run)
    why = _missing(run)
    if why is not None:
        note = f"The FRF overlay is not drawn: {why}."
    else:
        lo, hi = run.scalars.get("band_min_hz"), run.scalars.get("band_max_hz")
        band = f" ({lo:g} to {hi:g} Hz)" if isinstance(lo, float) and isinstance(hi, float) else ""
        note = (
            f"Measured FRFs read again from {t.get('data')}; the model's recomputed from {t.get('model')} "
            "as it is now"
            + (", with the updated values the run stored" if updated else "")
            + f"; the identification band{band} shaded."
        )
    return MeasuredView(_caption(updated), note, why is None, columns, rows)
