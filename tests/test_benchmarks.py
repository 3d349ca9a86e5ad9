"""The benchmarks run and their baselines agree with mechdyn (no timing is asserted)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))
import modal_chain
import periodic_response as periodic_benchmark

SCRIPTS = sorted(
    [*(ROOT / "benchmarks").glob("*.py"), *(ROOT / "docs").rglob("*.py"), *(ROOT / "examples").rglob("*.py")]
)


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_mechdyn_name_a_script_imports_is_there(script):
    """The benchmarks, the documentation's scripts and the examples import names of mechdyn that
    exist (a name moved to another module is found here, by default, not when the heavy step first
    runs the script)."""
    import ast
    import importlib

    missing = []
    for node in ast.walk(ast.parse(script.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "mechdyn":
            module = importlib.import_module(node.module)
            for alias in node.names:
                if alias.name != "*" and not hasattr(module, alias.name):
                    try:
                        importlib.import_module(f"{node.module}.{alias.name}")
                    except ModuleNotFoundError:
                        missing.append(f"{node.module}.{alias.name}")
    assert not missing, missing


def test_modal_chain_small_case_agrees_with_its_baselines():
    case = modal_chain.run_case(60, None)
    assert case["max_rel_diff_vs_dense"] < 1e-10
    assert case["max_rel_diff_vs_opentorsion"] < 1e-10
    case = modal_chain.run_case(3000, 5)
    assert case["solver"] == "banded" and case["max_rel_diff_vs_sparse"] < 1e-8


@pytest.mark.slow
def test_modal_chain_quick_run():
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "modal_chain.py"), "--quick", "--json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    doc = json.loads(out.stdout)
    assert [c["n"] for c in doc["cases"]] == [10, 100, 1000, 100_000]
    for c in doc["cases"]:
        for key, value in c.items():
            if key.startswith("max_rel_diff"):
                assert value < 1e-6, (c["n"], key, value)


def test_periodic_response_baseline_reaches_the_frequency_domain_steady_state():
    import mechdyn
    from mechdyn.support import periodic_response

    spec = mechdyn.load(ROOT / "examples" / "press_on_support.toml").settings
    q, periods = periodic_benchmark.integrate_to_steady_state(spec.machine, spec.load, 90)
    fd = periodic_response(spec.machine, spec.load, 90)
    assert periods > 2
    assert np.abs(q - fd.displacement).max() < 1e-6 * np.abs(fd.displacement).max()


def test_small_model_baselines_agree_with_mechdyn():
    import small_model

    m = small_model.modal_case(quick=True)
    assert m["max_rel_diff_vs_bare"] < 1e-12
    f = small_model.fourbar_case(quick=True)
    # the bare loop-equation solution is an independent reference for the four-bar's torque
    assert f["max_rel_diff_torque_vs_bare"] < 1e-10


@pytest.mark.slow  # CI's heavy step (issue 48: the test command's minutes)
def test_frf_speed_baselines_agree_with_mechdyn():
    import frf_speed

    c = frf_speed.frf_case(100, quick=True)
    assert c["method"] == "modal superposition over all 100 modes"
    assert c["max_rel_diff_vs_direct"] < 1e-9
    assert c["max_rel_diff_vs_opentorsion"] < 1e-8
    # the textbook sum treats eigh's rigid-body λ (about 1e-10, not 0) as a mode: 1e-7 at 1 Hz
    assert c["max_rel_diff_vs_plain_superposition"] < 1e-6
    block = frf_speed.study_block_case(quick=True)
    assert block["max_rel_diff_vs_bare"] < 1e-12
    assert block["max_rel_diff_vs_opentorsion"] < 1e-10


@pytest.mark.slow
def test_frf_speed_quick_run():
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "frf_speed.py"), "--quick", "--json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    doc = json.loads(out.stdout)
    assert [c["disks"] for c in doc["frf"]] == [10, 100, 400]
    assert all(c["method"].startswith("modal superposition") for c in doc["frf"])
    assert doc["study_block"]["variants"] == 1000


@pytest.mark.slow  # 30 s of integration at equal accuracy: .ci/run's heavy step
def test_gear_dynamics_quick_run_holds_both_sides_to_the_same_accuracy():
    # both K_v within the target of a reference that mechdyn's Magnus shooting confirms far below it
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "gear_dynamics.py"), "--quick", "--json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=600,  # a hang guard: the quick run takes about 25 s on an idle machine
    )
    doc = json.loads(out.stdout)
    assert doc["benchmark"] == "gear_dynamics" and doc["quick"] is True and doc["speeds"] == 2
    target = doc["target_rel_error"]
    assert doc["reference"]["max_rel_diff_vs_magnus_shooting"] < target / 100
    assert 0 < doc["speed_sweep"]["max_rel_error"] <= target
    assert 0 < doc["solve_ivp_to_steady_state"]["max_rel_error"] <= target
    assert doc["within_target"] and doc["ratio"] > 0


@pytest.mark.parametrize("name", ["model_loading", pytest.param("frf_memory", marks=pytest.mark.slow)])
def test_spine_benchmarks_run_quick_and_print_json(name):
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / f"{name}.py"), "--quick", "--json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=1200,  # a hang guard: a quick benchmark takes under a minute on an idle machine
    )
    doc = json.loads(out.stdout)
    assert doc["benchmark"] == name and doc["quick"] is True
    if name == "frf_memory":
        # memory grows with the result (frequencies × disks), not with frequencies × disks²
        assert doc["peak_growth_bytes_per_frequency"] < doc["stacked_growth_bytes_per_frequency"] / 4
    else:
        assert doc["disks"] == 2000 and doc["solver"] == "banded"


@pytest.mark.slow
def test_study_optimum_quick_run():
    # the polished optimum holds the stroke in every box, is a first-order point, and goes farther
    # than the plain sampler given the same evaluations
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "study_optimum.py"), "--quick", "--json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=1200,
    )
    doc = json.loads(out.stdout)
    assert doc["benchmark"] == "study_optimum" and [b["box"] for b in doc["boxes"]] == ["±10 %", "±30 %"]
    for b in doc["boxes"]:
        assert b["constraints_hold"] and b["optimality"] < 1e-6
        assert b["reduction_percent"] > (b["plain_sampler"]["reduction_percent"] or 0.0)


@pytest.mark.slow
def test_the_plots_benchmark_times_every_quick_example_with_and_without_its_plots():
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "plots.py"), "--quick", "--json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=1200,  # a hang guard
    )
    doc = json.loads(out.stdout)
    assert doc["benchmark"] == "plots" and len(doc["examples"]) == 3
    for r in doc["examples"]:
        assert (
            r["plots"] >= 1
            and r["seconds_without_plots"] > 0
            and r["seconds_with_plots"] > 0
            and r["ratio"] > 0  # the median of the pairs' ratios, not the ratio of the medians
            and r["plot_seconds"] == pytest.approx(r["seconds_with_plots"] - r["seconds_without_plots"])
        )


@pytest.mark.slow
def test_the_dashboard_benchmark_times_every_page_of_a_large_study_against_a_static_file():
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "dashboard.py"), "--quick", "--json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=1200,  # a hang guard
    )
    doc = json.loads(out.stdout)
    assert doc["benchmark"] == "dashboard" and doc["variants"] == 10240
    assert doc["baseline_static_file"]["bytes"] > 1e6
    for page in doc["pages"].values():
        assert page["status"] == 200 and page["seconds"] > 0 and page["ratio_to_static_file"] > 0


def test_mechanism_cycle_bare_dyad_form_agrees_with_mechdyn_to_round_off():
    import mechanism_cycle

    import mechdyn
    from mechdyn.mechanism import inverse_dynamics

    mech = mechdyn.load(ROOT / "examples" / "press_link_drive.toml").model
    d = inverse_dynamics(mech, 360)
    torque = mechanism_cycle.bare_dyads(mech, d.kinematics.crank_angle)
    # the bare dyad-by-dyad form is an independent reference: its own dyads, loop derivatives and a
    # batched 15 × 15 Newton–Euler solve
    assert np.abs(torque - d.driving_torque).max() < 1e-12 * np.abs(d.driving_torque).max()
