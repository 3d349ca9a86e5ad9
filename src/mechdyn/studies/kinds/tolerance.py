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

The model file's own ``[[scatter]]`` (and ``[[correlations]]``, :mod:`mechdyn.io.scatter`) is the
default: each of its rows whose values the study's ``[[parameters]]`` do not name is a parameter too,
after the study's, so that a study with no parameters samples the scatter the model file gives
(:func:`mechdyn.studies.kinds.tolerance_model.with_model_scatter`).

Parameters may be correlated (``[[correlations]]``: two parameters and a coefficient, the Gaussian
copula's own or Spearman's rank correlation), checked as a whole: each name a parameter, each pair
once, each coefficient in (−1, 1), the matrix positive definite.

A limit the samples exceed rarely (an estimated probability below :data:`RARE_PROBABILITY`, or not
at all) gets its probability by :func:`mechdyn.uncertainty.small_probability` as well (importance
sampling at the FORM design point by default, subset simulation where a parameter takes discrete
levels; ``[study] small_probability`` chooses). Its evaluations go through the batch engine and are
stored as the study's variants, after the design's; OpenTURNS, seeded with the study's seed, asks
for the same points again when the findings are stated from the database, so that they are answered
from the stored variants and the findings stay a function of them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.errors import StudyError
from mechdyn.studies.kinds.base import Found, Kind, Ran, register, value
from mechdyn.studies.storage import StoredVariant, variant_key

if TYPE_CHECKING:
    from mechdyn.studies.plan import Study, StudyFindings
    from mechdyn.uncertainty import InputSpace

__all__ = [
    "GIVEN_DATA_EVENTS",
    "GIVEN_DATA_SAMPLES",
    "RARE_PROBABILITY",
    "Tolerance",
    "correlation_matrix",
    "first_order_given_data",
    "space",
]

DEFAULT_SAMPLES = 1024
"""Samples of a tolerance study whose file gives none (a power of 2)."""

QUANTILES = (0.05, 0.5, 0.95)
"""The quantiles each output's distribution reports (probabilities, fraction)."""

GIVEN_DATA_SAMPLES = 256
"""Samples from which the ranking is the given-data first-order Sobol index (count); below, rank
correlation."""

GIVEN_DATA_EVENTS = 10
"""Samples needed on either side of a limit for its indicator's Sobol index (count)."""

RARE_PROBABILITY = 1e-3
"""Below this estimated probability (or with no sample beyond the limit) a limit's probability is also
found by :func:`mechdyn.uncertainty.small_probability` (fraction)."""

RARE_SAMPLES = (100, 1000)
"""Importance samples (or points per level of subset simulation) for a rare limit: the study's
samples, within these bounds (count)."""


def correlation_matrix(study: Study) -> np.ndarray | None:
    """The copula's correlation matrix (normal space) of the study's ``[[correlations]]``, in the
    parameters' order; None for independent parameters.

    Each row names two parameters (their names, the path where a row gives none) and a coefficient
    in (−1, 1), the Gaussian copula's own (``measure = "normal"``) or Spearman's rank correlation
    (``"spearman"``), converted exactly: ``R = 2 sin(π ρ_S / 6)`` (Kruskal, *JASA* 53, 1958).

    Parameters
    ----------
    study : Study
        A tolerance study.

    Raises
    ------
    StudyError
        Naming the file, the row, the field and the value: a name that is no parameter, a parameter
        paired with itself, a pair given twice, a coefficient outside (−1, 1), or coefficients that
        contradict each other (the matrix not positive definite).
    """
    import difflib

    rows = tuple(getattr(study, "correlations", ()) or ())
    if not rows:
        return None
    where = f"{study.path or study.name}: [[correlations]]"
    names = [p.name for p in study.parameters]
    R = np.eye(len(names))
    given: dict[frozenset[str], int] = {}
    for i, (a, b, rho, measure) in enumerate(rows):
        here = f"{where} #{i + 1}"
        for name in (a, b):
            if name not in names:
                near = difflib.get_close_matches(name, names, n=1)
                raise StudyError(
                    f"{here} → between: {name!r} is not a parameter of the study"
                    + (f" (did you mean {near[0]!r}?)" if near else "")
                    + f"; give two of {', '.join(map(repr, names))}"
                )
        if a == b:
            raise StudyError(f"{here} → between: {a!r} is paired with itself; give two different parameters")
        pair = frozenset((a, b))
        if pair in given:
            raise StudyError(
                f"{here} → between: the pair {a!r}, {b!r} is given already in #{given[pair]}; give each "
                "pair once (the correlation is symmetric)"
            )
        given[pair] = i + 1
        if not (isinstance(rho, (int, float)) and math.isfinite(rho) and abs(rho) < 1.0):
            raise StudyError(
                f"{here} → coefficient: {rho!r} is not a correlation coefficient; give a number between "
                "-1 and 1 (exclusive), e.g. 0.5"
            )
        if measure not in ("normal", "spearman"):
            raise StudyError(f"{here} → measure: {measure!r}; give 'normal' or 'spearman'")
        r = 2.0 * math.sin(math.pi * rho / 6.0) if measure == "spearman" else float(rho)
        i_a, i_b = names.index(a), names.index(b)
        R[i_a, i_b] = R[i_b, i_a] = r
    least = float(np.linalg.eigvalsh(R).min())
    if least <= 1e-10:
        pairs = ", ".join(f"{a} – {b}: {rho:g}" for a, b, rho, _ in rows)
        raise StudyError(
            f"{where}: the coefficients ({pairs}) contradict each other: the correlation matrix is not "
            f"positive definite (its smallest eigenvalue is {least:.3g}); weaken one of them"
        )
    return R


def space(study: Study) -> InputSpace:
    """The study's parameters' scatter as an :class:`~mechdyn.uncertainty.InputSpace`, SI, in the
    study's parameter order, tied by the ``[[correlations]]`` (:func:`correlation_matrix`).

    Parameters
    ----------
    study : Study
        A tolerance study (every parameter with its ``scatter``).
    """
    from mechdyn.uncertainty import InputSpace

    return InputSpace(tuple(p.scatter for p in study.parameters), correlation_matrix(study))


def _sampling(study: Study) -> tuple[int, int]:
    """Samples and replicates (1 for Monte Carlo)."""
    n = int(study.samples or DEFAULT_SAMPLES)
    return n, (1 if study.method == "mc" else min(16, n // 2))


def first_order_given_data(x: np.ndarray, y: np.ndarray) -> float:
    """The first-order Sobol index of ``y`` on ``x`` from the samples themselves: see
    :func:`mechdyn.uncertainty.sensitivity.first_order_given_data` (Plischke, Borgonovo & Smith 2013).

    Parameters
    ----------
    x : ndarray
        The input's samples (n), any unit.
    y : ndarray
        The output's (or a limit's indicator's) samples (n), any unit.

    Returns
    -------
    float
        The index, fraction.
    """
    from mechdyn.uncertainty.sensitivity import first_order_given_data as given_data

    return given_data(x, y)


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
        if getattr(study, "correlations", ()):
            method += "; with correlated parameters an index includes what they share"
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


def _correlations(study: Study) -> list[dict[str, Any]]:
    """The study's correlated pairs as findings hold them."""
    rows = tuple(getattr(study, "correlations", ()) or ())
    if not rows:
        return []
    R, names = correlation_matrix(study), [p.name for p in study.parameters]
    assert R is not None
    return [
        {
            "between": [a, b],
            "coefficient": float(rho),
            "measure": measure,
            "normal": float(R[names.index(a), names.index(b)]),
        }
        for a, b, rho, measure in rows
    ]


def rare_method(study: Study) -> str:
    """The method for a rarely exceeded limit: the study's ``small_probability``, by default
    ``importance`` (FORM, then importance sampling) or ``subset`` where a parameter takes discrete
    levels (FORM needs continuous inputs); ``off`` for none.

    Parameters
    ----------
    study : Study
        A tolerance study.
    """
    chosen = getattr(study, "small_probability", None)
    if chosen:
        return str(chosen)
    return "importance" if all(p.scatter.continuous for p in study.parameters) else "subset"


def _rare_samples(study: Study) -> int:
    """Importance samples or points per level for a rare limit (count, :data:`RARE_SAMPLES`)."""
    low, high = RARE_SAMPLES
    return int(min(high, max(low, _sampling(study)[0])))


def _rare(Y: np.ndarray, limit: Any) -> bool:
    """Whether the samples exceed the limit rarely enough for a small-probability method."""
    hits = int(np.count_nonzero(limit.exceeded(Y)))
    return hits == 0 or hits / len(Y) < RARE_PROBABILITY


def _small(
    study: Study, key: str, limit: Any, evaluate: Callable[[np.ndarray], list[StoredVariant]]
) -> dict[str, Any]:
    """One rare limit's probability by :func:`mechdyn.uncertainty.small_probability`, the model
    answered by ``evaluate`` (the runner, or the stored variants): the probability's fields
    (:meth:`~mechdyn.uncertainty.Probability.as_dict`) with ``reliability_index``, ``design_point``
    and ``importance`` (FORM's), or ``method`` and ``error``."""
    from mechdyn.errors import ModelError
    from mechdyn.uncertainty import small_probability

    method = rare_method(study)
    raised: list[BaseException] = []

    def f(X: np.ndarray) -> np.ndarray:
        try:
            return np.array([[value(v, key)] for v in evaluate(np.atleast_2d(X))])
        except Exception as exc:  # OpenTURNS wraps what its model raises: keep the cause
            raised.append(exc)
            raise

    try:
        r = small_probability(
            f,
            space(study),
            limit,
            outputs=[key],
            method=method,
            samples=_rare_samples(study),
            seed=study.seed,
        )
    except (ModelError, RuntimeError) as exc:
        cause = raised[-1] if raised else exc
        if raised and not isinstance(cause, (ModelError, StudyError)):
            raise cause from None  # not the method's failure (the database, a bug): stop the run
        text = str(cause).splitlines()[0].removeprefix("InternalException : ")
        return {"method": method, "error": text}
    return {
        **r.probability.as_dict(),
        "reliability_index": r.reliability_index,
        "design_point": r.design_point,
        "importance": r.importance,
    }


def _stored_lookup(variants: list[StoredVariant]) -> Callable[[np.ndarray], list[StoredVariant]]:
    """The stored variants of the rows of X (SI), found by their keys; a row not stored is refused."""
    by_key = {v.key: v for v in variants}

    def lookup(X: np.ndarray) -> list[StoredVariant]:
        out = []
        for row in np.atleast_2d(X):
            v = by_key.get(variant_key(row))
            if v is None:
                raise StudyError(
                    "a point the small-probability method asks for is not stored (is the study still "
                    "running?); run the study to evaluate it"
                )
            out.append(v)
        return out

    return lookup


@register
class Tolerance(Kind):
    """Tolerances to probabilities: each parameter's ``scatter`` sampled (Monte Carlo or randomized
    quasi-Monte Carlo), each output's mean, standard deviation and quantiles with 95 % intervals, each
    limit's exceedance probability with its interval, and the tolerances ranked by their share
    (:mod:`mechdyn.uncertainty`: SciPy's distributions and Sobol sequences); parameters tied by
    ``[[correlations]]`` (a Gaussian copula), and a rarely exceeded limit's probability by a
    small-probability method as well (OpenTURNS)."""

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
        correlation_matrix(study)
        chosen = getattr(study, "small_probability", None)
        discrete = [p.name for p in study.parameters if not p.scatter.continuous]
        if chosen in ("importance", "form", "sorm") and discrete:
            raise StudyError(
                f"{where}: [study] small_probability = {chosen!r} needs continuous scatter ({discrete} "
                'take discrete levels); give small_probability = "subset"'
            )

    def design(self, study: Study) -> np.ndarray:
        """The samples (n × P, SI), drawn as :func:`mechdyn.uncertainty.propagate` draws them with the
        study's seed."""
        s = space(study)
        n, r = _sampling(study)
        rng = np.random.default_rng(study.seed)
        if r == 1:
            return s.sample(n, method="mc", seed=rng)
        return np.concatenate([s.sample(n // r, method="qmc", seed=rng) for _ in range(r)])

    def run(self, runner: Any) -> Ran:
        """Evaluate the design, then, for each rarely exceeded limit, the points its small-probability
        method asks for (stored after the design's variants, in the order asked)."""
        study = runner.study
        n = _sampling(study)[0]
        variants = runner.evaluate(self.design(study))
        extra: dict[str, StoredVariant] = {}

        def evaluate(X: np.ndarray) -> list[StoredVariant]:
            got = runner.evaluate(X)
            for v in got:
                extra.setdefault(v.key, v)
            return got

        if rare_method(study) != "off":
            for w in study.watched:
                Y = np.array([value(v, w.key) for v in variants[:n]])
                if not np.isfinite(Y).all():
                    continue
                for lim in study.limits:
                    if lim.output == w.key and _rare(Y, lim):
                        _small(study, w.key, lim, evaluate)  # the findings state it from the stored points
        design = {v.key for v in variants}
        return Ran(variants + [v for k, v in extra.items() if k not in design])

    def order(self, study: Study, variants: Any) -> list[StoredVariant]:
        """The design's variants in design order, then those a small-probability method asked for,
        in the order stored."""
        first = super().order(study, variants)
        seen = {v.key for v in first}
        return first + sorted((v for v in variants if v.key not in seen), key=lambda v: v.id)

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """``samples``, ``method`` (in words), ``replicates``, ``correlations`` (each pair's
        ``between``, ``coefficient`` and ``measure`` as given and ``normal``, the copula's), and per
        output (``outputs``) its
        ``distribution`` (mean, std and quantiles with their intervals, SI: ``mean``, ``mean_low``,
        ``mean_high``, ``q5``, ...) and ``ranking`` (``method``, ``measures`` per parameter,
        ``ranked``), or ``{"error": ...}``; per limit (``limits``) ``output``, ``value`` (SI), ``side``,
        ``probability`` (:meth:`mechdyn.uncertainty.Probability.as_dict`), ``ranking`` and, for a rarely
        exceeded limit, ``small_probability`` (the same fields by the small-probability method, with
        ``reliability_index``, ``design_point`` and ``importance``, or ``error``). The variants after
        the design's are those the small-probability methods asked for."""
        from mechdyn.uncertainty import propagate

        n, r = _sampling(study)
        lookup = _stored_lookup(variants)
        variants = variants[:n]
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
                found = {
                    "output": w.key,
                    "value": lim.value,
                    "side": lim.side,
                    "probability": prob.as_dict(),
                    "ranking": _ranking(study, X, hit.astype(float), int(hit.sum())),
                }
                if rare_method(study) != "off" and _rare(Y, lim):
                    found["small_probability"] = _small(study, w.key, lim, lookup)
                limits.append(found)
        method = (
            "Monte Carlo" if r == 1 else f"randomized quasi-Monte Carlo (scrambled Sobol, {r} replicates)"
        )
        return Found(
            {
                "samples": n,
                "method": method,
                "replicates": r,
                "scatter": {p.name: _scatter(p.scatter) for p in study.parameters},
                "correlations": _correlations(study),
                "outputs": outputs,
                "limits": limits,
            }
        )

    # -- showing (mechdyn.studies.kinds.tolerance_show) ---------------------------------------
    def tables(self, result: StudyFindings) -> list[Table]:
        """The scatter and its correlations; each output's distribution (95 % intervals) in its unit;
        each limit's probability with its interval, and a rare limit's by its small-probability
        method; each ranking, largest share first, with its method."""
        from mechdyn.studies.kinds.tolerance_show import tables

        return tables(result)

    def plots(self, result: StudyFindings) -> dict[str, Callable[[], Any]]:
        """Per output: its histogram and its empirical CDF, each limit drawn."""
        from mechdyn.studies.kinds.tolerance_show import plots

        return plots(result)

    def views(self, result: StudyFindings) -> dict[str, Any]:
        """What a report and the dashboard lead with: each limit's probability in words, the sample
        size and how far to trust it, each output's histogram and CDF and each limit's ranking as a
        bar chart (:func:`mechdyn.studies.kinds.tolerance_show.views`)."""
        from mechdyn.studies.kinds.tolerance_show import views

        return views(result)
