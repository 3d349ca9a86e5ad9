"""Prediction with a band: an analysis of the tested model run on the updated model, the updated
values' uncertainty carried through (issue 47, point 5).

A measurement file's ``[predict]`` table names a registered analysis of the tested model (``"support"``
for a machine on its mounts), the summary keys to predict (``transmitted_force_max_N``, nested with
dots as a design study names them) with their display units, and the sampling (``samples``,
``method``, ``seed``). ``modes-from-test`` then runs the analysis on the tested model and on the
updated one, and samples the identifiable values' posterior through it
(:meth:`mechdyn.measurement.ModelUpdate.predict`, which calls :func:`mechdyn.uncertainty.propagate`):
the median and the 95 % band (the 2.5 % and 97.5 % quantiles, each with its confidence interval from
the order statistics) of every output.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field

from mechdyn.errors import ModelFileError
from mechdyn.io.fields import FileModel
from mechdyn.results import Table

__all__ = ["PredictSpec", "PredictTable", "Prediction", "build_predict", "check_samples", "predict"]

DEFAULT_SAMPLES = 64
MIN_SAMPLES = 8
# below this many samples the order statistics bound a 2.5 % or 97.5 % quantile only loosely
FEW_SAMPLES = 32
# the scramblings of a "qmc" propagation (mechdyn.uncertainty.propagate's default, which
# ModelUpdate.predict keeps): n must be this times a power of 2
QMC_REPLICATES = 16
QUANTILES = (0.025, 0.5, 0.975)


class PredictOutputRow(FileModel):
    output: str
    """A summary key of the analysis, nested with dots (``floor_force_range_N.3``: the third entry of
    a list, counting from 1)."""
    unit: str = ""
    """Display unit of the output (default: the unit a designer reads a value of its size in)."""


class PredictTable(FileModel):
    analysis: str
    """A registered analysis of the tested model (``mechdyn analyses`` lists them; ``"support"`` for a
    support file), run on the updated model."""
    outputs: list[Annotated[str, Field(min_length=1)] | PredictOutputRow] = Field(min_length=1)
    """The summary keys to predict: names (``"transmitted_force_max_N"``) or tables with a display
    unit (``{output = "transmitted_force_max_N", unit = "kN"}``)."""
    samples: int = DEFAULT_SAMPLES
    """Model evaluations of the band (at least 8; 32 or more for quantile intervals that are not
    wide; for ``"qmc"`` 16 × a power of 2)."""
    method: Literal["mc", "qmc"] = "mc"
    """``"mc"``: Monte Carlo; ``"qmc"``: randomised quasi-Monte Carlo (16 scrambled Sobol sequences)."""
    seed: int = 0
    """Random seed of the sampling (the same seed, the same band)."""
    options: dict[str, Any] = Field(default_factory=dict)
    """The analysis' options, as its command names them without the dashes (``{cycles = 1}``)."""


@dataclass(frozen=True)
class PredictOutput:
    """One output to predict: its summary key, SI unit and display unit (``""``: chosen by size)."""

    key: str
    unit: str
    display: str = ""

    def shown(self, values: Sequence[float], display_units: Mapping[str, str]) -> tuple[str, str]:
        """The unit to show ``values`` in: the file's, else the command's force or length unit, else
        the unit a designer reads the largest in (:func:`mechdyn.units.readable_unit`); as pint
        reads it and as shown (``""`` for a number without unit).

        Parameters
        ----------
        values : sequence of float
            The values to show, SI (NaN ignored).
        display_units : mapping
            ``force_unit``, ``length_unit``: the command's display units.
        """
        from mechdyn.studies.cells import unit_text
        from mechdyn.units import SHOWN_UNITS, readable_unit

        chosen = {"N": display_units.get("force_unit"), "m": display_units.get("length_unit")}
        pick = self.display or chosen.get(self.unit)
        if pick or self.unit in ("", "1"):
            return pick or "", unit_text(pick or "")
        sizes = [abs(float(v)) for v in values if np.isfinite(v)]
        return readable_unit(max(sizes, default=0.0), SHOWN_UNITS.get(self.unit, self.unit))

    @property
    def suffix(self) -> str:
        """The key suffix of the output's unit as its own key writes it (``hz`` for
        ``natural_frequencies_hz.1``, ``N`` for ``transmitted_force_max_N``), so that a key built with
        it reads back the same unit; ``""`` for a number without unit."""
        from mechdyn.units import key_suffix, key_unit

        if self.unit in ("", "1"):
            return ""
        for part in reversed(self.key.split(".")):
            words = part.split("_")
            for i in range(1, min(4, len(words))):
                tail = "_".join(words[-i:])
                if key_unit(f"x_{tail}") == self.unit:
                    return tail
        return key_suffix(self.unit)

    @property
    def words(self) -> str:
        """The output in words (``transmitted force max``, ``floor force range 3``)."""
        from mechdyn.studies.outputs import Watched

        return Watched(self.key, self.unit, self.display).words


@dataclass(frozen=True)
class PredictSpec:
    """A measurement file's ``[predict]`` table, checked against the registry and the tested model.

    Attributes
    ----------
    analysis : str
        The registered analysis to run.
    outputs : tuple of PredictOutput
        The summary keys to predict, with their units.
    samples : int
        Model evaluations of the band (count).
    method : {"mc", "qmc"}
        The sampling.
    seed : int
        Random seed.
    options : mapping
        The analysis' options, SI.
    path : str
        The measurement file (for messages).
    """

    analysis: str
    outputs: tuple[PredictOutput, ...]
    samples: int = DEFAULT_SAMPLES
    method: str = "mc"
    seed: int = 0
    options: Mapping[str, Any] = field(default_factory=dict)
    path: str = ""

    @property
    def keys(self) -> list[str]:
        """The outputs' summary keys."""
        return [o.key for o in self.outputs]

    def summary_of(self, loaded: Any) -> dict[str, Any]:
        """The analysis' summary of a loaded model (SI).

        Parameters
        ----------
        loaded : LoadedModel
            The tested model or a variant of it.
        """
        from mechdyn.registry import get

        return get(self.analysis).run(loaded, **self.options).summary()

    def values(self, loaded: Any) -> list[float]:
        """The outputs of a loaded model, SI, in the order of :attr:`outputs`: the function
        :meth:`ModelUpdate.predict` samples.

        Parameters
        ----------
        loaded : LoadedModel
            The tested model or a variant of it.

        Raises
        ------
        ModelFileError
            For an output that names no number in the analysis' summary.
        """
        from mechdyn.studies.outputs import output_problem, output_value

        summary = self.summary_of(loaded)
        out = []
        for i, key in enumerate(self.keys):
            value = output_value(summary, key)
            if value is None:
                why = output_problem(summary, key) or f"{key!r} is not a number"
                raise ModelFileError(
                    self.path,
                    f"[predict] → outputs #{i + 1}",
                    f"{why}; name a number of the {self.analysis} analysis' summary",
                    key,
                )
            out.append(value)
        return out


def _fail(path: str, where: str, message: str, value: Any) -> ModelFileError:
    return ModelFileError(path, f"[predict] → {where}", message, value)


def _output(analysis: Any, row: str | PredictOutputRow, i: int, path: str) -> PredictOutput:
    """An output of the analysis, checked against its registered outputs and its display unit."""
    from mechdyn.units import UnitError, convert

    key, unit = (row, "") if isinstance(row, str) else (row.output, row.unit)
    try:
        si = analysis.output_unit(key)
    except LookupError as exc:
        message = f"{exc.args[0]} (nested values with dots: floor_force_range_N.3)"
        raise _fail(path, f"outputs #{i + 1}", message, key) from None
    if unit:
        try:
            convert(1.0, si or "", unit)
        except UnitError:
            raise _fail(
                path,
                f"outputs #{i + 1} → unit",
                f"unit {unit!r} cannot show {key!r}, which is in {si or 'no unit'}; give a unit of the "
                "same kind (kN for a force in N) or none",
                unit,
            ) from None
    return PredictOutput(key, si, unit)


def _options(analysis: Any, given: Mapping[str, Any], path: str) -> dict[str, Any]:
    """The analysis' options from the file, checked as a design study checks its ``options``."""
    from mechdyn.studies.errors import StudyError
    from mechdyn.studies.study import analysis_options

    known = {o.name: o for o in analysis.options}
    for k in given:
        if k not in known or known[k].writes:
            usable = [n for n, o in known.items() if not o.writes]
            raise _fail(
                path,
                f"options → {k}",
                f"the {analysis.name} analysis has no option {k!r} to run with; its options: "
                f"{', '.join(usable) or 'none'}",
                given[k],
            )
    try:
        return analysis_options(analysis, given, "")
    except StudyError as exc:
        said = str(exc).split("[study] → options → ", 1)[-1]
        name, _, why = said.partition(": ")
        raise _fail(path, f"options → {name}", why or said, given.get(name)) from None


def check_samples(path: str, n: int, method: str, *, where: str = "samples") -> None:
    """Check a prediction's sample count: at least :data:`MIN_SAMPLES`, and for ``"qmc"`` 16 × a
    power of 2 (the scrambled Sobol sequences of :func:`mechdyn.uncertainty.propagate`).

    Parameters
    ----------
    path : str
        The measurement file (for messages).
    n : int
        The samples asked for (count).
    method : {"mc", "qmc"}
        The sampling.
    where : str
        The field named in the message.

    Raises
    ------
    ModelFileError
        Naming the file, the field, the value and the fix.
    """
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < MIN_SAMPLES:
        raise _fail(
            path,
            where,
            f"{n!r}: give at least {MIN_SAMPLES} samples ({DEFAULT_SAMPLES} by default; {FEW_SAMPLES} or "
            "more for 95 % band ends whose confidence intervals are not wide)",
            n,
        )
    per = int(n) // QMC_REPLICATES
    if method == "qmc" and (n % QMC_REPLICATES or per & (per - 1)):
        near = QMC_REPLICATES * (1 << max(per.bit_length() - 1, 1))
        raise _fail(
            path,
            where,
            f'{n}: method = "qmc" takes {QMC_REPLICATES} scrambled Sobol sequences of a power of 2 points '
            f'each; give samples = {QMC_REPLICATES} × 2^k (e.g. {near}), or method = "mc"',
            n,
        )


def build_predict(path: str, table: PredictTable, tested_type: str) -> PredictSpec:
    """The ``[predict]`` table checked: a registered analysis of the tested model's type, outputs it
    registers (with display units of their kind), options it has, and enough samples.

    Parameters
    ----------
    path : str
        The measurement file (for messages).
    table : PredictTable
        The file's ``[predict]`` table.
    tested_type : str
        The tested model's ``[model] type`` (``"support"``, ``"drivetrain"``).

    Returns
    -------
    PredictSpec

    Raises
    ------
    ModelFileError
        Naming the file, the field, the value and the fix.
    """
    from mechdyn.registry import analyses

    found = analyses()
    fits = [n for n, a in found.items() if tested_type in a.model_types]
    if table.analysis not in found or tested_type not in found[table.analysis].model_types:
        what = "is not a registered analysis of" if table.analysis not in found else "does not run on"
        raise _fail(
            path,
            "analysis",
            f"{table.analysis!r} {what} a {tested_type} model; give one of {', '.join(map(repr, fits))}",
            table.analysis,
        )
    analysis = found[table.analysis]
    outputs = tuple(_output(analysis, row, i, path) for i, row in enumerate(table.outputs))
    keys = [o.key for o in outputs]
    twice = sorted({k for k in keys if keys.count(k) > 1})
    if twice:
        raise _fail(
            path, "outputs", f"{', '.join(map(repr, twice))} given twice; give each output once", twice
        )
    check_samples(path, table.samples, table.method)
    return PredictSpec(
        analysis=table.analysis,
        outputs=outputs,
        samples=table.samples,
        method=table.method,
        seed=table.seed,
        options=_options(analysis, table.options, path),
        path=path,
    )


@dataclass(frozen=True, repr=False)
class Prediction:
    """An analysis' outputs on the tested model, on the updated one, and their band.

    Attributes
    ----------
    spec : PredictSpec
        What was asked.
    prior : ndarray
        (k,) each output of the tested model, SI.
    updated : ndarray
        (k,) each output of the updated model (at the updated values), SI; the tested model's
        where nothing was updated.
    band : PropagationResult or None
        The outputs over the identifiable values' posterior (None: no band, see ``note``).
    note : str
        Why there is no band, or what limits it (empty when nothing does).
    """

    spec: PredictSpec
    prior: np.ndarray
    updated: np.ndarray
    band: Any = None
    note: str = ""

    def _quantile(self, q: float, part: str) -> np.ndarray:
        if self.band is None:
            return np.full(len(self.spec.outputs), np.nan)
        return np.array([getattr(d.quantiles[q], part) for d in self.band.distributions], dtype=float)

    @property
    def median(self) -> np.ndarray:
        """(k,) the outputs' median over the posterior, SI (NaN without a band)."""
        return self._quantile(0.5, "value")

    @property
    def low(self) -> np.ndarray:
        """(k,) the 2.5 % quantile: the band's lower end, SI (NaN without a band)."""
        return self._quantile(0.025, "value")

    @property
    def high(self) -> np.ndarray:
        """(k,) the 97.5 % quantile: the band's upper end, SI (NaN without a band)."""
        return self._quantile(0.975, "value")

    def confidence(self, q: float) -> np.ndarray:
        """(k, 2) the 95 % confidence interval of quantile ``q`` (0.025, 0.5 or 0.975), SI, from the
        order statistics (:func:`mechdyn.uncertainty.estimates.quantile_interval`); ±inf where the
        samples cannot bound it, NaN without a band.

        Parameters
        ----------
        q : float
            The quantile's probability (fraction).
        """
        return np.stack([self._quantile(q, "low"), self._quantile(q, "high")], axis=1)

    def summary(self) -> dict[str, Any]:
        """Per output (by its key): the tested and updated model's values and, with a band, the median
        and the band's ends with the bounds of their confidence intervals that the samples give, SI,
        each key ending with its unit; ``band``: whether a band is claimed."""

        def num(v: float) -> float | None:
            return float(v) if np.isfinite(v) else None

        out: dict[str, Any] = {}
        for j, o in enumerate(self.spec.outputs):
            sfx = f"_{o.suffix}" if o.suffix else ""
            entry: dict[str, Any] = {
                f"tested_model{sfx}": num(self.prior[j]),
                f"updated_model{sfx}": num(self.updated[j]),
            }
            if self.band is not None:
                entry |= {
                    f"median{sfx}": num(self.median[j]),
                    f"low_95{sfx}": num(self.low[j]),
                    f"high_95{sfx}": num(self.high[j]),
                }
                # each band end's confidence interval, where the samples bound it (not ±inf)
                for end, q in (("low_95", 0.025), ("high_95", 0.975)):
                    for side, v in zip(("low", "high"), self.confidence(q)[j], strict=True):
                        if np.isfinite(v):
                            entry[f"{end}_confidence_{side}{sfx}"] = float(v)
            entry["band"] = self.band is not None
            out[o.key] = entry
        return out

    def table(self, **display_units: str) -> Table:
        """The outputs in words, each row in its display unit: tested model, updated model, median,
        the band's ends and their confidence intervals.

        Parameters
        ----------
        **display_units : str
            ``force_unit``, ``length_unit``: the command's display units (a row's own unit in the
            file wins).
        """
        from mechdyn.numbers import number_text
        from mechdyn.units import convert

        rows = []
        lo_ci, hi_ci = self.confidence(0.025), self.confidence(0.975)
        for j, o in enumerate(self.spec.outputs):
            si = [self.prior[j], self.updated[j], self.median[j], self.low[j], self.high[j]]
            display, shown = o.shown(si, display_units)
            scale = float(convert(1.0, o.unit, display)) if display and o.unit else 1.0  # no offsets

            def ci(pair: np.ndarray, scale: float = scale) -> str | None:
                if np.all(np.isnan(pair)):
                    return None
                ends = [number_text(v * scale) if np.isfinite(v) else ("−∞" if v < 0 else "∞") for v in pair]
                return " … ".join(ends)

            values = [float(v) * scale if np.isfinite(v) else None for v in si]
            rows.append([o.words, *values, ci(lo_ci[j]), ci(hi_ci[j]), shown])
        return Table(
            f"prediction of the {self.spec.analysis} analysis",
            [
                "output",
                "tested model",
                "updated model",
                "median",
                "95 % low",
                "95 % high",
                "CI of 95 % low",
                "CI of 95 % high",
                "unit",
            ],
            rows,
            note=self.describe(),
        )

    def describe(self) -> str:
        """What the band is in words: the sampling, and its limits."""
        s = self.spec
        if self.band is None:
            return self.note
        what = (
            f"updated model: at the updated values; median and 95 % band (2.5 % and 97.5 % quantiles) over "
            f"the updated values' posterior, {self.band.method}, {s.samples} samples (seed {s.seed}); CI: "
            "the 95 % confidence interval of each band end, from the order statistics (∞: the samples "
            "cannot bound it)"
        )
        return f"{what}; {self.note}" if self.note else what

    @property
    def warnings(self) -> tuple[str, ...]:
        """The note, when the band is missing or loose."""
        return (f"prediction of the {self.spec.analysis} analysis: {self.note}",) if self.note else ()

    def plot(self, ax: Any = None, **display_units: str) -> Any:
        """Each output before and after updating, with the band the test leaves, relative to the
        tested model's value (a bar per output: tested model at 1).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (a new figure when None).
        **display_units : str
            Unused (the values are drawn relative to the tested model's); accepted for the result
            protocol.

        Returns
        -------
        matplotlib Axes
        """
        import textwrap

        import matplotlib.pyplot as plt

        from mechdyn.plotting import legend

        k = len(self.spec.outputs)
        if ax is None:
            _, ax = plt.subplots(figsize=(max(4.5, 2.4 * k + 1.5), 3.8))
        x = np.arange(k)
        ref = np.where(self.prior != 0, self.prior, 1.0)
        ax.scatter(x - 0.25, self.prior / ref, marker="s", color="0.4", label="tested model", zorder=3)
        ax.scatter(x, self.updated / ref, marker="o", color="C1", label="updated model", zorder=3)
        if self.band is not None:
            med, lo, hi = self.median / ref, self.low / ref, self.high / ref
            ax.errorbar(
                x + 0.25,
                med,
                yerr=np.abs(np.vstack([med - lo, hi - med])),
                fmt="_",
                color="C0",
                capsize=6,
                label="median, 95 % band",
                zorder=2,
            )
        ax.axhline(1.0, color="0.7", lw=0.8)
        ax.set_xticks(x, [textwrap.fill(o.words, 18) for o in self.spec.outputs], fontsize="small")
        ax.set_xlim(-0.6, k - 0.4)
        ax.set_ylabel("relative to the tested model")
        ax.set_title(f"prediction of the {self.spec.analysis} analysis", fontsize="small")
        legend(ax, fontsize="small")
        ax.figure.tight_layout()
        return ax


def predict(spec: PredictSpec, tested: Any, update: Any = None) -> Prediction:
    """Run the ``[predict]`` analysis on the tested and the updated model, and carry the updated
    values' uncertainty through it.

    The band is :meth:`mechdyn.measurement.ModelUpdate.predict` with :meth:`PredictSpec.values` as
    the analysis: the identifiable values sampled from their lognormal posterior (with its
    correlation) and each sample's outputs computed; the quantiles' confidence intervals are the
    order-statistic intervals of :func:`mechdyn.uncertainty.propagate` (David & Nagaraja, *Order
    Statistics*, 3rd ed., 2003, §7.1). Without an identifiable value there is no band: the
    prediction is the model's value, and its note says so.

    Parameters
    ----------
    spec : PredictSpec
        The file's ``[predict]`` table as checked.
    tested : LoadedModel
        The tested model.
    update : ModelUpdate, optional
        The updating (None: nothing was updated).

    Returns
    -------
    Prediction

    Raises
    ------
    ModelFileError
        For an output that names no number in the analysis' summary.
    """
    prior = np.asarray(spec.values(tested), dtype=float)
    if update is None:
        note = "nothing was updated, so the prediction is the tested model's value and no band is claimed"
        return Prediction(spec, prior, prior.copy(), None, note)
    updated = np.asarray(spec.values(update.load()), dtype=float)
    if not np.any(update.identifiable):
        note = (
            "no updated value is identifiable from the measured modes, so the prediction is the model's "
            "value and no band is claimed"
        )
        return Prediction(spec, prior, updated, None, note)
    band = update.predict(spec.values, spec.keys, spec.samples, method=spec.method, seed=spec.seed)
    note = ""
    if spec.samples < FEW_SAMPLES:
        note = (
            f"with {spec.samples} samples (fewer than {FEW_SAMPLES}) the confidence intervals of the band's "
            "ends are wide: give more samples ([predict] → samples, or --samples) for a firmer band"
        )
    return Prediction(spec, prior, updated, band, note)
