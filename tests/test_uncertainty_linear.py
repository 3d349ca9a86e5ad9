"""A linear output of correlated normal inputs: its mean, variance and quantiles are exact
(``Y = aᵀX + b``: mean ``aᵀµ + b``, variance ``aᵀΣa``, quantiles ``µ_Y + σ_Y Φ⁻¹(q)``), so every
sampling estimate must hold them in its interval, and FORM on a linear limit state is exact. The
same study by OpenTURNS' own multivariate normal agrees; the Sobol ranking of independent inputs
matches the variance shares ``a_i² σ_i² / aᵀΣa``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import norm

from mechdyn.uncertainty import InputSpace, Limit, normal, propagate, rank_inputs, small_probability

MU = np.array([0.02, 1.5e6, 80.0])  # m, N/m, kg
SIGMA = np.array([0.001, 2.0e5, 4.0])
R = np.array([[1.0, 0.5, -0.3], [0.5, 1.0, 0.2], [-0.3, 0.2, 1.0]])
A = np.array([[100.0, 1e-5, 0.05], [0.0, 2e-6, -0.1]])  # two outputs, SI
B = np.array([1.0, 0.0])


def space(correlated: bool = True) -> InputSpace:
    names, units = ["gap", "stiffness", "mass"], ["m", "N/m", "kg"]
    variables = [normal(n, m, s, u) for n, m, s, u in zip(names, MU, SIGMA, units, strict=True)]
    return InputSpace(variables, R if correlated else None)


def model(X: np.ndarray) -> np.ndarray:
    return X @ A.T + B


def exact(correlated: bool = True) -> tuple[np.ndarray, np.ndarray]:
    cov = np.diag(SIGMA) @ (R if correlated else np.eye(3)) @ np.diag(SIGMA)
    return A @ MU + B, np.sqrt(np.einsum("ij,jk,ik->i", A, cov, A))


@pytest.mark.parametrize("method", ["mc", "qmc"])
def test_mean_std_and_quantiles_are_held_by_their_intervals(method):
    mean, std = exact()
    limit = float(mean[0] + 1.5 * std[0])
    r = propagate(
        model, space(), 16384, outputs=["y_a", "y_b"], limits=[Limit("y_a", limit)], method=method, seed=7
    )
    for j, name in enumerate(["y_a", "y_b"]):
        d = r.distribution(name)
        assert d.mean.contains(mean[j]) and d.std.contains(std[j]), (name, d.mean, d.std, mean[j], std[j])
        for q, iv in d.quantiles.items():
            assert iv.contains(mean[j] + std[j] * norm.ppf(q)), (name, q, iv)
        assert d.mean.width < 0.05 * std[j]
    assert r.probabilities[0].contains(norm.sf(1.5))
    assert r.evaluations == 16384


def test_the_copula_reproduces_the_correlation_of_normal_inputs():
    X = space().sample(2**15, seed=1)
    assert np.corrcoef(X.T) == pytest.approx(R, abs=0.02)
    assert X.mean(axis=0) == pytest.approx(MU, rel=1e-3)


def test_a_spearman_correlation_is_converted_for_the_copula():
    s = InputSpace([normal("a", 0, 1), normal("b", 0, 1)], {("a", "b"): 0.6}, correlation_kind="spearman")
    assert s.R[0, 1] == pytest.approx(2 * np.sin(np.pi * 0.6 / 6))
    from scipy.stats import spearmanr

    X = s.sample(2**15, seed=2)
    assert spearmanr(X[:, 0], X[:, 1]).statistic == pytest.approx(0.6, abs=0.015)


@pytest.mark.parametrize("side", ["above", "below"])
def test_form_is_exact_on_a_linear_limit_state(side):
    mean, std = exact()
    beta = 3.2
    value = float(mean[1] + (beta if side == "above" else -beta) * std[1])
    r = small_probability(model, space(), Limit("y_b", value, side), outputs=["y_a", "y_b"], method="form")
    assert r.probability.value == pytest.approx(norm.sf(beta), rel=1e-6)
    assert r.reliability_index == pytest.approx(beta, rel=1e-7)
    assert r.probability.evaluations < 200
    assert sum(r.importance.values()) == pytest.approx(1.0)


def test_openturns_own_normal_gives_the_same_form_and_monte_carlo():
    import openturns as ot

    mean, std = exact()
    value = float(mean[0] + 3.0 * std[0])
    dist = ot.Normal(ot.Point(MU), ot.Point(SIGMA), ot.CorrelationMatrix(R.tolist()))
    f = ot.SymbolicFunction(["g", "k", "m"], [f"{A[0, 0]}*g + {A[0, 1]}*k + {A[0, 2]}*m + {B[0]}"])
    event = ot.ThresholdEvent(ot.CompositeRandomVector(f, ot.RandomVector(dist)), ot.Greater(), value)
    solver = ot.AbdoRackwitz()
    solver.setStartingPoint(dist.getMean())
    form = ot.FORM(solver, event)
    form.run()
    ours = small_probability(model, space(), Limit("y_a", value), outputs=["y_a", "y_b"], method="form")
    assert ours.probability.value == pytest.approx(form.getResult().getEventProbability(), rel=1e-6)
    # and OpenTURNS' Monte Carlo of a moderate probability lies in our interval and ours in its
    value = float(mean[0] + 1.0 * std[0])
    event = ot.ThresholdEvent(ot.CompositeRandomVector(f, ot.RandomVector(dist)), ot.Greater(), value)
    ot.RandomGenerator.SetSeed(3)
    mc = ot.ProbabilitySimulationAlgorithm(event, ot.MonteCarloExperiment())
    mc.setBlockSize(20000)
    mc.setMaximumOuterSampling(1)
    mc.setMaximumCoefficientOfVariation(0.0)
    mc.run()
    res = mc.getResult()
    p_ot, half = res.getProbabilityEstimate(), res.getConfidenceLength(0.95) / 2
    p = propagate(
        model, space(), 20000, outputs=["y_a", "y_b"], limits=[Limit("y_a", value)], seed=4
    ).probabilities[0]
    assert p.low <= p_ot + half and p_ot - half <= p.high
    assert abs(p_ot - norm.sf(1.0)) <= half and p.contains(norm.sf(1.0))


def test_sobol_ranking_matches_the_variance_shares():
    mean, std = exact(correlated=False)
    limit = Limit("y_a", float(mean[0] + std[0]))
    r = rank_inputs(
        model, space(correlated=False), outputs=["y_a", "y_b"], limits=[limit], base_samples=2048, seed=5
    )
    assert r.evaluations == 2048 * 5
    shares = (A[0] * SIGMA) ** 2 / np.sum((A[0] * SIGMA) ** 2)
    ya = r.outputs[0]
    for i, name in enumerate(["gap", "stiffness", "mass"]):
        assert abs(ya.ST[name] - shares[i]) <= max(3 * ya.ST_conf[name], 0.02), (name, ya.ST[name], shares[i])
        assert abs(ya.S1[name] - shares[i]) <= max(3 * ya.S1_conf[name], 0.02)
    # the probability of y_a beyond its mean + σ is shared out in the order of the variance
    indicator = r.probabilities[0]
    assert indicator.ranked() == ya.ranked() == ["stiffness", "mass", "gap"]
    assert not indicator.note
    assert r.to_frame().shape == (9, 6)  # (2 outputs + 1 limit) × 3 inputs


def test_a_limit_never_reached_has_no_indices_and_says_why():
    r = rank_inputs(
        model,
        space(correlated=False),
        outputs=["y_a", "y_b"],
        limits=[Limit("y_a", 1e9)],
        base_samples=256,
        seed=1,
    )
    assert not r.probabilities[0].ST
    assert "no sample beyond the limit" in r.probabilities[0].note
    assert r.warnings
