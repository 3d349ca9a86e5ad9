"""Tolerances to probabilities (``tolerance``): each parameter scatters as its ``scatter`` table says,
and the study reports each output's distribution, each limit's exceedance probability, and which
tolerance matters most.

The design is the samples of the parameters' :class:`~mechdyn.uncertainty.InputSpace` (independent
inputs), drawn as :func:`mechdyn.uncertainty.propagate` draws them with the study's seed: Monte
Carlo (``method = "mc"``) or randomized quasi-Monte Carlo (``"qmc"``: scrambled Sobol points in
``min(16, samples / 2)`` independent replicates, ``samples`` a power of 2). The variants run through
the batch engine and are stored like every study's, so a study resumes; the findings hand the
stored outputs to :func:`~mechdyn.uncertainty.propagate` on the same points, so that they are what
the uncertainty core gives directly (its intervals: Student t, order statistics and Clopper–Pearson
for Monte Carlo; the replicates' spread for quasi-Monte Carlo).

The ranking shares out each output's variance and each limit's probability among the tolerances:
with at least :data:`GIVEN_DATA_SAMPLES` samples (and, for a limit, at least
:data:`GIVEN_DATA_EVENTS` samples on either side of it) the first-order Sobol index estimated from
the samples themselves (Plischke, Borgonovo & Smith, *Eur. J. Oper. Res.* 226, 2013: the variance of
the conditional means over √n classes of equal count, corrected for the bias of the classes' own
scatter); with fewer, Spearman's rank correlation (its square as the share). Each ranking says
which it is.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.cells import given, number, table, unit_text
from mechdyn.studies.errors import StudyError
from mechdyn.studies.kinds.base import Found, Kind, register, safe, value
from mechdyn.studies.storage import StoredVariant

if TYPE_CHECKING:
    from mechdyn.studies.outputs import Watched
    from mechdyn.studies.result import StudyResult
    from mechdyn.studies.study import Study
    from mechdyn.uncertainty import InputSpace

__all__ = ["GIVEN_DATA_EVENTS", "GIVEN_DATA_SAMPLES", "Tolerance", "first_order_given_data", "space"]

DEFAULT_SAMPLES = 1024
"""Samples of a tolerance study whose file gives none (a power of 2)."""

QUANTILES = (0.05, 0.5, 0.95)
"""The quantiles each output's distribution reports (probabilities, fraction)."""

GIVEN_DATA_SAMPLES = 256
"""Samples from which the ranking is the given-data first-order Sobol index (count); below, rank
correlation."""

GIVEN_DATA_EVENTS = 10
"""Samples needed on either side of a limit for its indicator's Sobol index (count)."""


def space(study: Study) -> InputSpace:
    """The study's parameters' scatter as an :class:`~mechdyn.uncertainty.InputSpace` (independent),
    SI, in the study's parameter order.

    Parameters
    ----------
    study : Study
        A tolerance study (every parameter with its ``scatter``).
    """
    from mechdyn.uncertainty import InputSpace

    return InputSpace(tuple(p.scatter for p in study.parameters))


def _sampling(study: Study) -> tuple[int, int]:
    """Samples and replicates (1 for Monte Carlo)."""
    n = int(study.samples or DEFAULT_SAMPLES)
    return n, (1 if study.method == "mc" else min(16, n // 2))


def first_order_given_data(x: np.ndarray, y: np.ndarray) -> float:
    """The first-order Sobol index of ``y`` on ``x`` from one sample (no design of its own).

    The samples are sorted by x into M = ⌊√n⌋ classes of equal count; the index is the variance of
    the class means over the variance of y (Plischke, Borgonovo & Smith, *Eur. J. Oper. Res.* 226,
    2013), corrected for the scatter of the class means themselves: a ratio r has expectation
    S + (1 − S)·b with b = (M − 1)/(n − 1), so S = (r − b)/(1 − b), at least 0.

    Parameters
    ----------
    x : ndarray
        The input's samples (n), any unit.
    y : ndarray
        The output's (or a limit's indicator's) samples (n), any unit.

    Returns
    -------
    float
        The index, fraction (0 for a constant y).
    """
    n = len(y)
    total = float(np.var(y))
    if n < 4 or total == 0.0:
        return 0.0
    m = max(2, math.isqrt(n))
    classes = np.array_split(np.argsort(x, kind="stable"), m)
    mean = float(np.mean(y))
    between = sum(len(c) * (float(np.mean(y[c])) - mean) ** 2 for c in classes) / n
    bias = (m - 1) / (n - 1)  # E[between / total] = S + (1 - S)·bias: the classes' own scatter
    return max(0.0, (between / total - bias) / (1.0 - bias))


def _ranking(study: Study, X: np.ndarray, y: np.ndarray, events: int | None) -> dict[str, Any]:
    """Each parameter's share of y (an output, or a limit's indicator with ``events`` beyond it)."""
    from scipy.stats import spearmanr

    n = len(y)
    enough = n >= GIVEN_DATA_SAMPLES and (events is None or min(events, n - events) >= GIVEN_DATA_EVENTS)
    if np.ptp(y) == 0:
        why = "every sample is on the same side of the limit" if events is not None else "it is constant"
        return {"method": f"none: {why}", "measures": {}}
    if enough:
        measures = {p.name: first_order_given_data(X[:, j], y) for j, p in enumerate(study.parameters)}
        method = "first-order Sobol index from the samples (Plischke et al. 2013)"
    else:
        measures = {}
        for j, p in enumerate(study.parameters):
            rho = float(spearmanr(X[:, j], y).statistic) if np.ptp(X[:, j]) > 0 else 0.0
            measures[p.name] = 0.0 if not math.isfinite(rho) else rho
        method = (
            f"Spearman rank correlation (fewer than {GIVEN_DATA_SAMPLES} samples"
            + (f" or {GIVEN_DATA_EVENTS} on either side of the limit" if events is not None else "")
            + " for a Sobol index)"
        )
    ranked = sorted(measures, key=lambda k: -abs(measures[k]))
    return {"method": method, "measures": measures, "ranked": ranked}


def _stored(Y: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """The batched model that answers the stored outputs (the samples are the design's)."""
    return lambda _X: Y


def _limit_text(w: Watched, limit: float) -> str:
    """A limit (SI) as the study file gives it, in the output's display unit."""
    shown = w.readable([limit])
    x = shown.show(limit)
    return f"{given(x if x is not None else limit)} {unit_text(shown.shown_unit)}".strip()


def _scatter(v: Any) -> dict[str, Any]:
    """A parameter's :class:`~mechdyn.uncertainty.Variable` as findings hold it (SI)."""
    return {
        "distribution": v.kind,
        "unit": v.unit,
        "parameters": {k: (list(x) if isinstance(x, tuple) else x) for k, x in v.parameters.items()},
        "mean": float(v.mean),
        "std": float(v.std),
        "source": v.source,
    }


def _scatter_text(d: dict[str, Any]) -> str:
    """A scatter's distribution and its parameters as given (each number with three digits at least)."""

    def shown(x: Any) -> str:
        if isinstance(x, list):
            return "[" + ", ".join(shown(y) for y in x) + "]"
        return given(float(x)) if isinstance(x, (int, float)) else str(x)

    return f"{d['distribution']} (" + ", ".join(f"{k} {shown(x)}" for k, x in d["parameters"].items()) + ")"


@register
class Tolerance(Kind):
    """Tolerances to probabilities: each parameter's ``scatter`` sampled (Monte Carlo or randomized
    quasi-Monte Carlo), each output's mean, standard deviation and quantiles with 95 % intervals, each
    limit's exceedance probability with its interval, and the tolerances ranked by their share
    (:mod:`mechdyn.uncertainty`: SciPy's distributions and Sobol sequences)."""

    name = "tolerance"
    title = "tolerances to probabilities"

    def check(self, study: Study) -> None:
        """Every parameter has a scatter (and no range), samples suit the method, limits name outputs."""
        where = study.path or study.name
        self.refuse_discrete(study.parameters, where)
        for i, p in enumerate(study.parameters):
            if p.scatter is None:
                raise StudyError(
                    f"{where}: [[parameters]] #{i + 1} ({p.name!r}): a tolerance study needs scatter = "
                    '{distribution = "lognormal", median = "...", cov = 0.15} (or {tolerance = "shore_a_5"}) '
                    "in place of a range or levels"
                )
        n, r = _sampling(study)
        if n < 4:
            raise StudyError(f"{where}: [study] samples = {n}: a tolerance study needs at least 4 samples")
        if r > 1 and n & (n - 1):
            raise StudyError(
                f'{where}: [study] samples = {n}: method = "qmc" needs a power of 2 (e.g. '
                f'{1 << (n.bit_length() - 1)} or {1 << n.bit_length()}), or method = "mc"'
            )
        if not study.watched:
            raise StudyError(f'{where}: give at least one [[outputs]] row (output = "...", limit = "...")')

    def design(self, study: Study) -> np.ndarray:
        """The samples (n × P, SI), drawn as :func:`mechdyn.uncertainty.propagate` draws them with the
        study's seed."""
        s = space(study)
        n, r = _sampling(study)
        rng = np.random.default_rng(study.seed)
        if r == 1:
            return s.sample(n, method="mc", seed=rng)
        return np.concatenate([s.sample(n // r, method="qmc", seed=rng) for _ in range(r)])

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """``samples``, ``method`` (in words), ``replicates``, and per output (``outputs``) its
        ``distribution`` (mean, std and quantiles with their intervals, SI: ``mean``, ``mean_low``,
        ``mean_high``, ``q5``, ...) and ``ranking`` (``method``, ``measures`` per parameter,
        ``ranked``), or ``{"error": ...}``; per limit (``limits``) ``output``, ``value`` (SI), ``side``,
        ``probability`` (:meth:`mechdyn.uncertainty.Probability.as_dict`) and ``ranking``."""
        from mechdyn.uncertainty import propagate

        n, r = _sampling(study)
        X = np.array([[v.parameters[p.name] for p in study.parameters] for v in variants], dtype=float)
        failed = sum(1 for v in variants if v.status != "ok")
        outputs: dict[str, Any] = {}
        limits: list[dict[str, Any]] = []
        for w in study.watched:
            Y = np.array([value(v, w.key) for v in variants])
            mine = [lim for lim in study.limits if lim.output == w.key]
            if not np.isfinite(Y).all():
                error = (
                    f"{int((~np.isfinite(Y)).sum())} of {Y.size} variants have no value (failed: {failed}); "
                    "truncate the scatter (lower/upper) to where the model can be evaluated"
                )
                outputs[w.key] = {"error": error}
                limits += [
                    {"output": w.key, "value": lim.value, "side": lim.side, "error": error} for lim in mine
                ]
                continue
            got = propagate(
                _stored(Y),
                space(study),
                n,
                outputs=[w.key],
                limits=mine,
                method=study.method,
                replicates=max(r, 2),
                quantiles=QUANTILES,
                seed=study.seed,
            )
            outputs[w.key] = {
                "distribution": got.distributions[0].as_dict(),
                "ranking": _ranking(study, X, Y, None),
            }
            for lim, prob in zip(mine, got.probabilities, strict=True):
                hit = lim.exceeded(Y)
                limits.append(
                    {
                        "output": w.key,
                        "value": lim.value,
                        "side": lim.side,
                        "probability": prob.as_dict(),
                        "ranking": _ranking(study, X, hit.astype(float), int(hit.sum())),
                    }
                )
        method = (
            "Monte Carlo" if r == 1 else f"randomized quasi-Monte Carlo (scrambled Sobol, {r} replicates)"
        )
        return Found(
            {
                "samples": n,
                "method": method,
                "replicates": r,
                "scatter": {p.name: _scatter(p.scatter) for p in study.parameters},
                "outputs": outputs,
                "limits": limits,
            }
        )

    # -- showing ------------------------------------------------------------------------------
    def tables(self, result: StudyResult) -> list[Table]:
        """The scatter; each output's distribution (95 % intervals) in its unit; each limit's
        probability with its interval; each ranking, largest share first, with its method."""
        st, f = result.study, result.findings
        watched = {w.key: w for w in st.watched}
        out = [
            table(
                f"{st.name}: scatter of the parameters ({f['samples']} samples, {f['method']})",
                ["parameter", "unit", "scatter", "mean", "standard deviation"],
                [
                    [name, unit_text(d["unit"]), _scatter_text(d), d["mean"], d["std"]]
                    for name, d in f["scatter"].items()
                ],
            )
        ]
        rows: list[list[Any]] = []
        for key, d in f["outputs"].items():
            w = watched[key]
            if "error" in d:
                rows.append([w.words, "no value", None, None, d["error"]])
                continue
            dist = d["distribution"]
            shown = w.readable([dist["mean"], dist.get("q95")])
            for stat in ("mean", "std", "q5", "q50", "q95"):
                if stat not in dist:
                    continue
                scale = shown.difference if stat == "std" else shown.show
                rows.append(
                    [
                        shown.label,
                        {
                            "mean": "mean",
                            "std": "standard deviation",
                            "q5": "5 % quantile",
                            "q50": "median",
                            "q95": "95 % quantile",
                        }[stat],
                        scale(dist[stat]),
                        scale(dist[f"{stat}_low"]),
                        scale(dist[f"{stat}_high"]),
                    ]
                )
        out.append(
            table(
                f"{st.name}: distribution of each output (95 % intervals)",
                ["output", "", "value", "low", "high"],
                rows,
            )
        )
        if f["limits"]:
            lrows: list[list[Any]] = []
            for d in f["limits"]:
                w = watched[d["output"]]
                event = f"{w.words} {'>' if d['side'] == 'above' else '<'} {_limit_text(w, d['value'])}"
                if "error" in d:
                    lrows.append([event.strip(), None, None, None, d["error"]])
                    continue
                p = d["probability"]
                lrows.append([event.strip(), p["value"], p["low"], p["high"], p["failures"]])
            out.append(
                table(
                    f"{st.name}: probability of exceeding each limit (95 % intervals)",
                    ["event", "probability", "low", "high", "samples beyond"],
                    lrows,
                )
            )
        for what, ranking in self._rankings(result):
            if not ranking.get("ranked"):
                out.append(
                    table(
                        f"{st.name}: tolerances ranked by their share of {what}",
                        ["note"],
                        [[ranking["method"]]],
                    )
                )
                continue
            m = ranking["measures"]
            out.append(
                table(
                    f"{st.name}: tolerances ranked by their share of {what}",
                    ["parameter", "measure"],
                    [[name, m[name]] for name in ranking["ranked"]],
                    note=f"measure: {ranking['method']}",
                )
            )
        return out

    def _rankings(self, result: StudyResult) -> list[tuple[str, dict[str, Any]]]:
        f, watched = result.findings, {w.key: w for w in result.study.watched}
        out = [
            (f"the scatter of {watched[k].words}", d["ranking"])
            for k, d in f["outputs"].items()
            if "ranking" in d
        ]
        for d in f["limits"]:
            if "ranking" in d:
                w = watched[d["output"]]
                side = ">" if d["side"] == "above" else "<"
                out.append((f"P({w.words} {side} {_limit_text(w, d['value'])})", d["ranking"]))
        return out

    def plots(self, result: StudyResult) -> dict[str, Callable[[], Any]]:
        """Per output: its histogram and its empirical CDF, each limit drawn."""
        out: dict[str, Callable[[], Any]] = {}
        for w in result.study.watched:
            if "error" not in result.findings["outputs"].get(w.key, {"error": 1}):
                out[f"tolerance_{safe(w.key)}.png"] = partial(distribution_plot, result, w)
        return out


def distribution_plot(result: StudyResult, w: Watched, ax: Any = None) -> Any:
    """One output's histogram over its samples with its empirical CDF (right axis), each of its limits
    drawn as a vertical line with its probability.

    Parameters
    ----------
    result : StudyResult
        A tolerance study's result.
    w : Watched
        The output.
    ax : matplotlib Axes, optional
    """
    from mechdyn.plotting import legend, new_axes

    y = np.array([value(v, w.key) for v in result.variants])
    y = y[np.isfinite(y)]
    shown = w.readable([float(np.max(np.abs(y)))] if y.size else [])
    ys = np.array([shown.show(float(v)) for v in y])
    ax = new_axes(ax, figsize=(7.0, 4.0))
    ax.hist(ys, bins=max(10, min(60, int(math.sqrt(len(ys))))), density=True, alpha=0.6, label="samples")
    ax.set_xlabel(shown.label)
    ax.set_ylabel("probability density")
    cdf = ax.twinx()
    s = np.sort(ys)
    cdf.step(s, np.arange(1, len(s) + 1) / len(s), where="post", color="k", lw=1.0, label="CDF")
    cdf.set_ylabel("cumulative probability")
    cdf.set_ylim(0.0, 1.0)
    for d in result.findings["limits"]:
        if d["output"] != w.key or "probability" not in d:
            continue
        x = shown.show(d["value"])
        p = d["probability"]
        ax.axvline(x, color="C3", ls="--", label=f"limit {number(x)}: P = {number(p['value'])}")
    ax.set_title(f"{w.words}: {result.findings['samples']} samples", fontsize=10)
    legend(ax, fontsize=8)
    return ax
