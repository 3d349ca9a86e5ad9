"""The polynomial-chaos surrogate: on a natural frequency ``f = √(k/m)/2π`` of lognormal k and m,
itself lognormal (``ln f = ½ ln k − ½ ln m − ln 2π``), its moments, its validation, its Sobol indices
and the probabilities computed through it are checked against the closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from mechdyn.errors import ModelError
from mechdyn.uncertainty import (
    InputSpace,
    Limit,
    lognormal,
    normal,
    polynomial_chaos,
    propagate,
    small_probability,
    truncated,
)

K_MEDIAN, K_COV = 2e6, 0.2  # N/m
M_MEDIAN, M_COV = 500.0, 0.1  # kg
S_K, S_M = (math.sqrt(math.log1p(c**2)) for c in (K_COV, M_COV))
LN_MEDIAN = 0.5 * math.log(K_MEDIAN / M_MEDIAN) - math.log(2 * math.pi)
S_F = 0.5 * math.hypot(S_K, S_M)


def model(X: np.ndarray) -> np.ndarray:
    return np.sqrt(X[:, 0] / X[:, 1]) / (2 * math.pi)


def inputs() -> list:
    return [
        lognormal("mount.stiffness", median=K_MEDIAN, cov=K_COV, unit="N/m"),
        lognormal("machine.mass", median=M_MEDIAN, cov=M_COV, unit="kg"),
    ]


@pytest.fixture(scope="module")
def surrogate():
    return polynomial_chaos(model, inputs(), 128, outputs=["frequency_hz"], degree=5, seed=1)


def test_the_surrogate_gives_the_moments_and_says_how_well_it_predicts(surrogate):
    mean = math.exp(LN_MEDIAN + S_F**2 / 2)
    std = mean * math.sqrt(math.expm1(S_F**2))
    assert surrogate.mean["frequency_hz"] == pytest.approx(mean, rel=1e-6)
    assert surrogate.std["frequency_hz"] == pytest.approx(std, rel=1e-5)
    assert surrogate.q2["frequency_hz"] > 0.9999 and not surrogate.warnings
    assert surrogate.evaluations == 128 + 32
    # the stiffness carries (nearly) its share of ln f's variance
    share = S_K**2 / (S_K**2 + S_M**2)
    assert surrogate.ST["frequency_hz"]["mount.stiffness"] == pytest.approx(share, abs=0.01)
    assert surrogate.S1["frequency_hz"]["machine.mass"] == pytest.approx(1 - share, abs=0.01)


def test_probabilities_through_the_surrogate_match_the_closed_form(surrogate):
    limit = math.exp(LN_MEDIAN + 1.0 * S_F)
    r = propagate(
        surrogate, inputs(), 2**14, outputs=["frequency_hz"], limits=[Limit("frequency_hz", limit)], seed=2
    )
    assert r.probabilities[0].contains(norm.sf(1.0))
    rare = math.exp(LN_MEDIAN + 3.09 * S_F)  # P = 1e-3
    form = small_probability(
        surrogate, inputs(), Limit("frequency_hz", rare), outputs=["frequency_hz"], method="form"
    )
    assert form.probability.value == pytest.approx(norm.sf(3.09), rel=1e-3)


def test_the_nataf_map_inverts_with_correlation_and_truncation():
    space = InputSpace(
        [*inputs(), truncated(normal("gap", 0.002, 1e-4, "m"), 0.0018, 0.0023)],
        {("mount.stiffness", "machine.mass"): 0.4, ("machine.mass", "gap"): -0.2},
    )
    xi = np.random.default_rng(0).standard_normal((200, 3)) * 0.8
    assert space.to_standard_normal(space.from_standard_normal(xi)) == pytest.approx(xi, abs=1e-7)


def test_too_few_evaluations_for_the_degree_is_refused():
    with pytest.raises(ModelError) as info:
        polynomial_chaos(model, inputs(), 20, degree=5)
    assert (
        info.value.field == "samples" and "21 polynomials" in str(info.value) and "n ≥ 42" in str(info.value)
    )
