"""Estimates with their confidence intervals, and the statements of their validity.

Monte Carlo (independent samples):

- mean: Student t interval ``ȳ ± t s/√n`` (central limit theorem);
- standard deviation: asymptotic interval of ``s`` from the sample kurtosis, distribution-free
  (``Var s² ≈ (m₄ − s⁴ (n − 3)/(n − 1))/n``, then the delta method);
- quantiles: distribution-free order-statistic interval ``[y₍ₗ₎, y₍ᵤ₎]`` with ``l``, ``u`` from the
  binomial distribution of the number of samples below the quantile (e.g. Hahn & Meeker,
  *Statistical Intervals*, 1991, §5.2);
- probabilities: Clopper–Pearson (exact, conservative) or Wilson score interval
  (:meth:`scipy.stats.binomtest.proportion_ci`); with no failure observed the estimate is an upper
  bound, ``1 − (1 − level)^(1/n)`` (≈ 3/n at 95 %: the rule of three).

Randomized quasi-Monte Carlo (R independent scramblings): the mean's, the standard deviation's and
the probabilities' intervals are ``pooled ± t_{R−1} s_R/√R`` from the spread of the R replicate
estimates (Owen, *Practical Quasi-Monte Carlo Integration*, 2023, ch. 17); the quantiles keep the
order-statistic interval of the pooled points (conservative: the replicate spread misses the bias of
each replicate's order statistic).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np

__all__ = ["Interval", "Probability"]

LEVEL = 0.95
"""The default confidence level of every interval (fraction)."""


@dataclass(frozen=True)
class Interval:
    """An estimate and its confidence interval.

    Attributes
    ----------
    value : float
        The estimate, in the unit of the quantity estimated.
    low, high : float
        The bounds of the interval, in the unit of the value (±inf where the samples cannot bound
        it).
    level : float
        The confidence level, fraction (0.95).
    method : str
        How the interval is made.
    """

    value: float
    low: float
    high: float
    level: float
    method: str

    @property
    def width(self) -> float:
        """``high − low``, in the unit of the quantity."""
        return self.high - self.low

    def contains(self, x: float) -> bool:
        """Whether ``x`` lies in the interval.

        Parameters
        ----------
        x : float
            A value in the unit of the quantity.
        """
        return self.low <= x <= self.high

    def as_dict(self) -> dict[str, Any]:
        """The fields as a JSON-ready dict."""
        return asdict(self)


@dataclass(frozen=True)
class Probability:
    """The probability of an event (an output beyond its limit), how it was found, and how far to
    trust it.

    Attributes
    ----------
    event : str
        The event in words, e.g. ``"transmissibility > 3"``.
    value : float
        The estimate, fraction (0 with an upper bound in ``high`` when no failure was observed).
    low, high : float
        The confidence interval, fraction.
    level : float
        Its confidence level, fraction.
    method : str
        The estimator: ``"Monte Carlo"``, ``"randomized quasi-Monte Carlo"``, ``"subset simulation"``,
        ``"FORM"``, ``"SORM (Breitung)"``, ``"importance sampling"``.
    interval_method : str
        How the interval is made (Clopper–Pearson, replicate spread, ±z·CoV, or "none" for FORM).
    evaluations : int
        Model evaluations spent (count).
    failures : int or None
        Samples beyond the limit (count), where the estimator counts them.
    cov : float or None
        Coefficient of variation of the estimator (its standard error over the estimate), ratio;
        None where it has none (FORM, or no failure observed).
    warnings : tuple of str
        What limits the estimate's validity.
    """

    event: str
    value: float
    low: float
    high: float
    level: float
    method: str
    interval_method: str
    evaluations: int
    failures: int | None = None
    cov: float | None = None
    warnings: tuple[str, ...] = ()

    @property
    def upper_bound_only(self) -> bool:
        """Whether no failure was observed, so that only ``high`` says anything."""
        return self.failures == 0

    def contains(self, p: float) -> bool:
        """Whether the probability ``p`` lies in the interval (with a relative slack of 1e-12).

        Parameters
        ----------
        p : float
            A probability, fraction.
        """
        slack = 1e-12 * max(abs(p), 1e-300)
        return self.low - slack <= p <= self.high + slack

    def as_dict(self) -> dict[str, Any]:
        """The fields as a JSON-ready dict."""
        out = asdict(self)
        out["warnings"] = list(self.warnings)
        return out


_SMALL_PROBABILITY_METHODS = ("subset simulation", "importance sampling at the FORM design point")


def _z(level: float) -> float:
    from scipy.stats import norm

    return float(norm.isf((1.0 - level) / 2.0))


def _t(level: float, dof: int) -> float:
    from scipy.stats import t

    return float(t.isf((1.0 - level) / 2.0, dof))


def validity(p: Probability) -> Probability:
    """``p`` with the warnings its numbers call for: no failure observed, or an interval wider than
    the probability itself."""
    from dataclasses import replace

    notes = list(p.warnings)
    if p.failures == 0:
        notes.append(
            f"no sample of {p.evaluations} exceeded the limit: the probability is below {p.high:.3g} "
            f"({p.level:.0%} upper bound); take more samples or a small-probability method (subset, FORM)"
        )
    elif p.interval_method != "none" and p.high - p.low > p.value:
        notes.append(
            f"the {p.level:.0%} interval [{p.low:.3g}, {p.high:.3g}] is wider than the probability "
            f"{p.value:.3g} itself: take more samples"
            + ("" if p.method in _SMALL_PROBABILITY_METHODS else " or a small-probability method")
        )
    return replace(p, warnings=tuple(dict.fromkeys(notes)))


def binomial_probability(
    failures: int, n: int, event: str, *, level: float = LEVEL, interval: str = "clopper-pearson"
) -> Probability:
    """The Monte Carlo probability ``k/n`` with its binomial confidence interval.

    Parameters
    ----------
    failures : int
        Samples beyond the limit k (count).
    n : int
        Samples (count).
    event : str
        The event in words.
    level : float
        Confidence level, fraction.
    interval : str
        ``"clopper-pearson"`` (exact) or ``"wilson"``.
    """
    from scipy.stats import binomtest

    label = {"clopper-pearson": "Clopper-Pearson", "wilson": "Wilson score"}[interval]
    if failures == 0:
        high = 1.0 - (1.0 - level) ** (1.0 / n)  # one-sided: the rule of three, 3/n at 95 %
        return validity(
            Probability(
                event,
                0.0,
                0.0,
                high,
                level,
                "Monte Carlo",
                "one-sided upper bound (rule of three)",
                n,
                0,
                None,
            )
        )
    ci = binomtest(failures, n).proportion_ci(
        confidence_level=level, method="exact" if interval != "wilson" else "wilson"
    )
    p = failures / n
    cov = math.sqrt((1.0 - p) / (n * p)) if p < 1 else 0.0
    return validity(
        Probability(event, p, float(ci.low), float(ci.high), level, "Monte Carlo", label, n, failures, cov)
    )


def replicate_probability(
    per_replicate: np.ndarray, n: int, event: str, *, level: float = LEVEL
) -> Probability:
    """The randomized-QMC probability: the mean of the replicates' fractions, its interval from their
    spread (Student t with R − 1 degrees of freedom).

    Parameters
    ----------
    per_replicate : ndarray
        The fraction of each replicate's points beyond the limit, fraction (R values).
    n : int
        Points in all (count).
    event : str
        The event in words.
    level : float
        Confidence level, fraction.
    """
    r = len(per_replicate)
    p = float(np.mean(per_replicate))
    failures = round(p * n)
    method = "randomized quasi-Monte Carlo"
    if failures == 0:
        high = 1.0 - (1.0 - level) ** (1.0 / n)
        return validity(
            Probability(
                event, 0.0, 0.0, high, level, method, "one-sided upper bound (rule of three)", n, 0, None
            )
        )
    se = float(np.std(per_replicate, ddof=1)) / math.sqrt(r)
    if se == 0.0 and p < 1.0:
        # every replicate gives the same fraction (few points each: the fraction is resolved to
        # R/n): their spread says nothing of the error, so the interval is the pooled points'
        # Clopper-Pearson one, conservative for randomized QMC, never a point
        pooled = binomial_probability(failures, n, event, level=level)
        return replace(
            pooled,
            value=p,
            method=method,
            interval_method=f"Clopper-Pearson of the pooled points (the {r} replicates agree exactly)",
        )
    half = _t(level, r - 1) * se
    return validity(
        Probability(
            event,
            p,
            max(p - half, 0.0),
            min(p + half, 1.0),
            level,
            method,
            f"replicate spread (Student t, {r} replicates)",
            n,
            failures,
            se / p,
        )
    )


def mean_interval(y: np.ndarray, *, level: float = LEVEL) -> Interval:
    """The sample mean with its Student t interval.

    Parameters
    ----------
    y : ndarray
        Independent samples, in the quantity's unit.
    level : float
        Confidence level, fraction.
    """
    n = len(y)
    m = float(np.mean(y))
    half = _t(level, n - 1) * float(np.std(y, ddof=1)) / math.sqrt(n)
    return Interval(m, m - half, m + half, level, "Student t (central limit theorem)")


def std_interval(y: np.ndarray, *, level: float = LEVEL) -> Interval:
    """The sample standard deviation with its asymptotic, distribution-free interval (from the
    sample kurtosis; the delta method for ``s`` from ``s²``).

    Parameters
    ----------
    y : ndarray
        Independent samples, in the quantity's unit.
    level : float
        Confidence level, fraction.
    """
    n = len(y)
    s2 = float(np.var(y, ddof=1))
    s = math.sqrt(s2)
    m4 = float(np.mean((y - np.mean(y)) ** 4))
    var_s2 = max(m4 - s2 * s2 * (n - 3) / (n - 1), 0.0) / n
    half = _z(level) * (math.sqrt(var_s2) / (2.0 * s) if s > 0 else 0.0)
    return Interval(s, max(s - half, 0.0), s + half, level, "asymptotic from the sample kurtosis")


def quantile_interval(sorted_y: np.ndarray, q: float, *, level: float = LEVEL) -> Interval:
    """A quantile with its distribution-free order-statistic interval.

    Parameters
    ----------
    sorted_y : ndarray
        Independent samples, sorted ascending, in the quantity's unit.
    q : float
        The quantile's probability, fraction in (0, 1).
    level : float
        Confidence level, fraction (coverage at least this).
    """
    from scipy.stats import binom

    n = len(sorted_y)
    a = (1.0 - level) / 2.0
    lo_rank = int(binom.ppf(a, n, q))  # 1-based rank of the lower bound
    hi_rank = int(binom.ppf(1.0 - a, n, q)) + 1
    low = float(sorted_y[lo_rank - 1]) if lo_rank >= 1 else -math.inf
    high = float(sorted_y[hi_rank - 1]) if hi_rank <= n else math.inf
    value = float(np.quantile(sorted_y, q))
    return Interval(value, low, high, level, "order statistics (distribution-free)")


def replicate_interval(
    pooled: float, per_replicate: np.ndarray, *, level: float = LEVEL, low: float = -math.inf
) -> Interval:
    """An RQMC estimate with the interval from its replicates' spread (Student t, R − 1 degrees of
    freedom), its lower end at least ``low`` (0 for a standard deviation: few replicates give a wide
    interval).

    Parameters
    ----------
    pooled : float
        The estimate from all points, in the quantity's unit.
    per_replicate : ndarray
        The same estimate from each replicate, in the quantity's unit.
    level : float
        Confidence level, fraction.
    low : float
        The least value the quantity can take, in its unit.
    """
    r = len(per_replicate)
    half = _t(level, r - 1) * float(np.std(per_replicate, ddof=1)) / math.sqrt(r)
    return Interval(
        pooled, max(pooled - half, low), pooled + half, level, f"replicate spread (Student t, {r} replicates)"
    )
