"""The uncertainty results keep the package's result contract: a JSON-ready ``summary()``, a
``to_frame()`` table, titled ``tables()``, ``plot()`` returning a figure, and their warnings."""

from __future__ import annotations

import json

import matplotlib
import numpy as np
import pytest

from mechdyn.uncertainty import (
    InputRanking,
    Limit,
    PropagationResult,
    ReliabilityResult,
    lognormal,
    normal,
    propagate,
    rank_inputs,
    small_probability,
    tolerance,
)

matplotlib.use("Agg")


def _model(X: np.ndarray) -> np.ndarray:
    k, h = X[:, 0], X[:, 1]
    frequency = np.sqrt(k * (1 + 0.02 * (h - 60)) / 500.0) / (2 * np.pi)
    return np.column_stack([frequency, 2.0 * frequency])


INPUTS = [
    lognormal("mount.stiffness", median="2 MN/m", cov=0.2, unit="N/m"),
    tolerance("pad.shore_a", "shore_a_5", nominal=60),
]
OUTPUTS = ["frequency_hz", "second_frequency_hz"]
LIMITS = [Limit("frequency_hz", 11.0, label="separation from 10 Hz"), Limit("frequency_hz", 8.0, "below")]


@pytest.fixture(scope="module")
def propagated() -> PropagationResult:
    return propagate(_model, INPUTS, 2048, outputs=OUTPUTS, limits=LIMITS, method="qmc", replicates=8, seed=1)


def test_a_propagation_keeps_the_result_contract(propagated):
    s = propagated.summary()
    json.dumps(s)
    assert s["evaluations"] == 2048 and set(OUTPUTS) <= set(s)
    assert s["frequency_hz"]["q50"] == pytest.approx(np.median(propagated.Y[:, 0]))
    frame = propagated.to_frame()
    assert list(frame.columns) == ["mount.stiffness_N_per_m", "pad.shore_a", *OUTPUTS]
    assert len(frame) == 2048
    titles = [t.title for t in propagated.tables()]
    assert titles[0] == "uncertain inputs" and "probabilities of exceeding the limits" in titles
    fig = propagated.plot()
    assert len(fig.axes) == 2
    matplotlib.pyplot.close("all")
    assert "frequency_hz > 11 (separation from 10 Hz)" in s["probabilities"]
    assert "frequency_hz < 8" in s["probabilities"]


def test_a_ranking_and_a_reliability_result_keep_the_contract():
    ranking = rank_inputs(_model, INPUTS, outputs=OUTPUTS, limits=LIMITS[:1], base_samples=256, seed=2)
    assert isinstance(ranking, InputRanking)
    json.dumps(ranking.summary())
    assert ranking.outputs[0].ranked()[0] == "mount.stiffness"
    assert ranking.tables() and len(ranking.to_frame()) == 6
    reliability = small_probability(
        _model, INPUTS, Limit("frequency_hz", 13.0), outputs=OUTPUTS, method="importance"
    )
    assert isinstance(reliability, ReliabilityResult)
    s = reliability.summary()
    json.dumps(s)
    assert s["method"] == "importance sampling at the FORM design point" and s["evaluations"] > 2000
    assert reliability.importance["mount.stiffness"] > reliability.importance["pad.shore_a"]
    assert [t.title for t in reliability.tables()][1] == "design point and importance factors (FORM)"
    assert list(reliability.to_frame().columns) == ["input", "design_point", "importance_factor"]


def test_subset_simulation_accepts_discrete_levels_that_form_refuses():
    from mechdyn.uncertainty import levels

    inputs = [levels("n", [1.0, 2.0, 3.0], [0.6, 0.3, 0.1]), normal("x", 0.0, 1.0)]
    r = small_probability(
        lambda X: X[:, 0] + X[:, 1], inputs, Limit("y", 5.5), outputs=["y"], method="subset", samples=500
    )
    from scipy.stats import norm

    exact = 0.6 * norm.sf(4.5) + 0.3 * norm.sf(3.5) + 0.1 * norm.sf(2.5)
    assert r.probability.contains(exact)
    assert r.design_point == {} and r.importance == {}
