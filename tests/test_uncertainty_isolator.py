"""A single-DOF isolator whose mount stiffness is lognormal: the probability that its transmissibility
exceeds a limit in closed form, reproduced by Monte Carlo and randomized QMC within their stated
intervals, a probability of about 1e-4 reached in fewer than 1e4 evaluations (subset simulation,
FORM, importance sampling), and the same study answered by OpenTURNS' own distributions and
algorithms.

Transmissibility (Den Hartog, *Mechanical Vibrations*, 4th ed., 1956, §2.7; Rao, *Mechanical
Vibrations*, 6th ed., eq. 3.68): ``T(r, ζ) = √((1 + (2ζr)²) / ((1 − r²)² + (2ζr)²))`` with
``r = ω/ω_n``, ``ω_n = √(k/m)``. ``T > L`` ⇔ ``q(s) = L² s² + (aL² − 2L² − a) s + (L² − 1) < 0`` with
``s = r²``, ``a = 4ζ²``: ``s`` between the roots, so ``k = mω²/s`` lies in an interval and the
probability is a difference of two lognormal CDFs.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.stats import norm

from mechdyn.uncertainty import Limit, lognormal, propagate, small_probability

MASS = 1000.0  # kg
OMEGA = 2 * math.pi * 25.0  # rad/s, the forcing
ZETA = 0.1  # damping ratio, held fixed (an elastomer's loss factor)
LIMIT = 2.0  # transmissibility limit: amplification near resonance


def transmissibility(k: np.ndarray) -> np.ndarray:
    r2 = OMEGA**2 * MASS / k
    two_zeta_r_sq = 4 * ZETA**2 * r2
    return np.sqrt((1 + two_zeta_r_sq) / ((1 - r2) ** 2 + two_zeta_r_sq))


def model(X: np.ndarray) -> np.ndarray:
    return transmissibility(X[:, 0])


def failing_stiffness(limit: float = LIMIT) -> tuple[float, float]:
    """The interval of k (N/m) where T > limit (limit > 1)."""
    a = 4 * ZETA**2
    L2 = limit**2
    s1, s2 = sorted(np.roots([L2, a * L2 - 2 * L2 - a, L2 - 1]).real)
    k_w2 = MASS * OMEGA**2
    return k_w2 / s2, k_w2 / s1


def exact_probability(median: float, cov: float, limit: float = LIMIT) -> float:
    k_lo, k_hi = failing_stiffness(limit)
    s = math.sqrt(math.log1p(cov**2))
    return float(norm.cdf(math.log(k_hi / median) / s) - norm.cdf(math.log(k_lo / median) / s))


# a soft mount near resonance: P ≈ 0.2
MEDIAN_MC = MASS * OMEGA**2 / 1.3**2
COV_MC = 0.25
# a mount tuned well below: P ≈ 1.6e-4 at β = 3.6 from the interval's lower end
COV_SMALL = 0.15
MEDIAN_SMALL = failing_stiffness()[0] * math.exp(-3.6 * math.sqrt(math.log1p(COV_SMALL**2)))


def test_the_failure_set_is_the_interval_where_the_closed_form_says():
    k_lo, k_hi = failing_stiffness()
    k = np.array([k_lo * 0.999, k_lo * 1.001, k_hi * 0.999, k_hi * 1.001])
    assert (transmissibility(k) > LIMIT).tolist() == [False, True, True, False]


@pytest.mark.parametrize("method", ["mc", "qmc"])
def test_monte_carlo_reproduces_the_closed_form_within_its_interval(method):
    k = lognormal("mount.stiffness", median=MEDIAN_MC, cov=COV_MC, unit="N/m")
    p_exact = exact_probability(MEDIAN_MC, COV_MC)
    assert 0.1 < p_exact < 0.4
    r = propagate(
        model,
        [k],
        16384,
        outputs=["transmissibility"],
        limits=[Limit("transmissibility", LIMIT)],
        method=method,
        seed=3,
    )
    p = r.probabilities[0]
    assert p.contains(p_exact), (p, p_exact)
    assert p.high - p.low < 0.05 * p_exact * (4 if method == "mc" else 2)
    assert p.evaluations == 16384 and not p.warnings
    # the quantiles of T above 1 in closed form too: P(T > t) = 1 − q
    dist = r.distribution("transmissibility")
    for q in (0.5, 0.95):
        t_q = brentq(lambda t, q=q: exact_probability(MEDIAN_MC, COV_MC, t) - (1 - q), 1.0001, 5.0)
        assert dist.quantiles[q].contains(t_q), (q, dist.quantiles[q], t_q)


def test_a_probability_of_1e_4_by_subset_simulation_in_fewer_than_1e4_evaluations():
    k = lognormal("mount.stiffness", median=MEDIAN_SMALL, cov=COV_SMALL, unit="N/m")
    p_exact = exact_probability(MEDIAN_SMALL, COV_SMALL)
    assert 1e-4 < p_exact < 2e-4
    r = small_probability(model, [k], Limit("transmissibility", LIMIT), method="subset", samples=1500, seed=1)
    p = r.probability
    assert p.method == "subset simulation" and p.evaluations < 10_000
    # the stated CoV is Au & Beck's upper bound; OpenTURNS' lower bound (independent levels) beside it
    assert p.cov is not None and 0.2 < p.cov < 1.0
    assert r.details["coefficient_of_variation_independent_levels"] < p.cov
    assert p.contains(p_exact), (p, p_exact)


@pytest.mark.parametrize("method", ["form", "sorm", "importance"])
def test_a_probability_of_1e_4_by_form_sorm_and_importance_sampling(method):
    k = lognormal("mount.stiffness", median=MEDIAN_SMALL, cov=COV_SMALL, unit="N/m")
    p_exact = exact_probability(MEDIAN_SMALL, COV_SMALL)
    r = small_probability(model, [k], Limit("transmissibility", LIMIT), method=method, samples=1000, seed=2)
    p = r.probability
    assert p.evaluations < 10_000
    # the failure set's far end is 15 σ away: FORM's half-space misses nothing that counts
    if method == "importance":
        assert p.cov is not None and p.cov < 0.1 and p.contains(p_exact)
    else:
        assert p.interval_method == "none" and p.value == pytest.approx(p_exact, rel=1e-3)
    assert r.design_point["mount.stiffness"] == pytest.approx(failing_stiffness()[0], rel=1e-3)
    assert r.importance == {"mount.stiffness": pytest.approx(1.0)}


def test_no_failure_observed_gives_an_upper_bound_and_says_so():
    k = lognormal("mount.stiffness", median=MEDIAN_SMALL, cov=COV_SMALL, unit="N/m")
    r = propagate(
        model, [k], 1000, outputs=["transmissibility"], limits=[Limit("transmissibility", LIMIT)], seed=0
    )
    p = r.probabilities[0]
    assert p.failures == 0 and p.value == 0.0 and p.upper_bound_only
    assert p.high == pytest.approx(3.0 / 1000, rel=0.01)  # the rule of three
    assert any("no sample of 1000" in w for w in r.warnings)


def test_a_wide_interval_is_flagged():
    k = lognormal("mount.stiffness", median=MEDIAN_SMALL, cov=0.3, unit="N/m")
    r = propagate(
        model, [k], 500, outputs=["transmissibility"], limits=[Limit("transmissibility", LIMIT)], seed=0
    )
    p = r.probabilities[0]
    assert 0 < p.failures < 20
    assert any("wider than the probability" in w for w in p.warnings)


# --- the same study answered by OpenTURNS' own distributions and algorithms -------------------------


def _openturns_event(median: float, cov: float):
    import openturns as ot

    s = math.sqrt(math.log1p(cov**2))
    k = ot.LogNormal(math.log(median), s)
    T = ot.PythonFunction(1, 1, func_sample=lambda X: transmissibility(np.asarray(X)[:, 0])[:, None])
    return ot.ThresholdEvent(ot.CompositeRandomVector(T, ot.RandomVector(k)), ot.Greater(), LIMIT), k


def test_openturns_monte_carlo_agrees_within_the_intervals():
    import openturns as ot

    event, _ = _openturns_event(MEDIAN_MC, COV_MC)
    ot.RandomGenerator.SetSeed(11)
    algo = ot.ProbabilitySimulationAlgorithm(event, ot.MonteCarloExperiment())
    algo.setBlockSize(16384)
    algo.setMaximumOuterSampling(1)
    algo.setMaximumCoefficientOfVariation(0.0)
    algo.run()
    res = algo.getResult()
    p_ot, half_ot = res.getProbabilityEstimate(), res.getConfidenceLength(0.95) / 2
    k = lognormal("mount.stiffness", median=MEDIAN_MC, cov=COV_MC, unit="N/m")
    ours = propagate(
        model, [k], 16384, outputs=["transmissibility"], limits=[Limit("transmissibility", LIMIT)], seed=5
    )
    p = ours.probabilities[0]
    # the two independent estimates' intervals overlap, and each holds the closed form
    assert p.low <= p_ot + half_ot and p_ot - half_ot <= p.high
    assert abs(p_ot - exact_probability(MEDIAN_MC, COV_MC)) <= half_ot


def test_openturns_form_on_its_own_lognormal_agrees():
    import openturns as ot

    event, k_ot = _openturns_event(MEDIAN_SMALL, COV_SMALL)
    solver = ot.AbdoRackwitz()
    solver.setStartingPoint(k_ot.getMean())
    form = ot.FORM(solver, event)
    form.run()
    k = lognormal("mount.stiffness", median=MEDIAN_SMALL, cov=COV_SMALL, unit="N/m")
    ours = small_probability(model, [k], Limit("transmissibility", LIMIT), method="form")
    assert ours.probability.value == pytest.approx(form.getResult().getEventProbability(), rel=1e-4)
    assert ours.reliability_index == pytest.approx(form.getResult().getHasoferReliabilityIndex(), rel=1e-5)
