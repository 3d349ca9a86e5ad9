"""Robust design (issue 46, item 3): an ``optimize`` study whose objective and constraints are
statistics of outputs over the scatter, each design estimated on the same common random numbers.

The closed-form case is a single-DOF isolator (Den Hartog, *Mechanical Vibrations*, 4th ed., 1956,
§2.7): a machine of mass m on a mount of stiffness k (designed in [1, 6] MN/m, bought lognormal with
a coefficient of variation of 0.2 about the design's value), forced at 25 Hz. Its transmissibility
``T = √((1 + (2ζr)²) / ((1 − r²)² + (2ζr)²))``, ``r² = mω²/k``, rises with k in the isolation
region (r > √2), and its static deflection ``δ = mg/k`` falls: minimise the 95 % quantile of T
keeping the 95 % quantile of δ under 3 mm. With k = k_d e^{σξ} (σ² = ln(1 + cov²)) the constraint
is active at the optimum: on the common points ξ the estimated quantile of δ is
``(mg/k_d) · Q``, ``Q = quantile_0.95(e^{−σξ})`` (np.quantile is positively homogeneous), so the
estimate's optimum is exactly ``k* = mg Q / δ_max``; the true one, with the exact quantile
``e^{1.645σ}`` for Q, lies within the estimate's interval.

The analysis here is the closed form itself, registered for the test on the support model type, with
a batch evaluation, so that the study runs in a second.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import norm

from mechdyn import registry
from mechdyn.studies import run_study
from mechdyn.studies.errors import StudyError
from mechdyn.studies.kinds.robust import RobustEvaluator, common_points, space_at
from mechdyn.studies.polish import FIRST_ORDER
from mechdyn.studies.run import recompute, stored_result
from mechdyn.studies.study import load_study, study_from_data
from mechdyn.uncertainty import propagate

MASS = 1000.0  # kg
OMEGA = 2 * math.pi * 25.0  # rad/s
ZETA = 0.1
G = 9.80665  # m/s², as mechdyn's standard gravity
COV = 0.2
SIGMA = math.sqrt(math.log1p(COV**2))
DEFLECTION = 3e-3  # m, the limit on the static deflection's 95 % quantile
ANALYSIS = "test-isolator"

ISOLATOR = """
[model]
type = "support"
name = "isolator"

[machine]
mass = "1000 kg"

[support]
stiffness = "3e6 N/m"
damping_ratio = 0.1

[excitation]
period = "0.04 s"
harmonics = [[1, "1 kN", "0 deg"]]
"""

STUDY = """
[study]
name = "robust-isolator"
kind = "optimize"
model = "isolator.toml"
analysis = "test-isolator"
samples = 12
scatter_samples = 256
seed = 7

[[parameters]]
path = "support.stiffness"
name = "k"
range = ["1e6 N/m", "6e6 N/m"]
scatter = {distribution = "lognormal", cov = 0.2}

[[outputs]]
output = "static_deflection_m"
limit = "3 mm"
statistic = "p_exceed"

[[objectives]]
output = "transmissibility"
statistic = "q95"

[[constraints]]
output = "static_deflection_m"
statistic = "q95"
unit = "mm"
max = "3 mm"
"""


def transmissibility(k):
    r2 = OMEGA**2 * MASS / np.asarray(k, dtype=float)
    a = 4 * ZETA**2 * r2
    return np.sqrt((1 + a) / ((1 - r2) ** 2 + a))


class _Result:
    def __init__(self, k: float):
        self.k = k

    def summary(self):
        return {"transmissibility": float(transmissibility(self.k)), "static_deflection_m": MASS * G / self.k}

    def arrays(self):
        return {}


def _run(loaded, **options):
    return _Result(float(loaded.model.mounts[0].stiffness[2]))


def _batch(loaded, columns, keys, **options):
    k = np.asarray(next(iter(columns.values())), dtype=float)
    figures = {"transmissibility": transmissibility(k), "static_deflection_m": MASS * G / k}
    return {key: figures[key] for key in keys}, [None] * len(k)


@pytest.fixture
def isolator(tmp_path, monkeypatch):
    """The isolator's study file (and its model), its analysis registered for the test only."""
    analysis = registry.Analysis(
        ANALYSIS,
        ("support",),
        _run,
        "a single-DOF isolator in closed form (a test)",
        outputs=(
            registry.Output("transmissibility", "force transmissibility at 25 Hz", ""),
            registry.Output("static_deflection_m", "static deflection under gravity", "m"),
        ),
        batch=_batch,
    )
    monkeypatch.setitem(registry._REGISTRY, ANALYSIS, analysis)
    (tmp_path / "isolator.toml").write_text(ISOLATOR, encoding="utf-8")
    path = tmp_path / "robust.toml"
    path.write_text(STUDY, encoding="utf-8")
    return path


def out_T(k: float, xi: np.ndarray) -> float:
    """The estimate of T's 95 % quantile at the design k, on the common points."""
    return float(np.quantile(transmissibility(k * np.exp(SIGMA * xi[:, 0])), 0.95))


def _q(xi: np.ndarray) -> float:
    """The estimate's Q on the common points: quantile_0.95 of e^{−σξ}."""
    return float(np.quantile(np.exp(-SIGMA * xi[:, 0]), 0.95))


def test_the_design_is_mapped_from_common_points_that_propagate_draws_too(isolator):
    study = load_study(isolator)
    ev = RobustEvaluator(study)
    xi = common_points(1, 256, 16, study.seed)
    assert np.array_equal(ev.xi, xi)
    for k in (2e6, 4e6):  # the same ξ at every design, mapped through that design's scatter
        space = space_at(study, [k])
        got = propagate(lambda X: X[:, 0], space, 256, method="qmc", replicates=16, seed=study.seed)
        np.testing.assert_allclose(ev.samples([k])[:, 0], got.X[:, 0], rtol=1e-15)  # round-off
        np.testing.assert_allclose(ev.samples([k])[:, 0], k * np.exp(SIGMA * xi[:, 0]), rtol=1e-12)


def test_the_robust_optimum_is_the_closed_form_on_the_common_points_and_near_the_exact_one(
    isolator, tmp_path
):
    study = load_study(isolator)
    r = run_study(study, str(tmp_path / "r.db"))
    f = r.findings
    best = f["best"]
    k_found = best["parameters"]["k"]
    xi = RobustEvaluator(study).xi
    k_crn = MASS * G * _q(xi) / DEFLECTION  # the estimate's optimum, exact
    k_true = MASS * G * math.exp(norm.ppf(0.95) * SIGMA) / DEFLECTION  # the true statistic's
    assert k_found == pytest.approx(k_crn, rel=1e-6)
    # every polish start reached the first-order point on the active constraint, and the optimum is
    # called converged there (SLSQP ends a round-off outside an active limit: it still holds)
    for end in f["polish"]["per_start"]:
        assert end["measure"] is not None and end["measure"] <= FIRST_ORDER
        assert end["value"] == pytest.approx(out_T(k_crn, xi), rel=1e-6)
        assert end["feasible"] is True
    assert f["verdict"] == "converged", f["optimality"]
    # the estimate at the optimum and its interval hold the exact statistics there
    out = best["outputs"]
    exact_delta = MASS * G * math.exp(norm.ppf(0.95) * SIGMA) / k_found
    assert out["static_deflection_m.q95_low"] <= exact_delta <= out["static_deflection_m.q95_high"]
    exact_T = float(transmissibility(k_found * math.exp(norm.ppf(0.95) * SIGMA)))
    assert out["transmissibility.q95"] == pytest.approx(out_T(k_found, xi), rel=1e-12)
    assert out["transmissibility.q95_low"] <= exact_T <= out["transmissibility.q95_high"]
    p_exact = float(norm.cdf(math.log(MASS * G / (DEFLECTION * k_found)) / SIGMA))
    assert out["static_deflection_m.p_exceed_low"] <= p_exact <= out["static_deflection_m.p_exceed_high"]
    # the true optimum lies within what the estimate can resolve: its k moves δ's quantile by less
    # than the interval's width
    width = out["static_deflection_m.q95_high"] - out["static_deflection_m.q95_low"]
    assert abs(MASS * G * _q(xi) / k_true - DEFLECTION) < width
    rb = f["robust"]
    assert rb["samples"] == 256 and rb["replicates"] == 16
    assert rb["scatter"]["k"]["centred_on_design"] is True
    assert rb["objective"]["value"] == out["transmissibility.q95"]
    imp = rb["improvement"]  # the base (3 MN/m) breaks the constraint: better in T, not feasible
    assert imp["difference"] < 0 and imp["significant"] is False and imp["base_feasible"] is False
    check = f["single_design_check"]
    assert check["status"] == "ok" and check["relative_difference"] < 1e-12
    # stored: one variant per design, the findings the same from the database alone, a design
    # recomputed from what is stored gives its statistics again, and a second run evaluates nothing
    db = str(tmp_path / "r.db")
    again = stored_result(db, study.name)
    assert again.findings["best"]["parameters"]["k"] == k_found
    assert recompute(db, best["variant"]).outputs["transmissibility.q95"] == out["transmissibility.q95"]
    assert run_study(study, db).evaluated == 0
    assert len(r.variants) == f["evaluations"]
    text = "\n".join(t.to_text() if hasattr(t, "to_text") else str(t) for t in r.tables())
    assert "common random numbers" in text and "256 samples of the scatter per design" in text


def test_common_random_numbers_make_the_statistic_a_smooth_function_of_the_design(isolator):
    study = load_study(isolator)
    ev = RobustEvaluator(study)
    k = 2.5e6 * (1 + 1e-6 * np.arange(3))  # steps of the polish's finite differences
    got = [e.outputs for e in ev(k[:, None])]
    y = np.array([g["transmissibility.q95"] for g in got])
    half = (got[0]["transmissibility.q95_high"] - got[0]["transmissibility.q95_low"]) / 2
    # nearby designs differ by their design only: far less than the estimate's own uncertainty, and
    # along a straight line (the second difference is nothing beside the first)
    assert 0 < y[1] - y[0] < 1e-4 * half
    assert abs(y[2] - 2 * y[1] + y[0]) < 1e-3 * (y[1] - y[0])
    # without common random numbers (the second design on other points) the difference is noise,
    # orders of magnitude above the design's own effect
    data = _data(isolator)
    other = RobustEvaluator(study_from_data(str(isolator), {**data, "study": {**data["study"], "seed": 8}}))
    y_other = other(k[1:2, None])[0].outputs["transmissibility.q95"]
    assert abs(y_other - y[0]) > 100 * (y[1] - y[0])


def _data(path: Path) -> dict:
    return tomllib.loads(path.read_text(encoding="utf-8"))


def _refused(path: Path, data: dict, *said: str) -> None:
    with pytest.raises(StudyError) as err:
        study_from_data(str(path), data)
    text = str(err.value)
    assert text.startswith(str(path)), text
    for s in said:
        assert s in text, (s, text)


def test_bad_robust_input_is_refused_with_the_field_named(isolator):
    base = _data(isolator)
    d = copy.deepcopy(base)
    del d["parameters"][0]["scatter"]
    _refused(isolator, d, "[[outputs]] #1 → statistic", "no parameter scatters")
    d = copy.deepcopy(base)
    del d["outputs"][0]["limit"]
    _refused(isolator, d, "[[outputs]] #1 → statistic", '"p_exceed"', "needs the output's limit")
    d = copy.deepcopy(base)
    d["objectives"][0]["statistic"] = "q150"
    _refused(isolator, d, "[[objectives]] #1 → statistic", "'q150' is not a statistic", "q95")
    d = copy.deepcopy(base)
    d["study"]["scatter_samples"] = 100
    _refused(isolator, d, "scatter_samples = 100", "power of 2")
    d = copy.deepcopy(base)
    d["parameters"][0]["scatter"] = {"distribution": "lognormal", "median": "3 MN/m", "cov": 0.2}
    _refused(isolator, d, "→ scatter", "does not move with the design", "cov")
    d = copy.deepcopy(base)
    for row in (*d["outputs"], *d["objectives"], *d["constraints"]):
        del row["statistic"]
    _refused(isolator, d, "no objective or constraint names a statistic")
    d = copy.deepcopy(base)
    d["study"]["kind"] = "lhs"
    del d["parameters"][0]["scatter"]
    d["objectives"] = d["constraints"] = []
    _refused(isolator, d, "[[outputs]] #1 → statistic", "is for an optimize study with scatter")


@pytest.mark.slow  # CI's heavy step (issue 48: the test command's minutes)
def test_a_probability_constraint_is_never_called_a_converged_optimum(isolator, tmp_path):
    """P(δ > 3 mm) ≤ 5 % instead of δ's q95 ≤ 3 mm: the same event, but a probability counts samples,
    a step function of the design whose zero gradient proves nothing: the verdict says so."""
    text = isolator.read_text(encoding="utf-8").replace(
        '[[constraints]]\noutput = "static_deflection_m"\nstatistic = "q95"\nunit = "mm"\nmax = "3 mm"',
        '[[constraints]]\noutput = "static_deflection_m"\nstatistic = "p_exceed"\nmax = 0.05',
    )
    assert 'statistic = "p_exceed"\nmax = 0.05' in text
    text = text.replace("samples = 12", "samples = 4")  # its point is the verdict, not the optimum
    text = text.replace("scatter_samples = 256", "scatter_samples = 64")
    isolator.write_text(text, encoding="utf-8")
    r = run_study(load_study(isolator), str(tmp_path / "r.db"))
    assert r.findings["verdict"] == "not converged" and "counts samples" in r.findings["not_judged"]
    words = [row for t in r.tables() for row in t.rows if row and row[0] == "verdict"]
    assert words and "step function of the design" in str(words[0][1]), words
