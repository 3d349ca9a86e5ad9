"""The result of ``modes-from-test``: identified modes, the model against the test (MAC, frequency and
damping errors) before and after updating, the updated values, the FRF overlays, and the prediction
of another analysis with the band the test leaves."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechdyn.measurement.compare import ModeComparison
from mechdyn.measurement.data import MeasuredFRF
from mechdyn.measurement.identify import IdentifiedModes
from mechdyn.measurement.prediction import Prediction
from mechdyn.measurement.update_result import ModelUpdate
from mechdyn.results import Result, Table, summary_table

__all__ = ["TestCorrelation"]

_PAIR_COLUMNS = [
    "measured mode",
    "model mode",
    "measured [Hz]",
    "model [Hz]",
    "error [%]",
    "measured damping [%]",
    "model damping [%]",
    "damping error [%]",
    "MAC",
]


def _list(values: Any) -> list[float]:
    return [float(v) for v in np.asarray(values, dtype=float)]


def _max_abs(values: Any) -> float:
    a = np.asarray(values, dtype=float)
    return float(np.max(np.abs(a))) if a.size else float("nan")


def _cell(v: float) -> float | None:
    return None if not np.isfinite(v) else float(v)


@dataclass(frozen=True, repr=False)
class TestCorrelation(Result):
    """A test against its model (:func:`mechdyn.measurement.correlation.modes_from_test`).

    Attributes
    ----------
    name : str
        The test's name.
    data_file, model_file : str
        The data file and the tested model file, as the measurement file names them.
    f_min_hz, f_max_hz : float
        The identification band, Hz.
    measured : MeasuredFRF
        The measured FRFs, SI.
    modes : IdentifiedModes
        The identified modes with their scatter and stabilisation chart.
    before : ModeComparison
        The measured modes against the tested model's (paired by MAC).
    model_frf : MeasuredFRF
        The tested model's FRFs at the measured points, noise-free.
    update : ModelUpdate or None
        The updating (None when the file asks for none).
    updated_frf : MeasuredFRF or None
        The updated model's FRFs at the measured points.
    written : str or None
        The updated model file, when written.
    prediction : Prediction or None
        The file's ``[predict]`` analysis on the tested and the updated model, with its band (None:
        the file asks for none).
    """

    __test__ = False  # not a pytest class, whatever its name

    name: str
    data_file: str
    model_file: str
    f_min_hz: float
    f_max_hz: float
    measured: MeasuredFRF = field(compare=False)
    modes: IdentifiedModes = field(compare=False)
    before: ModeComparison = field(compare=False)
    model_frf: MeasuredFRF = field(compare=False)
    update: ModelUpdate | None = field(default=None, compare=False)
    updated_frf: MeasuredFRF | None = field(default=None, compare=False)
    written: str | None = None
    prediction: Prediction | None = field(default=None, compare=False)

    @property
    def after(self) -> ModeComparison | None:
        """The measured modes against the updated model's (same pairs), or None."""
        return None if self.update is None else self.update.after

    # -- the protocol -------------------------------------------------------------------------------

    def summary(self) -> dict[str, Any]:
        """The identified modes, the pairs' errors and MAC, and the updated values (SI)."""
        m, b = self.modes, self.before
        points = dict.fromkeys(p for p, _ in (*self.measured.outputs, *self.measured.references))
        out: dict[str, Any] = {
            "data_file": self.data_file,
            "tested_model_file": self.model_file,
            "band_min_hz": float(self.f_min_hz),
            "band_max_hz": float(self.f_max_hz),
            "measured_points": len(points),
            "identified_modes": int(m.omega.size),
            "frequencies_hz": _list(m.frequencies_hz),
            "frequency_scatter_hz": _list(m.frequency_scatter_hz),
            "damping_ratios": _list(m.damping),
            "damping_scatter": _list(m.damping_scatter),
            "paired_modes": len(b.pairs),
            "model_frequencies_hz": _list(b.model_hz),
            "frequency_error_percent": _list(100 * b.frequency_error),
            "damping_error_percent": _list(100 * b.damping_error),
            "mac": _list(b.paired_mac),
            "frequency_error_max_percent": 100 * _max_abs(b.frequency_error),
            "mac_min": float(np.min(b.paired_mac)) if len(b.pairs) else float("nan"),
        }
        u = self.update
        if u is not None:
            a = u.after
            out |= {
                "updated_parameters": len(u.names),
                "identifiable_parameters": int(np.count_nonzero(u.identifiable)),
                "updated_model_frequencies_hz": _list(a.model_hz),
                "updated_frequency_error_percent": _list(100 * a.frequency_error),
                "updated_damping_error_percent": _list(100 * a.damping_error),
                "updated_mac": _list(a.paired_mac),
                "updated_frequency_error_max_percent": 100 * _max_abs(a.frequency_error),
                "chi2_before": float(u.chi2_before),
                "chi2_after": float(u.chi2_after),
                "birge_ratio": float(u.birge_ratio),
                "updated_values": {name: _value_entry(u, i) for i, name in enumerate(u.names)},
                "posterior_method": u.posterior_method,
            }
            if u.posterior is not None:
                out["posterior_diagnostics"] = u.posterior.diagnostics()
        if self.written is not None:
            out["updated_model_file"] = self.written
        p = self.prediction
        if p is not None:
            out |= {
                "prediction_analysis": p.spec.analysis,
                "prediction_samples": p.spec.samples if p.band is not None else 0,
                "predicted": p.summary(),
            }
        return out

    def to_frame(self) -> Any:
        """One row per paired mode: measured and model frequencies, damping, errors and MAC (before
        updating, and after where updated)."""
        import pandas as pd

        b = self.before
        frame = pd.DataFrame(
            {
                "measured_mode": b.pairs[:, 0] + 1,
                "model_mode": b.pairs[:, 1] + 1,
                "measured_frequency_hz": b.measured_hz,
                "measured_scatter_hz": b.measured_scatter_hz,
                "model_frequency_hz": b.model_hz,
                "frequency_error_percent": 100 * b.frequency_error,
                "measured_damping_ratio": b.measured_damping,
                "model_damping_ratio": b.model_damping,
                "damping_error_percent": 100 * b.damping_error,
                "mac_ratio": b.paired_mac,
            }
        )
        a = self.after
        if a is not None:
            after = pd.DataFrame(
                {
                    "measured_mode": a.pairs[:, 0] + 1,
                    "updated_model_frequency_hz": a.model_hz,
                    "updated_frequency_error_percent": 100 * a.frequency_error,
                    "updated_model_damping_ratio": a.model_damping,
                    "updated_damping_error_percent": 100 * a.damping_error,
                    "updated_mac_ratio": a.paired_mac,
                }
            )
            frame = frame.merge(after, on="measured_mode", how="left")
        return frame

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        """The pairs' table and the identified modes, with their units, for the results database."""
        from mechdyn.results import frame_arrays

        m = self.modes
        pairs = frame_arrays(self.to_frame())
        # the model against the measurement first (a dashboard draws the first few against the mode)
        first = ["measured_mode", "frequency_error_percent", "updated_frequency_error_percent", "mac_ratio"]
        ordered = {k: pairs[k] for k in [*first, "updated_mac_ratio"] if k in pairs}
        return (
            ordered
            | pairs
            | {
                "identified_frequency_hz": (np.asarray(m.frequencies_hz, float), "Hz"),
                "identified_frequency_scatter_hz": (np.asarray(m.frequency_scatter_hz, float), "Hz"),
                "identified_damping_ratio": (np.asarray(m.damping, float), "1"),
                "identified_damping_scatter_ratio": (np.asarray(m.damping_scatter, float), "1"),
            }
        )

    def tables(self, **display_units: str) -> list[Table]:
        """The summary, the identified modes, the pairs before (and after) updating, the updated values."""
        skip = ("updated_model_file",) if self.written is None else ()
        tables = [summary_table(self.summary(), skip=skip, display_units=display_units)]
        m = self.modes
        tables.append(
            Table(
                "identified modes",
                [
                    "mode",
                    "frequency [Hz]",
                    "scatter [Hz]",
                    "damping [%]",
                    "damping scatter [%]",
                    "stable orders",
                ],
                [
                    [i + 1, float(f), float(df), 100 * float(z), 100 * float(dz), int(n)]
                    for i, (f, df, z, dz, n) in enumerate(
                        zip(
                            m.frequencies_hz,
                            m.frequency_scatter_hz,
                            m.damping,
                            m.damping_scatter,
                            m.stable_orders,
                            strict=True,
                        )
                    )
                ],
                note=f"{m.method}, between {self.f_min_hz:g} and {self.f_max_hz:g} Hz",
            )
        )
        tables.append(_pair_table("model against the test (paired by MAC)", self.before, self.model_file))
        u = self.update
        if u is not None:
            tables.append(_pair_table("updated model against the test", u.after, "the updated model"))
            tables.append(_values_table(u))
        if self.prediction is not None:
            tables.append(self.prediction.table(**display_units))
        return tables

    def plots(self, **display_units: str) -> dict[str, Callable[[], Any]]:
        """The stabilisation chart, the MAC matrix (before and after updating), the FRF overlay
        (measured against the model before and after updating) and, when updated, the frequency
        errors before and after, and the prediction (each output before and after updating, with its
        band)."""
        out: dict[str, Callable[[], Any]] = {
            "stabilisation.png": lambda: self.modes.chart.plot(modes=self.modes),
            "mac.png": self.plot_mac,
            "frf_overlay.png": self.plot_frf,
        }
        if self.update is not None:
            out["frequency_errors.png"] = self.update.plot
        if self.prediction is not None:
            out["prediction.png"] = self.prediction.plot
        return out

    @property
    def warnings(self) -> tuple[str, ...]:
        """Measured modes left unpaired, values not identifiable, the updating's warnings, and a
        prediction without a band or with a loose one."""
        notes: list[str] = []
        unpaired = self.modes.omega.size - len(self.before.pairs)
        if unpaired:
            notes.append(
                f"{unpaired} of the {self.modes.omega.size} identified modes pair with no model mode "
                "(MAC below the threshold): check the points' mapping, or the model has no such mode"
            )
        u = self.update
        if u is not None:
            notes.extend(u.warnings)
            for name, ok, why in zip(u.names, u.identifiable, u.reasons, strict=True):
                if not ok:
                    notes.append(
                        f"{name} is not identifiable from these modes ({why}); held at its model value"
                    )
        if self.prediction is not None:
            notes.extend(self.prediction.warnings)
        return tuple(notes)

    # -- plots ----------------------------------------------------------------------------------------

    def plot_mac(self) -> Any:
        """The MAC matrices of the measured modes against the model's, before (and after) updating.

        Returns
        -------
        matplotlib Axes
            The first panel.
        """
        import matplotlib.pyplot as plt

        shown = [("tested model", self.before)]
        if self.after is not None:
            shown.append(("updated model", self.after))
        _, axes = plt.subplots(1, len(shown), figsize=(5 * len(shown), 4.5), squeeze=False)
        for ax, (title, c) in zip(axes[0], shown, strict=True):
            c.plot(ax=ax)
            for i, j in c.pairs:
                ax.text(j, i, f"{c.mac[i, j]:.2f}", ha="center", va="center", fontsize=7, color="k")
            rows, cols = c.mac.shape
            ax.set_xticks(range(cols), [str(k + 1) for k in range(cols)])
            ax.set_yticks(range(rows), [str(k + 1) for k in range(rows)])
            ax.set_title(title)
        return axes[0, 0]

    def plot_frf(self) -> Any:
        """Measured FRFs against the model's at the same points, before and after updating (magnitude,
        log scale): the driving points first, then the strongest, at most four
        (:func:`mechdyn.measurement.plots.plot_frf_overlay`).

        Returns
        -------
        matplotlib Axes
            The first panel.
        """
        from mechdyn.measurement.plots import plot_frf_overlay

        return plot_frf_overlay(
            self.measured, self.model_frf, self.updated_frf, band_hz=(self.f_min_hz, self.f_max_hz)
        )


def _pair_table(title: str, c: ModeComparison, against: str) -> Table:
    rows = [
        [
            int(i) + 1,
            int(j) + 1,
            float(fm),
            float(fk),
            100 * float(e),
            100 * float(zm),
            _cell(100 * float(zk)),
            _cell(100 * float(ez)),
            float(mac),
        ]
        for (i, j), fm, fk, e, zm, zk, ez, mac in zip(
            c.pairs,
            c.measured_hz,
            c.model_hz,
            c.frequency_error,
            c.measured_damping,
            c.model_damping,
            c.damping_error,
            c.paired_mac,
            strict=True,
        )
    ]
    note = (
        f"{against}: errors are (model − measured)/measured; modes pair one to one by the largest summed MAC"
        if rows
        else f"no measured mode pairs with a mode of {against}: check the points' mapping"
    )
    return Table(title, _PAIR_COLUMNS, rows, note=note)


def _value_entry(u: ModelUpdate, i: int) -> dict[str, Any]:
    """Parameter ``i`` of an update, SI, each key ending with its unit (``updated_N_per_m``)."""
    from mechdyn.units import key_suffix

    sfx = key_suffix(u.units[i]) if u.units[i] else ""
    sfx = f"_{sfx}" if sfx else ""
    entry: dict[str, Any] = {f"prior{sfx}": float(u.prior[i]), f"updated{sfx}": float(u.value[i])}
    if u.identifiable[i]:
        entry[f"standard_uncertainty{sfx}"] = float(u.standard_uncertainty[i])
        entry[f"low_95{sfx}"], entry[f"high_95{sfx}"] = (float(v) for v in u.interval_95[i])
        if u.posterior is not None:  # the sample's own figures (its arrays hold the identifiable values)
            j = int(np.count_nonzero(u.identifiable[:i]))
            entry[f"posterior_mean{sfx}"] = float(u.posterior.mean[j])
            entry[f"posterior_median{sfx}"] = float(u.posterior.median[j])
    entry["identifiable"] = bool(u.identifiable[i])
    return entry


def _values_table(u: ModelUpdate) -> Table:
    from mechdyn.units import SHOWN_UNITS

    rows = []
    for i, name in enumerate(u.names):
        f = float(u.factors[i])
        lo, hi = (float(v) / f for v in u.interval_95[i])
        rows.append(
            [
                name,
                float(u.prior[i]) / f,
                float(u.value[i]) / f,
                _cell(float(u.standard_uncertainty[i]) / f),
                _cell(lo),
                _cell(hi),
                "yes" if u.identifiable[i] else "no",
                SHOWN_UNITS.get(u.units[i], u.units[i]),
            ]
        )
    held = [f"{n}: {why}" for n, ok, why in zip(u.names, u.identifiable, u.reasons, strict=True) if not ok]
    note = f"χ² {u.chi2_before:.4g} before, {u.chi2_after:.4g} after (Birge ratio {u.birge_ratio:.3g}); " + (
        "95 % credible intervals of the sampled posterior; " + u.posterior.statement
        if u.posterior is not None
        else "95 % intervals from the residuals' covariance"
    )
    if held:
        note += "; not identifiable, held at the model's value: " + "; ".join(held)
    return Table(
        "updated values",
        [
            "parameter",
            "model",
            "updated",
            "standard uncertainty",
            "95 % low",
            "95 % high",
            "identifiable",
            "unit",
        ],
        rows,
        note=note,
    )
