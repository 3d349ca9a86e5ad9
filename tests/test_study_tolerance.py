"""The ``tolerance`` study kind (issue 46): each parameter's scatter sampled through the batch engine,
each output's distribution and each limit's probability with their intervals, the tolerances ranked;
checked against :func:`mechdyn.uncertainty.propagate` on a direct evaluation, against closed forms
for a linear output, for resuming from the database, and for the errors of a bad scatter table."""

from __future__ import annotations

import copy
import math
import tomllib
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats

from conftest import EXAMPLES
from mechdyn.studies import StudyError, load_study, run_study
from mechdyn.studies.kinds import kind
from mechdyn.studies.kinds.tolerance import first_order_given_data
from mechdyn.studies.run import stored_result
from mechdyn.studies.spec import Parameter, Watched
from mechdyn.studies.storage import StoredVariant, variant_key
from mechdyn.studies.study import study_from_data
from mechdyn.uncertainty import Limit, normal, propagate, uniform

STUDY = EXAMPLES / "studies" / "press_support_tolerance.toml"


def _quick(samples: int, method: str = "qmc"):
    return replace(load_study(STUDY).quick(samples), method=method)


def test_the_press_support_probability_is_what_propagate_gives_on_a_direct_evaluation(tmp_path):
    """The study's probability that the bed moves more than 1.3 mm (256 scrambled Sobol points, stored
    variants) lies in the 95 % interval of plain Monte Carlo by :func:`mechdyn.uncertainty.propagate`
    on other samples (1024, another seed) evaluated directly by the evaluator, outside any study; the
    two means agree within their intervals; and the evaluator's batch path is the single-design path
    (each variant built from its file and analysed alone) on a few of those samples."""
    from mechdyn.studies.evaluate import Evaluator
    from mechdyn.studies.kinds.tolerance import space

    study = _quick(256)
    result = run_study(study, str(tmp_path / "r.db"))
    key = "displacement_max_m"
    found = next(d for d in result.findings["limits"] if d["output"] == key)["probability"]
    assert "quasi-Monte Carlo" in found["method"] and 0.1 < found["value"] < 0.9
    ev = Evaluator(study.source, study.analysis, study.parameters, [key], study.options)

    def direct(X: np.ndarray) -> np.ndarray:
        return np.array([e.outputs[key] for e in ev(X)])

    limit = next(lim for lim in study.limits if lim.output == key)
    mc = propagate(direct, space(study), 1024, outputs=[key], limits=[limit], method="mc", seed=11)
    assert mc.probabilities[0].contains(found["value"]), (mc.probabilities[0], found)
    mean = result.findings["outputs"][key]["distribution"]
    assert mc.distributions[0].mean.low <= mean["mean_high"]
    assert mean["mean_low"] <= mc.distributions[0].mean.high
    one = [ev.one(row).outputs[key] for row in mc.X[:6]]
    assert one == pytest.approx(mc.Y[:6, 0], rel=1e-9)
    # the stiffness drives a quasi-static displacement: it ranks first
    assert result.findings["outputs"][key]["ranking"]["ranked"][0] == "support stiffness"


def _variant(i: int, params: dict[str, float], outputs: dict[str, float]) -> StoredVariant:
    from datetime import UTC, datetime

    key = variant_key(list(params.values()))
    return StoredVariant(i, "s", key, i, params, {}, outputs, "ok", None, None, "", "", datetime.now(UTC))


@pytest.mark.parametrize("method", ["qmc", "mc"])
def test_a_linear_output_of_normal_and_uniform_inputs_has_its_exact_mean_spread_and_probability(method):
    """y = 3 x₁ − 2 x₂ with x₁ ~ N(1, 0.2²) and x₂ ~ U(0, 1): mean 2, variance 9·0.04 + 4/12, its
    quantiles and P(y > 3) those of the exact distribution (by numerical convolution), each within the
    study's 95 % interval; the ranking puts x₁ first (share 0.36/0.693 against 0.333/0.693)."""
    x1 = replace(Parameter.function("x1", lambda m, x: m, 1.0), scatter=normal("x1", 1.0, 0.2))
    x2 = replace(Parameter.function("x2", lambda m, x: m, 0.5), scatter=uniform("x2", 0.0, 1.0))
    y = Watched("y_N", "N", "")
    study = SimpleNamespace(
        name="s",
        path=None,
        parameters=[x1, x2],
        watched=[y],
        samples=4096,
        seed=5,
        method=method,
        limits=(Limit("y_N", 3.0),),
    )
    k = kind("tolerance")
    X = k.design(study)
    assert X.shape == (4096, 2)
    variants = [_variant(i, {"x1": a, "x2": b}, {"y_N": 3 * a - 2 * b}) for i, (a, b) in enumerate(X)]
    f = k.findings(study, variants).findings
    d = f["outputs"]["y_N"]["distribution"]
    var = 9 * 0.04 + 4 / 12
    assert d["mean_low"] <= 2.0 <= d["mean_high"]
    assert d["std_low"] <= math.sqrt(var) <= d["std_high"]
    # y = 3 x1 + u, u ~ U(-2, 0): P(y > t) = E_u[P(3 x1 > t - u)]
    u = np.linspace(-2, 0, 20001)
    exceed = float(np.trapezoid(stats.norm.sf((3.0 - u) / 3, 1.0, 0.2), u) / 2)
    p = f["limits"][0]["probability"]
    assert p["low"] <= exceed <= p["high"], (p, exceed)
    cdf = lambda t: 1 - float(np.trapezoid(stats.norm.sf((t - u) / 3, 1.0, 0.2), u) / 2)  # noqa: E731
    from scipy.optimize import brentq

    q95 = brentq(lambda t: cdf(t) - 0.95, 0, 5)
    assert d["q95_low"] <= q95 <= d["q95_high"]
    ranking = f["outputs"]["y_N"]["ranking"]
    assert ranking["ranked"] == ["x1", "x2"] and "Sobol" in ranking["method"]
    assert ranking["measures"]["x1"] == pytest.approx(0.36 / var, abs=0.05)
    assert ranking["measures"]["x2"] == pytest.approx((4 / 12) / var, abs=0.05)


def test_the_given_data_index_is_near_the_exact_one_and_near_zero_for_an_unrelated_input():
    rng = np.random.default_rng(2)
    x = rng.standard_normal((4096, 2))
    y = x[:, 0] + 0.5 * x[:, 1]
    assert first_order_given_data(x[:, 0], y) == pytest.approx(0.8, abs=0.04)
    assert first_order_given_data(x[:, 1], y) == pytest.approx(0.2, abs=0.04)
    assert first_order_given_data(rng.standard_normal(4096), y) < 0.01


def test_few_samples_rank_by_rank_correlation_and_say_so(tmp_path):
    result = run_study(_quick(16), str(tmp_path / "r.db"))
    ranking = result.findings["outputs"]["displacement_max_m"]["ranking"]
    assert "Spearman" in ranking["method"] and ranking["ranked"][0] == "support stiffness"
    assert ranking["measures"]["support stiffness"] < -0.5  # a stiffer support moves less


def test_a_stored_tolerance_study_is_resumed_reusing_its_variants(tmp_path):
    """Run, then run again: every variant found stored, none evaluated; the findings the same, and
    the same read from the database alone; its tables and plots made."""
    db = str(tmp_path / "r.db")
    study = _quick(32)
    first = run_study(study, db)
    assert first.count == 32 and first.reused == 0
    again = run_study(study, db)
    assert again.reused == 32 and again.evaluated == 0
    assert again.findings == first.findings
    from mechdyn.store import ResultStore

    with ResultStore(db, read_only=True) as store:
        stored = stored_result(store, study.name)
    assert stored.findings == first.findings
    tables = kind("tolerance").tables(first)
    assert any("probability of exceeding" in t.title for t in tables)
    plots = kind("tolerance").plots(first)
    assert set(plots) == {"tolerance_displacement_max_m.png", "tolerance_transmitted_force_range_N.png"}
    import matplotlib

    matplotlib.use("Agg")
    for draw in plots.values():
        draw()


def _data() -> dict:
    return tomllib.loads(STUDY.read_text(encoding="utf-8"))


@pytest.mark.parametrize(
    ("scatter", "said"),
    [
        (
            {"distribution": "lognorml", "cov": 0.15},
            ["'distribution'", "'lognorml'", "did you mean 'lognormal'"],
        ),
        ({"distribution": "normal", "sd": "1 MN/m"}, ["'sd'", "did you mean 'std'"]),
        ({"distribution": "uniform", "low": "1 mm", "high": "2 mm"}, ["'low'", "'1 mm'", "N/m"]),
        ({"distribution": "lognormal", "cov": -0.1}, ["'cov'", "-0.1", "above zero"]),
        ({"tolerance": "shore_a_9"}, ["'tolerance'", "'shore_a_9'", "did you mean 'shore_a_5'"]),
        ({"median": "2 MN/m"}, ["neither distribution nor tolerance", 'distribution = "lognormal"']),
    ],
)
def test_a_bad_scatter_table_names_the_file_the_field_the_value_and_the_fix(scatter, said):
    data = _data()
    data["parameters"][0]["scatter"] = scatter
    with pytest.raises(StudyError) as err:
        study_from_data(str(STUDY), data)
    text = str(err.value)
    assert text.startswith(f"{STUDY}: [[parameters]] #1 (path = 'support.stiffness') → scatter"), text
    for s in said:
        assert s in text, (s, text)


def test_a_tolerance_study_refuses_a_range_a_missing_scatter_and_samples_that_do_not_suit():
    data = _data()
    data["parameters"][0]["range"] = "±10 %"
    with pytest.raises(StudyError, match="a scatter or a range or levels, not both"):
        study_from_data(str(STUDY), data)
    del data["parameters"][0]["scatter"]
    with pytest.raises(StudyError, match=r"#1 \('support.stiffness'\): a tolerance study needs scatter"):
        study_from_data(str(STUDY), data)
    data = _data()
    data["study"]["samples"] = 100
    with pytest.raises(StudyError, match=r"samples = 100: method = \"qmc\" needs a power of 2"):
        study_from_data(str(STUDY), data)
    data["study"]["method"] = "mc"
    assert study_from_data(str(STUDY), data).samples == 100
    data = _data()
    data["outputs"][0]["limit"] = 1.3
    with pytest.raises(StudyError, match=r"\[\[outputs\]\] #1: limit 1.3 .* needs a quantity in m"):
        study_from_data(str(STUDY), data)
    data = _data()
    data["outputs"][0]["side"] = "over"
    with pytest.raises(StudyError, match="side"):
        study_from_data(str(STUDY), data)
    # another kind refuses a scatter without a range, saying what it needs
    data = _data()
    data["study"]["kind"] = "lhs"
    with pytest.raises(StudyError, match="needs a range"):
        study_from_data(str(STUDY), copy.deepcopy(data))


@pytest.mark.slow  # a local Dask cluster of two processes: its start alone takes seconds
def test_a_tolerance_study_on_a_dask_cluster_equals_the_in_process_run(tmp_path):
    """The samples evaluated by Dask workers (in blocks, out of order) are stored under the same
    keys: the findings (distributions, probabilities with their intervals, the ranking) are the
    in-process run's, value for value."""
    study = replace(_quick(64), chunk=8)  # eight blocks for the two workers
    on_dask = run_study(study, str(tmp_path / "dask.db"), dask="local")
    in_process = run_study(study, str(tmp_path / "local.db"))
    assert on_dask.count == in_process.count == 64
    assert on_dask.findings == in_process.findings
