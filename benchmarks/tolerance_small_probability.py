"""Evaluations needed for a probability of 1e-4: the small-probability methods against plain Monte Carlo.

    python benchmarks/tolerance_small_probability.py            # 40 seeds per method
    python benchmarks/tolerance_small_probability.py --quick    # 8 seeds per method, within a minute
    python benchmarks/tolerance_small_probability.py --json     # one JSON object

The model: the single-DOF isolator of ``tests/test_uncertainty_isolator.py`` (1000 kg forced at
25 Hz, damping ratio 0.1, a lognormal mount stiffness of coefficient of variation 0.15), whose
probability that the transmissibility exceeds 2 is a difference of two lognormal CDFs; the median is
set so that it is exactly 1e-4.

mechdyn: :func:`mechdyn.uncertainty.small_probability` by importance sampling at the FORM design
point (1000 samples after FORM) and by subset simulation (1000 points per level), each run over
several seeds: the evaluations it spent, the coefficient of variation it states, the one measured as
the scatter of its estimates over the seeds, how often its 95 % interval held the exact value.

Baseline, in the same run: plain Monte Carlo at the same coefficient of variation. Its evaluations
are ``n = (1 − p)/(p·CoV²)`` (the binomial estimator's variance), and the benchmark measures it too:
plain Monte Carlo with that n over the same number of seeds (the model is a closed form, so a
million evaluations take a fraction of a second), its measured coefficient of variation beside the
target. The ratio is plain Monte Carlo's evaluations over the method's, at the CoV the method
measured (itself uncertain by about 1/√(2(R − 1)) over R seeds), and also at the CoV the method
states (for subset simulation an upper bound, so a lower ratio).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

import numpy as np
from scipy.stats import norm

from mechdyn.uncertainty import Limit, lognormal, small_probability

MASS = 1000.0  # kg
OMEGA = 2 * math.pi * 25.0  # rad/s
ZETA = 0.1  # damping ratio
LIMIT = 2.0  # transmissibility
COV = 0.15  # of the mount stiffness
TARGET = 1e-4  # the probability the median is set for


def transmissibility(k: np.ndarray) -> np.ndarray:
    """T(r, ζ) = √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)), r² = mω²/k (Den Hartog 1956, §2.7)."""
    r2 = OMEGA**2 * MASS / k
    a = 4 * ZETA**2 * r2
    return np.sqrt((1 + a) / ((1 - r2) ** 2 + a))


def failing_interval() -> tuple[float, float]:
    """The stiffnesses (N/m) where T > LIMIT: T² > L² ⇔ a quadratic in s = r² is negative."""
    a, L2 = 4 * ZETA**2, LIMIT**2
    s1, s2 = sorted(np.roots([L2, a * L2 - 2 * L2 - a, L2 - 1]).real)
    return MASS * OMEGA**2 / s2, MASS * OMEGA**2 / s1


def exact(median: float) -> float:
    """P(T > LIMIT) for a lognormal stiffness of this median and COV."""
    lo, hi = failing_interval()
    s = math.sqrt(math.log1p(COV**2))
    return float(norm.cdf(math.log(hi / median) / s) - norm.cdf(math.log(lo / median) / s))


def median_for(p: float) -> float:
    """The median stiffness (N/m), below the failing interval, that makes P(T > LIMIT) = p."""
    from scipy.optimize import brentq

    lo = failing_interval()[0]
    return brentq(lambda m: exact(m) - p, lo * 0.2, lo * 0.999, xtol=1e-6, rtol=1e-14)


def model(X: np.ndarray) -> np.ndarray:
    return transmissibility(X[:, 0])


def method_runs(method: str, seeds: int, samples: int, median: float, p: float) -> dict:
    """One small-probability method over several seeds: evaluations, stated and measured CoV."""
    k = lognormal("mount.stiffness", median=median, cov=COV, unit="N/m")
    limit = Limit("transmissibility", LIMIT)
    values, stated, evaluations, held = [], [], [], 0
    t0 = time.perf_counter()
    for seed in range(seeds):
        r = small_probability(
            model, [k], limit, outputs=["transmissibility"], method=method, samples=samples, seed=seed
        )
        q = r.probability
        values.append(q.value)
        stated.append(q.cov if q.cov is not None else math.nan)
        evaluations.append(q.evaluations)
        held += int(q.low <= p <= q.high)
    wall = time.perf_counter() - t0
    v = np.array(values)
    measured = float(np.std(v, ddof=1) / p)
    return {
        "method": r.method,
        "samples": samples,
        "seeds": seeds,
        "evaluations_mean": float(np.mean(evaluations)),
        "mean_over_exact": float(np.mean(v) / p),
        "cov_stated_mean": float(np.nanmean(stated)),
        "cov_measured": measured,
        "interval_held": held,
        "wall_s_per_run": wall / seeds,
    }


def plain_monte_carlo(n: int, seeds: int, median: float, p: float) -> dict:
    """Plain Monte Carlo with n samples over several seeds: its measured CoV and Clopper–Pearson
    coverage (n from the target CoV)."""
    from scipy.stats import binomtest

    sigma = math.sqrt(math.log1p(COV**2))
    values, held = [], 0
    t0 = time.perf_counter()
    for seed in range(seeds):
        rng = np.random.default_rng(1000 + seed)
        k = median * np.exp(sigma * rng.standard_normal(n))
        hits = int(np.count_nonzero(transmissibility(k) > LIMIT))
        values.append(hits / n)
        ci = binomtest(hits, n).proportion_ci(0.95, method="exact")
        held += int(ci.low <= p <= ci.high)
    return {
        "evaluations": n,
        "seeds": seeds,
        "mean_over_exact": float(np.mean(values) / p),
        "cov_measured": float(np.std(values, ddof=1) / p),
        "interval_held": held,
        "wall_s_per_run": (time.perf_counter() - t0) / seeds,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="8 seeds per method, within a minute")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    seeds = 8 if args.quick else 40
    median = median_for(TARGET)
    p = exact(median)
    methods = {}
    for method in ("importance", "subset"):
        m = method_runs(method, seeds, 1000, median, p)
        # plain Monte Carlo for the same CoV: the binomial estimator's variance p(1 − p)/n
        n_mc = math.ceil((1 - p) / (p * m["cov_measured"] ** 2))
        m["plain_mc_evaluations_same_cov"] = n_mc
        m["plain_mc"] = plain_monte_carlo(n_mc, seeds, median, p)
        m["ratio_plain_mc_over_method"] = n_mc / m["evaluations_mean"]
        # the measured CoV is itself uncertain: a standard deviation of R values, ±1/√(2(R − 1))
        m["cov_measured_relative_error"] = 1 / math.sqrt(2 * (seeds - 1))
        # and at the CoV the method states (for subset simulation an upper bound: a lower ratio)
        m["ratio_at_stated_cov"] = (1 - p) / (p * m["cov_stated_mean"] ** 2) / m["evaluations_mean"]
        methods[method] = m
    doc = {
        "benchmark": "tolerance_small_probability",
        "quick": args.quick,
        "model": "single-DOF isolator, lognormal stiffness (cov 0.15), P(transmissibility > 2)",
        "probability_exact": p,
        "methods": methods,
    }
    if args.json:
        print(json.dumps(doc))
        return 0
    print(
        f"P(T > {LIMIT:g}) = {p:.4g} (closed form), {seeds} seeds per method "
        f"(a measured CoV ±{1 / math.sqrt(2 * (seeds - 1)):.0%})"
    )
    head = (
        f"{'method':<46} {'evaluations':>11} {'CoV stated':>10} {'CoV measured':>12} "
        f"{'held':>5} {'plain MC, same CoV':>18} {'ratio':>7} {'at stated CoV':>13}"
    )
    print(head)
    for m in methods.values():
        print(
            f"{m['method']:<46} {m['evaluations_mean']:>11.0f} {m['cov_stated_mean']:>10.3f} "
            f"{m['cov_measured']:>12.3f} {m['interval_held']:>2}/{m['seeds']:<2} "
            f"{m['plain_mc_evaluations_same_cov']:>18,d} {m['ratio_plain_mc_over_method']:>7.0f} "
            f"{m['ratio_at_stated_cov']:>13.1f}"
        )
    for name, m in methods.items():
        mc = m["plain_mc"]
        print(
            f"plain MC at {name}'s CoV: n = {mc['evaluations']:,d}, CoV measured {mc['cov_measured']:.3f}, "
            f"mean/exact {mc['mean_over_exact']:.3f}, interval held {mc['interval_held']}/{mc['seeds']}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
