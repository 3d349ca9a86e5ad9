"""The benchmarks' regression guard (``benchmarks/guard.py``) judges fabricated documents as it should.

No benchmark is run and nothing is timed: the comparison, the directions, the missing figures and the
recorded file are checked on JSON documents written here.
"""

from __future__ import annotations

import json
import sys

import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))
import guard
from guard import GUARDED, Key, compare, lookup, worse_by

LOWER = Key("modal_chain", "variant.ratio_variant_vs_bare_eigh", "lower", "variant / eigh")
HIGHER = Key("gear_dynamics", "ratio", "higher", "solve_ivp / speed_sweep")
RECORDED = {"modal_chain": {LOWER.path: 2.0}, "gear_dynamics": {HIGHER.path: 3.0}}


def _docs(variant_ratio, gear_ratio):
    return {
        "modal_chain": {"benchmark": "modal_chain", "variant": {"ratio_variant_vs_bare_eigh": variant_ratio}},
        "gear_dynamics": {"benchmark": "gear_dynamics", "ratio": gear_ratio},
    }


def _row(rows, key):
    (row,) = [r for r in rows if r.key == key]
    return row


@pytest.mark.parametrize(("factor", "fails"), [(1.25, True), (1.15, False), (0.5, False), (1.0, False)])
def test_a_time_ratio_fails_when_more_than_20_percent_worse(factor, fails):
    rows = compare(RECORDED, _docs(2.0 * factor, 3.0), keys=[LOWER, HIGHER])
    row = _row(rows, LOWER)
    assert row.failed is fails and row.status == ("worse" if fails else "ok")
    assert row.worse == pytest.approx(factor - 1.0)
    assert not _row(rows, HIGHER).failed


@pytest.mark.parametrize(("factor", "fails"), [(1 / 1.25, True), (1 / 1.15, False), (2.0, False)])
def test_a_speed_up_fails_when_it_falls_so_that_it_is_more_than_20_percent_worse(factor, fails):
    rows = compare(RECORDED, _docs(2.0, 3.0 * factor), keys=[LOWER, HIGHER])
    row = _row(rows, HIGHER)
    assert row.failed is fails
    assert row.worse == pytest.approx(1.0 / factor - 1.0)


def test_the_direction_decides_which_way_is_worse():
    assert worse_by(LOWER, 2.0, 2.5) == pytest.approx(0.25)  # a larger time ratio: worse
    assert worse_by(HIGHER, 2.0, 2.5) == pytest.approx(-0.2)  # a larger speed-up: better
    assert worse_by(HIGHER, 2.0, 0.0) == float("inf")
    with pytest.raises(ValueError, match="better must be"):
        worse_by(Key("x", "y", "sideways", ""), 1.0, 1.0)


def test_a_missing_benchmark_a_failed_one_and_a_missing_figure_are_reported():
    optional = Key("mechanism_cycle", "summary_bytes_per_variant", "lower", "bytes", optional=True)
    required = Key("mechanism_cycle", "ratio_vs_loop", "higher", "loop / mechdyn")
    docs = {"mechanism_cycle": {"benchmark": "mechanism_cycle", "ratio_vs_bare_dyads": 1.2}}
    rows = compare(
        {"mechanism_cycle": {"ratio_vs_loop": 400.0}, **RECORDED},
        docs,
        keys=[LOWER, HIGHER, optional, required],
        failed_benchmarks=["gear_dynamics"],
    )
    assert _row(rows, LOWER).status == "not run" and not _row(rows, LOWER).failed
    assert _row(rows, HIGHER).status == "benchmark failed" and _row(rows, HIGHER).failed
    assert _row(rows, optional).status == "not measured" and not _row(rows, optional).failed
    assert _row(rows, required).status == "not measured" and _row(rows, required).failed
    text = guard.table(rows)
    assert "not run" in text and "BENCHMARK FAILED" in text and "not measured" in text
    # a figure measured but never recorded is no failure either
    (row,) = compare({}, _docs(5.0, 1.0), keys=[LOWER])
    assert row.status == "no baseline" and not row.failed and row.current == 5.0


def test_several_runs_compare_each_figures_median():
    runs = {"modal_chain": [_docs(x, 0)["modal_chain"] for x in (2.3, 2.1, 9.0)]}
    (row,) = compare(RECORDED, runs, keys=[LOWER])
    assert row.current == 2.3 and row.status == "ok"  # an outlier run does not decide
    runs = {"gear_dynamics": [_docs(0, x)["gear_dynamics"] for x in (2.0, 2.9)]}
    (row,) = compare(RECORDED, runs, keys=[HIGHER])
    assert row.current == pytest.approx(2.45)


def test_paths_select_keys_list_items_by_field_or_index_and_bare_names_anywhere():
    doc = {
        "cases": [{"n": 10, "ratio_vs_dense": 0.5}, {"n": 1000, "ratio_vs_dense": 2.5}],
        "pages": {"1 DOF": {"ratio": 8.0}},
        "deep": {"inner": [{"summary_bytes_per_variant": 900}]},
        "flag": True,
    }
    assert lookup(doc, "cases[n=1000].ratio_vs_dense") == 2.5
    assert lookup(doc, "cases[0].ratio_vs_dense") == 0.5
    assert lookup(doc, "cases[-1].ratio_vs_dense") == 2.5
    assert lookup(doc, "pages.1 DOF.ratio") == 8.0
    assert lookup(doc, "summary_bytes_per_variant") == 900.0
    for absent in (
        "cases[n=7].ratio_vs_dense",
        "cases[5].ratio_vs_dense",
        "pages.2 DOF.ratio",
        "flag",
        "nope",
    ):
        assert lookup(doc, absent) is None


def test_the_guarded_list_is_explicit_and_every_key_is_well_formed():
    assert len({(k.benchmark, k.path) for k in GUARDED}) == len(GUARDED)
    for k in GUARDED:
        assert k.better in ("lower", "higher"), k
        assert (ROOT / "benchmarks" / f"{k.benchmark}.py").exists(), k
    names = {k.path for k in GUARDED if k.benchmark == "mechanism_cycle"}
    assert {"ratio_vs_bare_dyads", "summary_variant_cycles_per_s", "summary_bytes_per_variant"} <= names
    assert all(k.optional for k in GUARDED if k.path.startswith("summary_"))


def test_the_recorded_baseline_holds_a_figure_for_each_guarded_key_and_its_commit():
    doc = json.loads((ROOT / "benchmarks" / "baseline.json").read_text())
    assert doc["recorded"]["commit"] and doc["recorded"]["date"]
    assert doc["tolerance"] == pytest.approx(0.2)
    figures = doc["figures"]
    missing = [(k.benchmark, k.path) for k in GUARDED if k.path not in figures.get(k.benchmark, {})]
    assert not [m for m in missing if not any(k.optional for k in GUARDED if (k.benchmark, k.path) == m)]
    assert all(v > 0 for bench in figures.values() for v in bench.values())


def test_record_writes_the_figures_and_keeps_the_ones_not_measured(tmp_path):
    path = tmp_path / "baseline.json"
    path.write_text(json.dumps({"figures": {"gear_dynamics": {"ratio": 3.0}}}))
    rows = compare({}, _docs(2.2, 1.0), keys=[LOWER])
    doc = guard.record(rows, path, 0.2)
    again = json.loads(path.read_text())
    assert again == doc
    assert again["figures"] == {"gear_dynamics": {"ratio": 3.0}, "modal_chain": {LOWER.path: 2.2}}
    assert again["tolerance"] == 0.2 and again["recorded"]["date"]


def test_the_command_exits_non_zero_on_a_regression(tmp_path, monkeypatch):
    baseline = tmp_path / "baseline.json"
    baseline.write_text(json.dumps({"tolerance": 0.2, "figures": RECORDED}))
    monkeypatch.setattr(guard, "GUARDED", (LOWER,))
    monkeypatch.setattr(guard, "run_benchmark", lambda name: (_docs(2.5, 3.0)[name], ""))
    assert guard.main(["--baseline", str(baseline)]) == 1
    monkeypatch.setattr(guard, "run_benchmark", lambda name: (_docs(2.2, 3.0)[name], ""))
    assert guard.main(["--baseline", str(baseline)]) == 0
    monkeypatch.setattr(guard, "run_benchmark", lambda name: (None, "exit status 1"))
    assert guard.main(["--baseline", str(baseline)]) == 1
