"""Estimates that must not depend on the size of the numbers: a small probability of a limit state
in metres (FORM's line search once stalled on a displacement limit of 1e-3 m), and a standard
deviation's interval from few randomized-QMC replicates (never below zero)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from mechdyn.uncertainty import Limit, lognormal, propagate, small_probability
from mechdyn.uncertainty.estimates import replicate_interval

FORCE = 1e5  # N, a static load on a lognormal stiffness
COV = 0.15
MEDIAN = 4.5e8  # N/m


@pytest.mark.parametrize("method", ["form", "importance"])
def test_a_displacement_limit_in_metres_is_found_as_a_force_limit_would_be(method):
    """x = F/k with k lognormal: P(x > L) = P(k < F/L) = Φ(−β) exactly; the limit, 3.9e-4 m, set for
    β = 3.719 (P = 1.0e-4). FORM gives it to 1e-6 relative, importance sampling within its interval:
    the model is handed to OpenTURNS relative to the size of its limit."""
    k = lognormal("k", median=MEDIAN, cov=COV, unit="N/m")
    s = math.sqrt(math.log1p(COV**2))
    limit = FORCE / MEDIAN * math.exp(3.719 * s)
    exact = float(norm.sf(3.719))
    r = small_probability(lambda X: FORCE / X[:, 0], [k], Limit("x_m", limit), outputs=["x_m"], method=method)
    p = r.probability
    if method == "form":
        assert p.value == pytest.approx(exact, rel=1e-6)
        assert r.design_point["k"] == pytest.approx(FORCE / limit, rel=1e-6)
    else:
        assert p.low <= exact <= p.high, (p, exact)
    assert r.reliability_index == pytest.approx(3.719, abs=0.05)


def test_a_standard_deviation_s_replicate_interval_stays_at_or_above_zero():
    """Two replicates: Student t of 1 degree of freedom (12.7) makes the interval wider than the
    estimate; its lower end is 0, not negative, and a mean keeps its symmetric interval."""
    iv = replicate_interval(0.16, np.array([0.05, 0.27]), low=0.0)
    assert iv.low == 0.0 and iv.high == pytest.approx(0.16 + 12.706 * 0.1556 / math.sqrt(2), rel=1e-3)
    mean = replicate_interval(-0.5, np.array([-1.0, 0.0]))
    assert mean.low == pytest.approx(-0.5 - (mean.high + 0.5))
    Y = np.array([1.0, 2.0, 10.0, 1.5])
    r = propagate(lambda X: Y, [lognormal("k", median=1.0, cov=0.1)], 4, method="qmc", replicates=2, seed=1)
    assert r.distributions[0].std.low >= 0.0


def test_replicates_that_agree_exactly_give_the_pooled_binomial_interval_not_a_point():
    """Sixteen replicates of eight points each, three beyond the limit in every one: their spread is
    zero, which says nothing of the error; the interval is the pooled points' Clopper-Pearson one."""
    import numpy as np
    from scipy.stats import binomtest

    from mechdyn.uncertainty.estimates import replicate_probability

    p = replicate_probability(np.full(16, 3 / 8), 128, "x > 1")
    exact = binomtest(48, 128).proportion_ci(confidence_level=0.95, method="exact")
    assert p.value == 0.375 and p.low < p.value < p.high
    assert (p.low, p.high) == (exact.low, exact.high) and "agree exactly" in p.interval_method
    assert p.method == "randomized quasi-Monte Carlo" and p.evaluations == 128
