"""Rarely exceeded limits in a ``tolerance`` study (issue 46): when the samples exceed a limit less
often than 1e-3 (or never), the kind finds its probability by a small-probability method
(:func:`mechdyn.uncertainty.small_probability`), stores the points it asks for as the study's
variants, and states the probability with its method, its interval and its evaluations.

Checked on the single-DOF isolator of ``tests/test_uncertainty_isolator.py`` (a lognormal mount
stiffness, a transmissibility limit, the probability in closed form) run through the kind with a
runner that evaluates the closed form, and on press A's support through the batch engine: stored,
resumed with nothing evaluated, and stated again from the database alone."""

from __future__ import annotations

import math
import tomllib
from dataclasses import replace
from datetime import UTC, datetime
from types import SimpleNamespace

import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.studies import run_study
from mechdyn.studies.kinds import kind
from mechdyn.studies.spec import Parameter, Watched
from mechdyn.studies.storage import StoredVariant, variant_key
from mechdyn.studies.study import study_from_data
from mechdyn.uncertainty import Limit, lognormal
from test_uncertainty_isolator import (
    COV_SMALL,
    LIMIT,
    MEDIAN_SMALL,
    exact_probability,
    failing_stiffness,
    transmissibility,
)

KEY = "transmissibility_ratio"


class ClosedFormRunner:
    """A runner (:class:`mechdyn.studies.run.Runner`'s ``study`` and ``evaluate``) that answers the
    isolator's transmissibility in closed form, storing each distinct point once, as the batch engine
    does."""

    def __init__(self, study):
        self.study = study
        self.cache: dict[str, StoredVariant] = {}

    def evaluate(self, X):
        out = []
        for row in np.atleast_2d(np.asarray(X, dtype=float)):
            key = variant_key(row)
            if key not in self.cache:
                i = len(self.cache)
                y = float(transmissibility(np.array([row[0]]))[0])
                self.cache[key] = StoredVariant(
                    i, "s", key, i, {"k": float(row[0])}, {}, {KEY: y}, "ok", None, None, "", "",
                    datetime.now(UTC),
                )  # fmt: skip
            out.append(self.cache[key])
        return out


def _isolator(method: str | None, samples: int = 1024):
    k = replace(
        Parameter.function("k", lambda m, x: m, MEDIAN_SMALL),
        scatter=lognormal("k", median=MEDIAN_SMALL, cov=COV_SMALL, unit="N/m"),
    )
    return SimpleNamespace(
        name="isolator",
        path="isolator.toml",
        parameters=[k],
        watched=[Watched(KEY, "", "")],
        samples=samples,
        seed=4,
        method="qmc",
        limits=(Limit(KEY, LIMIT),),
        correlations=(),
        small_probability=method,
    )


@pytest.mark.parametrize(
    ("method", "label"), [(None, "importance sampling"), ("subset", "subset simulation")]
)
def test_the_isolator_s_1e4_probability_is_reached_in_fewer_than_1e4_evaluations(method, label):
    """P(T > 2) = 1.59e-4 (β = 3.6): the 1024 design samples see it rarely or never, so the kind runs
    the small-probability method (by default importance sampling at the FORM design point; subset
    simulation when asked), whose 95 % interval holds the closed form, in fewer than 1e4 evaluations
    of the model in all (design included). The findings stated again from the variants alone (in the
    order the database gives them) are the same."""
    study = _isolator(method)
    runner = ClosedFormRunner(study)
    k = kind("tolerance")
    ran = k.run(runner)
    exact = exact_probability(MEDIAN_SMALL, COV_SMALL)
    assert 1.5e-4 < exact < 1.7e-4
    assert len(runner.cache) == len(ran.variants) < 10_000
    found = k.findings(study, ran.variants).findings
    d = found["limits"][0]
    sampled = d["probability"]
    assert sampled["failures"] / 1024 < 1e-3 and sampled["high"] > exact  # sampling alone cannot say
    rare = d["small_probability"]
    assert rare["method"].startswith(label), rare
    assert rare["low"] <= exact <= rare["high"], (rare, exact)
    assert rare["cov"] < (0.1 if method is None else 1.0)  # subset simulation's is an upper bound
    # each distinct point asked for is one variant (FORM may ask for a point twice)
    assert 1024 < len(ran.variants) <= 1024 + rare["evaluations"] < 10_000
    assert rare["reliability_index"] == pytest.approx(3.6, abs=0.3)
    if method is None:
        # the most likely failure: the soft end of the failing interval of k
        assert rare["design_point"]["k"] == pytest.approx(failing_stiffness()[0], rel=1e-3)
        assert rare["importance"] == {"k": pytest.approx(1.0)}
    shuffled = ran.variants[::-1]
    again = k.findings(study, k.order(study, shuffled)).findings
    assert again == found
    # the distribution is the design's alone
    assert found["samples"] == 1024


def test_form_states_no_interval_and_off_runs_nothing_more():
    """FORM: the closed form within 1e-4 relative (the limit state is an interval of one lognormal
    input; FORM misses only the far end), its interval none; ``off``: the design alone."""
    study = _isolator("form")
    ran = kind("tolerance").run(ClosedFormRunner(study))
    rare = kind("tolerance").findings(study, ran.variants).findings["limits"][0]["small_probability"]
    assert rare["value"] == pytest.approx(exact_probability(MEDIAN_SMALL, COV_SMALL), rel=1e-4)
    assert rare["low"] == rare["high"] == rare["value"] and rare["interval_method"] == "none"
    assert rare["evaluations"] < 200
    off = _isolator("off")
    ran = kind("tolerance").run(ClosedFormRunner(off))
    assert len(ran.variants) == 1024
    assert "small_probability" not in kind("tolerance").findings(off, ran.variants).findings["limits"][0]


def test_a_frequent_limit_runs_no_small_probability_method():
    study = SimpleNamespace(**{**vars(_isolator(None)), "limits": (Limit(KEY, 1.02),)})  # P ≈ 0.4
    ran = kind("tolerance").run(ClosedFormRunner(study))
    assert len(ran.variants) == 1024
    d = kind("tolerance").findings(study, ran.variants).findings["limits"][0]
    assert d["probability"]["failures"] > 10 and "small_probability" not in d


def test_a_rare_limit_on_press_a_s_support_is_stored_resumed_and_stated_from_the_database(tmp_path):
    """Press A's bed moving more than 2.2 mm is rare (no sample of 64 beyond it): the kind's
    importance sampling evaluates its points through the batch engine and stores them after the
    design's; a rerun evaluates nothing; the database alone gives the same findings; the tables show
    the small probability with its method and interval, and rank the tolerances by FORM's importance
    factors."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.run import stored_result

    path = EXAMPLES / "studies" / "press_support_tolerance.toml"
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    data["outputs"][0]["limit"] = "2.2 mm"
    study = study_from_data(str(path), data).quick(64)
    db = str(tmp_path / "r.db")
    first = run_study(study, db)
    d = next(x for x in first.findings["limits"] if x["output"] == "displacement_max_m")
    assert d["probability"]["failures"] == 0
    rare = d["small_probability"]
    assert "importance sampling" in rare["method"] and 0 < rare["value"] < 1e-3, rare
    assert rare["low"] <= rare["value"] <= rare["high"] and rare["cov"] < 0.3
    assert 64 < first.count == first.evaluated <= 64 + rare["evaluations"]
    assert max(rare["importance"], key=rare["importance"].get) == "support stiffness"
    again = run_study(study, db)
    assert again.evaluated == 0 and again.reused == first.count
    assert again.findings == first.findings
    with ResultStore(db, read_only=True) as store:
        assert stored_result(store, study.name).findings == first.findings
    tables = kind("tolerance").tables(first)
    rare_table = next(t for t in tables if "small-probability method" in t.title)
    assert rare_table.rows[0][1].startswith("importance sampling")
    assert any("design point" in t.title for t in tables)
    import matplotlib

    matplotlib.use("Agg")
    for draw in kind("tolerance").plots(first).values():
        draw()


class FailingRunner(ClosedFormRunner):
    """The isolator that cannot be evaluated above 1.70 × the median stiffness (its model stops
    short of the failure set, which begins at 1.71 × the median): the design point cannot be reached."""

    def evaluate(self, X):
        out = super().evaluate(X)
        return [
            replace(v, outputs={KEY: math.nan}, status="failed", error="outside the model")
            if v.parameters["k"] > 1.70 * MEDIAN_SMALL
            else v
            for v in out
        ]


def test_a_small_probability_method_that_fails_says_why_and_the_sampled_estimate_stands():
    study = _isolator(None)
    ran = kind("tolerance").run(FailingRunner(study))
    found = kind("tolerance").findings(study, ran.variants).findings
    d = found["limits"][0]
    assert d["probability"]["failures"] == 0 and d["probability"]["high"] > 0
    assert d["small_probability"]["method"] == "importance"
    assert "error" in d["small_probability"] and "InternalException" not in d["small_probability"]["error"]


class BrokenStoreRunner(ClosedFormRunner):
    """A runner whose database fails once the design is stored: the run must stop, not record it."""

    def evaluate(self, X):
        if len(self.cache) >= 1024:
            raise OSError("disk full")
        return super().evaluate(X)


def test_a_database_error_during_the_small_probability_method_stops_the_run():
    with pytest.raises(OSError, match="disk full"):
        kind("tolerance").run(BrokenStoreRunner(_isolator(None)))
