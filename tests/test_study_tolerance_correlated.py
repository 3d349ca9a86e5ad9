"""Correlated scatter in a ``tolerance`` study (issue 46): ``[[correlations]]`` ties two parameters
by a Gaussian copula. Checked against the closed form of a linear output of two correlated normal
inputs (mean, variance ``a²σ₁² + b²σ₂² + 2abρσ₁σ₂``, a quantile and an exceedance probability), against
the exact rank correlation of the copula, through a study file, and for the errors of a bad table."""

from __future__ import annotations

import math
import tomllib
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats

from conftest import EXAMPLES
from mechdyn.studies import StudyError, run_study
from mechdyn.studies.kinds import kind
from mechdyn.studies.spec import Parameter, Watched
from mechdyn.studies.storage import StoredVariant, variant_key
from mechdyn.studies.study import study_from_data
from mechdyn.uncertainty import Limit, normal, uniform

STUDY = EXAMPLES / "studies" / "press_support_tolerance.toml"

A, B = 3.0, -2.0
M1, S1, M2, S2 = 1.0, 0.2, 2.0, 0.5


def _variant(i: int, params: dict[str, float], outputs: dict[str, float]) -> StoredVariant:
    from datetime import UTC, datetime

    key = variant_key(list(params.values()))
    return StoredVariant(i, "s", key, i, params, {}, outputs, "ok", None, None, "", "", datetime.now(UTC))


def _study(rho: float, method: str, n: int = 4096, limit: float = 0.0, measure: str = "normal", **kw):
    x1 = replace(Parameter.function("x1", lambda m, x: m, M1), scatter=normal("x1", M1, S1))
    x2 = replace(Parameter.function("x2", lambda m, x: m, M2), scatter=normal("x2", M2, S2))
    return SimpleNamespace(
        name="s",
        path="linear.toml",
        parameters=[x1, x2],
        watched=[Watched("y_N", "N", "")],
        samples=n,
        seed=1,
        method=method,
        limits=(Limit("y_N", limit),),
        correlations=(("x1", "x2", rho, measure),),
        small_probability=kw.get("small_probability"),
    )


def _linear_findings(study) -> tuple[np.ndarray, dict]:
    k = kind("tolerance")
    X = k.design(study)
    variants = [_variant(i, {"x1": a, "x2": b}, {"y_N": A * a + B * b}) for i, (a, b) in enumerate(X)]
    return X, k.findings(study, variants).findings


@pytest.mark.parametrize("method", ["qmc", "mc"])
@pytest.mark.parametrize("rho", [0.6, -0.6])
def test_a_linear_output_of_correlated_normal_inputs_has_its_exact_variance(method, rho):
    """y = 3 x₁ − 2 x₂, x₁ ~ N(1, 0.2²), x₂ ~ N(2, 0.5²) correlated by ρ: y is normal with mean
    3 − 4 = −1 and variance a²σ₁² + b²σ₂² + 2abρσ₁σ₂; the study's 95 % intervals hold the exact mean,
    standard deviation, 95 % quantile and P(y > 0), and exclude the standard deviation the same inputs
    would give independent (so that a correlation dropped on the way fails the test). Each interval is
    a 95 % one, so over seeds about one check in twenty misses: the seed is fixed (the first tried)."""
    study = _study(rho, method)
    X, f = _linear_findings(study)
    assert np.corrcoef(X.T)[0, 1] == pytest.approx(rho, abs=0.05)
    var = A**2 * S1**2 + B**2 * S2**2 + 2 * A * B * rho * S1 * S2
    mean, std = A * M1 + B * M2, math.sqrt(var)
    d = f["outputs"]["y_N"]["distribution"]
    assert d["mean_low"] <= mean <= d["mean_high"], (d, mean)
    assert d["std_low"] <= std <= d["std_high"], (d, std)
    q95 = stats.norm.ppf(0.95, mean, std)
    assert d["q95_low"] <= q95 <= d["q95_high"], (d, q95)
    independent = math.sqrt(A**2 * S1**2 + B**2 * S2**2)
    assert not d["std_low"] <= independent <= d["std_high"]
    p = f["limits"][0]["probability"]
    exact = float(stats.norm.sf(0.0, mean, std))
    assert p["low"] <= exact <= p["high"], (p, exact)
    assert f["correlations"] == [
        {"between": ["x1", "x2"], "coefficient": rho, "measure": "normal", "normal": rho}
    ]
    assert "share" in f["outputs"]["y_N"]["ranking"]["method"]


def test_a_rank_correlation_is_converted_exactly_to_the_copula_s():
    """Two uniform inputs with Spearman's ρ_S = 0.5: the copula's R = 2 sin(π/12) = 0.5176, and the
    rank correlation of 4096 samples is 0.5 within its standard error (about 1/√n)."""
    u1 = replace(Parameter.function("u1", lambda m, x: m, 0.5), scatter=uniform("u1", 0.0, 1.0))
    u2 = replace(Parameter.function("u2", lambda m, x: m, 0.5), scatter=uniform("u2", 0.0, 1.0))
    study = SimpleNamespace(
        name="s",
        path="",
        parameters=[u1, u2],
        samples=4096,
        seed=3,
        method="mc",
        correlations=(("u1", "u2", 0.5, "spearman"),),
    )
    from mechdyn.studies.kinds.tolerance import correlation_matrix

    R = correlation_matrix(study)
    assert R[0, 1] == pytest.approx(2 * math.sin(math.pi / 12), rel=1e-12)
    X = kind("tolerance").design(study)
    assert stats.spearmanr(X[:, 0], X[:, 1]).statistic == pytest.approx(0.5, abs=3 / math.sqrt(4096))


def _data(correlations: list[dict]) -> dict:
    data = tomllib.loads(STUDY.read_text(encoding="utf-8"))
    data["correlations"] = correlations
    return data


def test_a_study_file_with_correlations_runs_and_shows_them(tmp_path):
    """The press support's stiffness and damping correlated (a stiffer pad damps less: ρ = −0.5 rank):
    read from the file, the samples carry the correlation, the findings and a table state it, and a
    stored study gives the same findings again."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.run import stored_result

    data = _data(
        [{"between": ["support stiffness", "damping ratio"], "coefficient": -0.5, "measure": "spearman"}]
    )
    study = study_from_data(str(STUDY), data).quick(64)
    assert study.correlations == (("support stiffness", "damping ratio", -0.5, "spearman"),)
    db = str(tmp_path / "r.db")
    result = run_study(study, db)
    X = np.array(
        [[v.parameters["support stiffness"], v.parameters["damping ratio"]] for v in result.variants]
    )
    assert stats.spearmanr(X[:, 0], X[:, 1]).statistic < -0.3
    c = result.findings["correlations"][0]
    assert c["normal"] == pytest.approx(2 * math.sin(math.pi * -0.5 / 6), rel=1e-12)
    titles = [t.title for t in kind("tolerance").tables(result)]
    assert any("correlations of the scatter" in t for t in titles), titles
    with ResultStore(db, read_only=True) as store:
        assert stored_result(store, study.name).findings == result.findings


@pytest.mark.parametrize(
    ("rows", "said"),
    [
        (
            [{"between": ["support stiffnes", "damping ratio"], "coefficient": 0.5}],
            ["[[correlations]] #1 → between", "'support stiffnes'", "did you mean 'support stiffness'"],
        ),
        (
            [{"between": ["damping ratio", "damping ratio"], "coefficient": 0.5}],
            ["#1 → between", "paired with itself"],
        ),
        (
            [
                {"between": ["support stiffness", "damping ratio"], "coefficient": 0.5},
                {"between": ["damping ratio", "support stiffness"], "coefficient": 0.3},
            ],
            ["#2 → between", "given already in #1", "each pair once"],
        ),
        (
            [{"between": ["support stiffness", "damping ratio"], "coefficient": 1.2}],
            ["#1 → coefficient", "1.2", "between -1 and 1"],
        ),
        (
            [{"between": ["support stiffness", "damping ratio"], "coefficient": 0.5, "measure": "pearson"}],
            ["correlations → #1 → measure", "'pearson'"],
        ),
        (
            [{"between": ["support stiffness"], "coefficient": 0.5}],
            ["correlations → #1 → between"],
        ),
    ],
)
def test_a_bad_correlation_names_the_file_the_row_the_field_and_the_fix(rows, said):
    with pytest.raises(StudyError) as err:
        study_from_data(str(STUDY), _data(rows))
    text = str(err.value)
    assert text.startswith(str(STUDY)), text
    for s in said:
        assert s in text, (s, text)


def test_contradicting_correlations_are_refused_as_not_positive_definite():
    """Three parameters, two pairs strongly alike and the third strongly opposed: no joint normal
    distribution has these correlations (the matrix's smallest eigenvalue is −0.8)."""
    data = _data(
        [
            {"between": ["support stiffness", "damping ratio"], "coefficient": 0.9},
            {"between": ["support stiffness", "machine mass"], "coefficient": 0.9},
            {"between": ["damping ratio", "machine mass"], "coefficient": -0.9},
        ]
    )
    data["parameters"].append(
        {"path": "machine.mass", "name": "machine mass", "scatter": {"distribution": "normal", "cov": 0.05}}
    )
    with pytest.raises(StudyError, match=r"\[\[correlations\]\]: the coefficients .* not positive definite"):
        study_from_data(str(STUDY), data)
    data["correlations"][2]["coefficient"] = 0.9
    assert study_from_data(str(STUDY), data).correlations[2][2] == 0.9


def test_another_kind_refuses_correlations():
    data = _data([{"between": ["support stiffness", "damping ratio"], "coefficient": 0.5}])
    data["study"]["kind"] = "lhs"
    for row in data["parameters"]:
        del row["scatter"]
        row["range"] = "±10 %"
    with pytest.raises(StudyError, match=r"\[\[correlations\]\] is for kind = \"tolerance\" studies"):
        study_from_data(str(STUDY), data)
