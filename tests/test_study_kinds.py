"""The study kinds' protocol (:mod:`mechdyn.studies.kinds`): one registered object per kind, whose
findings are a pure function of the study and its variants, checked here against closed forms on
variants made by hand, and the same after a run and from the database alone."""

from __future__ import annotations

import itertools
import math
from datetime import UTC, datetime
from types import SimpleNamespace

import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.studies import StudyError, load_study, run_study
from mechdyn.studies.kinds import KINDS, Kind, kind
from mechdyn.studies.run import stored_result
from mechdyn.studies.spec import Constraint, Objective, Parameter, Watched
from mechdyn.studies.storage import StoredVariant, variant_key

NOW = datetime.now(UTC)


def _variant(
    i: int, params: dict[str, float], outputs: dict[str, float], status: str = "ok"
) -> StoredVariant:
    key = variant_key(list(params.values()))
    return StoredVariant(i, "s", key, i, params, {}, outputs, status, None, None, "", "", NOW)


def _study(parameters, watched, objectives=(), constraints=(), **kw):
    return SimpleNamespace(
        name="s",
        path=None,
        kind=kw.pop("kind", "lhs"),
        parameters=list(parameters),
        watched=list(watched),
        objectives=list(objectives),
        constraints=list(constraints),
        targets=[],
        samples=kw.pop("samples", None),
        seed=1,
        **kw,
    )


def _parameter(name: str, base: float, levels=(), low=None, high=None) -> Parameter:
    return Parameter.function(name, lambda m, x: m, base, levels=levels, low=low, high=high)


Y = Watched("y_N", "N", "")


def test_every_kind_is_one_registered_object_with_the_whole_protocol():
    assert list(KINDS) == ["oat", "factorial", "lhs", "sobol", "optimize", "synthesis", "tolerance"]
    for name, k in KINDS.items():
        assert isinstance(k, Kind) and k.name == name and kind(name) is k and k.title
        assert k.uses in ("levels", "ranges")
        for method in ("check", "design", "run", "order", "findings", "tables", "plots"):
            assert callable(getattr(k, method))
    with pytest.raises(StudyError, match="no study kind 'sweep': the kinds are oat, factorial"):
        kind("sweep")


def test_a_study_file_with_an_unknown_kind_names_the_kinds(tmp_path):
    text = (EXAMPLES / "studies" / "press_support_influence.toml").read_text()
    path = tmp_path / "s.toml"
    path.write_text(
        text.replace('kind = "oat"', 'kind = "factorail"').replace(
            '"../press_on_support.toml"', repr(str(EXAMPLES / "press_on_support.toml"))
        )
    )
    with pytest.raises(StudyError) as e:
        load_study(path)
    message = str(e.value)
    assert str(path) in message and "kind" in message and "'factorail'" in message
    assert "did you mean 'factorial'" in message


def test_oat_findings_are_the_change_from_the_base_and_a_negative_output_growing_in_size_grows():
    a = _parameter("a", 2.0, levels=(1.0, 3.0))
    b = _parameter("b", 5.0, levels=(4.0,))
    study = _study([a, b], [Y], kind="oat")
    oat = kind("oat")
    X = oat.design(study)
    assert X.tolist() == [[2.0, 5.0], [1.0, 5.0], [3.0, 5.0], [2.0, 4.0]]

    def y(x):  # negative, and larger in size as a grows
        return -100.0 * x[0] - x[1]

    variants = [_variant(i, {"a": r[0], "b": r[1]}, {"y_N": y(r)}) for i, r in enumerate(X)]
    f = oat.findings(study, variants).findings
    assert f["base"] == {"y_N": -205.0} and f["base_variant"] == 0
    changes = [(e["parameter"], e["level"], e["outputs"]["y_N"]["change_percent"]) for e in f["effects"]]
    assert changes == [
        ("a", "1", pytest.approx(100 * (-105 + 205) / -205)),  # smaller in size: −48.8 %
        ("a", "3", pytest.approx(100 * (-305 + 205) / -205)),  # larger in size: +48.8 %
        ("b", "4", pytest.approx(100 * (-204 + 205) / -205)),
    ]
    assert changes[1][2] > 0 > changes[0][2]
    assert [e["level_percent"] for e in f["effects"]] == pytest.approx([-50.0, 50.0, -20.0])


def test_factorial_main_effects_and_interaction_are_the_closed_form_of_a_bilinear_response():
    # y = 3a + 2b + ab on a ∈ {0, 1}, b ∈ {0, 1, 2}: ȳ = 1.5 + 2 + 0.5·1 = 4; main effect of a at
    # level ℓ: ȳ(a = ℓ) − ȳ = (3 + 1)(ℓ − ½); of b at m: (2 + ½)(m − 1); interaction (ℓ − ½)(m − 1)
    a = _parameter("a", 0.5, levels=(0.0, 1.0))
    b = _parameter("b", 1.0, levels=(0.0, 1.0, 2.0))
    study = _study([a, b], [Y], kind="factorial")
    fac = kind("factorial")
    X = fac.design(study)
    assert X.shape == (1 + 6, 2) and X[0].tolist() == [0.5, 1.0]
    variants = [
        _variant(i, {"a": r[0], "b": r[1]}, {"y_N": 3 * r[0] + 2 * r[1] + r[0] * r[1]})
        for i, r in enumerate(X)
    ]
    e = fac.findings(study, variants).findings["factorial"]["y_N"]
    assert e["mean"] == pytest.approx(4.0)
    assert e["main"]["a"]["effects"] == pytest.approx([4 * (0 - 0.5), 4 * (1 - 0.5)])
    assert e["main"]["b"]["effects"] == pytest.approx([2.5 * (m - 1) for m in (0, 1, 2)])
    assert e["main"]["a"]["spread"] == pytest.approx(4.0) and e["main"]["b"]["spread"] == pytest.approx(5.0)
    largest = max(abs((ell - 0.5) * (m - 1)) for ell, m in itertools.product((0, 1), (0, 1, 2)))
    assert e["interactions"] == [{"parameters": ["a", "b"], "largest": pytest.approx(largest)}]
    assert variants[[v.id for v in variants].index(e["lowest"])].parameters == {"a": 0.0, "b": 0.0}
    assert variants[[v.id for v in variants].index(e["highest"])].parameters == {"a": 1.0, "b": 2.0}


def test_lhs_findings_rank_the_parameters_by_their_rank_correlation_and_name_the_best_design():
    a, b = _parameter("a", 0.5, low=0.0, high=1.0), _parameter("b", 0.5, low=0.0, high=1.0)
    study = _study([a, b], [Y], objectives=[Objective(Y, "maximize")], kind="lhs", samples=40)
    lhs = kind("lhs")
    X = lhs.design(study)
    assert X.shape == (41, 2) and X[0].tolist() == [0.5, 0.5]
    # y grows with a and does not depend on b at all (a monotone function of a: ρ = 1 exactly)
    variants = [_variant(i, {"a": r[0], "b": r[1]}, {"y_N": math.exp(r[0])}) for i, r in enumerate(X)]
    found = lhs.findings(study, variants)
    rho = found.findings["rank_correlation"]["y_N"]
    assert rho["a"] == pytest.approx(1.0) and abs(rho["b"]) < 0.5
    top = int(np.argmax(X[:, 0]))
    assert found.findings["best"]["variant"] == top and found.best == {top}
    assert found.findings["output_ranges"]["y_N"] == {
        "min": pytest.approx(math.exp(X[:, 0].min())),
        "max": pytest.approx(math.exp(X[:, 0].max())),
    }


def test_the_pareto_front_is_the_non_dominated_feasible_designs_with_its_knee_and_ends():
    rng = np.random.default_rng(3)
    F = rng.random((200, 2))
    g = Watched("g_N", "N", "")
    f1, f2 = Watched("f1_N", "N", ""), Watched("f2_N", "N", "")
    a = _parameter("a", 0.5, low=0.0, high=1.0)
    limit = Constraint(g, max=0.9)
    study = _study(
        [a],
        [f1, f2, g],
        objectives=[Objective(f1, "minimize"), Objective(f2, "maximize")],
        constraints=[limit],
        kind="optimize",
    )
    G = rng.random(200)
    base = _variant(0, {"a": 0.5}, {"f1_N": 9.0, "f2_N": -9.0, "g_N": 0.0})
    variants = [base] + [
        _variant(i + 1, {"a": i / 1000}, {"f1_N": F[i, 0], "f2_N": F[i, 1], "g_N": G[i]}) for i in range(200)
    ]
    found = kind("optimize").findings(study, variants)
    ids = [d["variant"] for d in found.findings["pareto_front"]]
    # brute force: feasible (g ≤ 0.9), and no feasible design at least as good in both, better in one
    ok = [i for i in range(200) if G[i] <= 0.9]
    expect = [
        i + 1
        for i in ok
        if not any(F[j, 0] <= F[i, 0] and F[j, 1] >= F[i, 1] and tuple(F[j]) != tuple(F[i]) for j in ok)
    ]
    assert sorted(ids) == expect and found.best == set(expect)
    # the ends: the front's lowest f1 and highest f2; the knee: nearest the ideal point, scaled
    front = np.array([[F[i - 1, 0], -F[i - 1, 1]] for i in expect])
    assert found.findings["ends"] == {
        "f1_N": expect[int(np.argmin(front[:, 0]))],
        "f2_N": expect[int(np.argmin(front[:, 1]))],
    }
    scaled = (front - front.min(axis=0)) / np.ptp(front, axis=0)
    assert found.findings["knee"] == expect[int(np.argmin(np.hypot(*scaled.T)))]
    assert found.findings["base"]["variant"] == 0


@pytest.mark.parametrize("sense", ["minimize", "maximize"])
def test_an_optimum_s_improvement_is_positive_when_it_is_better_than_the_base(sense):
    a = _parameter("a", 1.0, low=0.0, high=2.0)
    study = _study([a], [Y], objectives=[Objective(Y, sense)], kind="optimize")
    y = {0.0: 50.0, 1.0: 100.0, 2.0: 200.0}  # the base (a = 1) first
    variants = [_variant(i, {"a": x}, {"y_N": y[x]}) for i, x in enumerate((1.0, 0.0, 2.0))]
    f = kind("optimize").findings(study, variants).findings
    assert f["base"]["variant"] == 0
    if sense == "minimize":
        assert f["best"]["outputs"]["y_N"] == 50.0 and f["improvement_percent"] == pytest.approx(50.0)
    else:
        assert f["best"]["outputs"]["y_N"] == 200.0 and f["improvement_percent"] == pytest.approx(100.0)


CHEAP = """
[study]
name = "{kind}-kinds"
kind = "{kind}"
model = {model!r}
analysis = "mechanism"
samples = {samples}
curves = 0
{extra}

[[parameters]]
path = "points.A.x"
{span}

[[outputs]]
output = "driving_torque_peak_Nm"

[[outputs]]
output = "stroke_m"
unit = "mm"
"""

_EXTRA = {
    "optimize": '[[objectives]]\noutput = "driving_torque_peak_Nm"\ngoal = "minimize"\n',
    "synthesis": '[[targets]]\noutput = "stroke_m"\nequals = "190 mm"\ntolerance = "1 mm"\n',
}

_SPAN = {"tolerance": 'scatter = {distribution = "normal", std = "1 mm"}'}


@pytest.mark.parametrize("name", list(KINDS))
def test_every_kind_states_the_same_findings_after_a_run_and_from_the_database_alone(tmp_path, name):
    levels = KINDS[name].uses == "levels"
    path = tmp_path / f"{name}.toml"
    path.write_text(
        CHEAP.format(
            kind=name,
            model=str(EXAMPLES / "slider_crank.toml"),
            samples={"sobol": 4, "lhs": 6, "optimize": 8, "synthesis": 3, "tolerance": 4}.get(name, 1),
            extra=_EXTRA.get(name, ""),
            span=_SPAN.get(name, 'levels = ["-10 %", "10 %"]' if levels else 'range = "±10 %"'),
        )
    )
    db = str(tmp_path / "r.db")
    ran = run_study(load_study(path), db)
    stored = stored_result(db, ran.study.name)
    assert [v.id for v in stored.variants] == [v.id for v in ran.variants]
    only_a_run_knows = {"trials", "polish", "generations", "stages", "single_design_check"}
    assert {k: v for k, v in ran.findings.items() if k not in only_a_run_knows} == stored.findings
    assert ran.evaluated + ran.reused == len({v.key for v in ran.variants}) == stored.reused  # each once
    assert ran.tables() and [t.title for t in ran.tables()] == [t.title for t in stored.tables()]
    assert set(ran.plots()) == set(stored.plots())


@pytest.mark.slow  # RP-1 one variant at a time beside the batch: 13 s
def test_a_variant_s_warnings_are_stored_with_it_on_the_batch_and_the_single_design_path(tmp_path):
    """RP-1 with one gear's installation angle off: the idler's two meshes give it two pitch curves,
    which the model warns of as it is built. Every variant of a study of it, evaluated by the batch
    (one compiled cycle) or one by one, is stored with that warning, and nothing reaches the console."""
    import warnings

    from mechdyn.studies import Evaluator
    from mechdyn.studies.storage import StudyStore

    text = (EXAMPLES / "transplanter_rp1.toml").read_text()
    (tmp_path / "rp1.toml").write_text(
        text.replace('orientation = "-35.000000000 deg"', 'orientation = "-45 deg"')
    )
    (tmp_path / "s.toml").write_text(
        '[study]\nname = "warned"\nkind = "oat"\nmodel = "rp1.toml"\nanalysis = "mechanism"\n'
        '[[parameters]]\npath = "bodies.arm.mass"\nlevels = ["-10 %", "10 %"]\n'
        '[[outputs]]\noutput = "driving_torque_peak_Nm"\n'
    )
    study = load_study(tmp_path / "s.toml")
    db = str(tmp_path / "r.db")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning that escapes the variants fails the test
        result = run_study(study, db)
    from mechdyn.store import ResultStore

    with ResultStore(db, read_only=True) as store:
        stored = StudyStore(store).variants("warned")
    assert len(stored) == 3
    for v in stored:
        assert any("gear 'idler 1' meshes in 'G1-G2' and 'G3-G2'" in w for w in v.warnings), v.warnings
    single = Evaluator(
        study.source, study.analysis, study.parameters, ["driving_torque_peak_Nm"], batch=False
    )
    batch = Evaluator(study.source, study.analysis, study.parameters, ["driving_torque_peak_Nm"])
    X = [[v.parameters["bodies.arm.mass"]] for v in result.variants]
    for one, many in zip(single(X), batch(X), strict=True):
        assert set(many.warnings) <= set(one.warnings) and many.warnings


def test_a_variant_whose_dyad_points_coincide_fails_alone_and_does_not_stop_the_block():
    """A four-bar whose rocker pivot O4 sits where the crank tip A is drawn: at that angle the dyad
    A–B–O4 has its two known points in one place (a polish once stepped onto such a design and the
    compiled kernel raised ZeroDivisionError, stopping the study). The variant fails with its reason;
    the other variant of the block is the base design's."""
    import mechdyn
    from mechdyn.mechanism import inverse_dynamics
    from mechdyn.mechanism.batch import cycle_columns

    m = mechdyn.load(EXAMPLES / "fourbar.toml").model
    cols = {("points", "O4", 0): np.array([0.18, 0.025]), ("points", "O4", 1): np.array([0.0, 0.04330127])}
    batch = cycle_columns(m, cols, 36)
    assert set(batch.failures) == {1} and "does not close" in batch.failures[1]
    base = inverse_dynamics(m, 36).summary()["driving_torque_peak_Nm"]
    assert batch.summary()["driving_torque_peak_Nm"][0] == pytest.approx(base, rel=1e-12)
