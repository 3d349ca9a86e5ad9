"""Design studies: parameters by path, the batched and one-by-one evaluations, every kind, the
results database (resume, kill -9, two processes on PostgreSQL), Dask, and the command line."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.io.modelfile import read
from mechdyn.store import ResultStore
from mechdyn.studies import (
    Evaluator,
    ModelTree,
    Parameter,
    StudyError,
    load_studies,
    load_study,
    recompute,
    run_study,
)
from mechdyn.studies.cells import signed
from mechdyn.studies.kinds.sweeps import RHO_DIGITS
from mechdyn.studies.paths import PathError
from mechdyn.studies.storage import StudyStore
from mechdyn.support.model import MountedMachine
from mechdyn.support.response import periodic_response

STUDIES = EXAMPLES / "studies"


def write_study(tmp_path: Path, body: str, name: str = "study.toml") -> Path:
    """A study file beside copies of the press models (so that relative paths resolve)."""
    for f in ("press_on_support.toml", "press_link_drive.toml", "slider_crank.toml", "fourbar.toml"):
        (tmp_path / f).write_text((EXAMPLES / f).read_text())
    p = tmp_path / name
    p.write_text(textwrap.dedent(body))
    return p


# -- parameters by path ------------------------------------------------------------------------


def test_paths_follow_the_file_and_its_references():
    tree = ModelTree(read(EXAMPLES / "press_on_support.toml"))
    paths = tree.paths()
    assert {"support.stiffness", "machine.mass", "excitation.mechanism.points.C.x"} <= set(paths)
    assert "excitation.mechanism.bodies.slide.mass" in paths
    (loc,) = tree.resolve("excitation.mechanism.bodies.slide.mass")
    assert loc.files == (str(EXAMPLES / "press_link_drive.toml"),) and loc.keys == ("bodies", 4, "mass")
    assert len(tree.resolve("excitation.mechanism.points.C")) == 2
    drivetrain = ModelTree(read(EXAMPLES / "turret_milling.toml"))
    (disk,) = drivetrain.resolve("disks.3.inertia")
    assert disk.keys == ("disks", 2, "inertia")


@pytest.mark.parametrize("name", ["press_on_mounts.toml", "press_on_pads.toml", "press_on_support.toml"])
def test_every_listed_path_resolves_and_table_rows_are_listed_with_their_star_form(name):
    # `mechdyn study --paths` lists the `*` form (every row at once) before the rows, as the docs
    # recommend it for mounts; each listed path names at least one value, the star form one per row
    tree = ModelTree(read(EXAMPLES / name))
    paths = tree.paths()
    assert len(paths) == len(set(paths))
    for path in paths:
        assert tree.resolve(path), path
    if name == "press_on_mounts.toml":
        assert paths.index("mounts.*.stiffness") < paths.index("mounts.front left.stiffness")
        assert len(tree.resolve("mounts.*.stiffness.z")) == 4
    if name == "press_on_pads.toml":
        assert "mounts.*.mount.pad.thickness" in paths


def test_an_unknown_path_lists_the_valid_paths_nearby():
    tree = ModelTree(read(EXAMPLES / "press_on_support.toml"))
    with pytest.raises(PathError, match=r"no value at 'support.stifness'.*support.stiffness"):
        tree.resolve("support.stifness")


def test_a_point_is_one_parameter_per_coordinate_and_a_wildcard_moves_together():
    tree = ModelTree(read(EXAMPLES / "press_on_support.toml"))
    cx, cy = Parameter.from_spec(tree, "excitation.mechanism.points.C", range="±10 %")
    assert cx.name.endswith("C.x") and cy.name.endswith("C.y")
    assert cx.low == pytest.approx(0.9 * 0.576357773) and cy.high == pytest.approx(0.9 * -2.079683037)
    pads = ModelTree(read(EXAMPLES / "press_on_pads.toml"))
    (t,) = Parameter.from_spec(pads, "mounts.*.mount.pad.thickness", levels=["-10 %"])
    assert len(t.locations) == 4
    assert t.levels == pytest.approx([0.9 * t.base])


def test_a_variant_is_new_and_the_base_is_untouched():
    source = read(EXAMPLES / "press_on_support.toml")
    before = json.dumps(source.data, sort_keys=True)
    tree = ModelTree(source)
    (k,) = Parameter.from_spec(tree, "support.stiffness", range="±10 %")
    (m,) = Parameter.from_spec(tree, "excitation.mechanism.bodies.slide.mass", range="±10 %")
    v = mechdyn.io.modelfile.load_source(tree.variant({**k.file_values(4e8), **m.file_values(1.0e5)}))
    assert v.model.mounts[0].stiffness[2] == pytest.approx(4e8)
    assert v.settings.excitation.mechanism.bodies[4].mass == pytest.approx(1.0e5)
    assert json.dumps(source.data, sort_keys=True) == before
    assert mechdyn.load(EXAMPLES / "press_on_support.toml").model.mounts[0].stiffness[2] == 4.5e8


def test_ranges_with_the_wrong_unit_say_which_unit_they_need():
    tree = ModelTree(read(EXAMPLES / "press_on_support.toml"))
    with pytest.raises(StudyError, match=r"needs its unit.*e.g. \"1 N/m\""):
        Parameter.from_spec(tree, "support.stiffness", range=[1, 2])
    with pytest.raises(StudyError, match=r"range bound '1 m'.*quantity in N/m"):
        Parameter.from_spec(tree, "support.stiffness", range=["1 m", "2 m"])
    with pytest.raises(StudyError, match="relative range is written"):
        Parameter.from_spec(tree, "support.stiffness", range="10 %")


# -- evaluation: one compiled batch and one by one give the same numbers -----------------------


def _random_rows(params, n, seed=0):
    rng = np.random.default_rng(seed)
    lo = np.array([p.low for p in params])
    hi = np.array([p.high for p in params])
    return lo + rng.random((n, len(params))) * (hi - lo)


@pytest.mark.parametrize(
    "paths",
    [
        (
            "excitation.mechanism.points.C",
            "support.stiffness",
            "support.damping_ratio",
            "machine.mass",
            "excitation.mechanism.bodies.slide.mass",
        ),
        ("support.stiffness", "machine.mass"),  # the file's damping ratio is kept: c = 2ζ√(km)
    ],
)
def test_the_support_batch_equals_the_support_analysis_variant_by_variant(paths):
    source = read(EXAMPLES / "press_on_support.toml")
    tree = ModelTree(source)
    params = [q for p in paths for q in Parameter.from_spec(tree, p, range="±10 %")]
    outputs = [
        "transmitted_force_range_N",
        "transmitted_force_min_N",
        "displacement_max_m",
        "inertia_force_range_N",
        "excitation.stroke_m",
        "excitation.inertia_force_fluctuation_N",
    ]
    X = _random_rows(params, 5)
    batch = Evaluator(source, "support", params, outputs, {"cycles": 1})
    fast = batch(X)
    assert batch.batch  # the compiled path took them
    slow = Evaluator(source, "support", params, outputs, {"cycles": 1}, batch=False)(X)
    for a, b in zip(fast, slow, strict=True):
        assert a.status == b.status == "ok"
        for k in outputs:
            assert a.outputs[k] == pytest.approx(b.outputs[k], rel=1e-12), k


def test_the_support_batch_halves_the_nyquist_term_as_the_single_path_does(tmp_path):
    """At 12 angles per cycle the Nyquist harmonic of the shaking force carries weight: counted twice,
    the batch's transmitted force was 1.7 % off the single-design path."""
    text = (EXAMPLES / "press_on_support.toml").read_text()
    press = EXAMPLES / "press_link_drive.toml"
    text = text.replace('mechanism = "press_link_drive.toml"', f'mechanism = "{press}"\nangles = 12')
    path = tmp_path / "coarse.toml"
    path.write_text(text)
    source = read(path)
    params = Parameter.from_spec(ModelTree(source), "support.stiffness", range="±30 %")
    outputs = ["transmitted_force_range_N", "transmitted_force_max_N", "displacement_max_m"]
    X = np.array([[params[0].low], [params[0].base], [params[0].high]])
    batch = Evaluator(source, "support", params, outputs, {"cycles": 1})
    fast = batch(X)
    assert batch.batch
    slow = Evaluator(source, "support", params, outputs, {"cycles": 1}, batch=False)(X)
    for a, b in zip(fast, slow, strict=True):
        for k in outputs:
            assert a.outputs[k] == pytest.approx(b.outputs[k], rel=1e-10), k


def test_a_linkage_that_does_not_assemble_fails_alone_with_its_reason():
    source = read(EXAMPLES / "fourbar.toml")
    tree = ModelTree(source)
    (bx,) = [p for p in Parameter.from_spec(tree, "points.B", range="±10 %") if p.name.endswith(".x")]
    rows = np.array([[bx.base], [bx.base * 40.0], [bx.base * 1.05]])
    outs = ["driving_torque_peak_Nm"]
    fast = Evaluator(source, "mechanism", [bx], outs)(rows)
    slow = Evaluator(source, "mechanism", [bx], outs, batch=False)(rows)
    assert [e.status for e in fast] == [e.status for e in slow] == ["ok", "failed", "ok"]
    assert "assembl" in fast[1].error.lower() or "reach" in fast[1].error.lower()
    assert fast[2].outputs["driving_torque_peak_Nm"] == pytest.approx(
        slow[2].outputs["driving_torque_peak_Nm"], rel=1e-12
    )


# -- the kinds ---------------------------------------------------------------------------------


def test_the_support_influence_study_against_the_closed_form_response(tmp_path):
    """Each variant against its own steady state computed directly: a softer support of the same
    damping ratio (c = 2ζ√(km)), and a smaller damping ratio at the same stiffness."""
    study = load_study(STUDIES / "press_support_influence.toml")
    result = run_study(study, str(tmp_path / "r.db"))
    assert result.failed == 0 and len(result.variants) == 7
    loaded = mechdyn.load(EXAMPLES / "press_on_support.toml")
    m, load = loaded.model.body.mass, loaded.settings.load
    for e in result.findings["effects"]:
        k, zeta = 4.5e8, 0.05
        factor = 1 + e["level_percent"] / 100
        if e["parameter"] == "support.stiffness":
            k *= factor
        else:
            zeta *= factor
        direct = periodic_response(MountedMachine.single_dof(m, k, zeta), load).summary()
        assert e["outputs"]["transmitted_force_range_N"]["value"] == pytest.approx(
            direct["transmitted_force_range_N"], rel=1e-12
        )
        assert e["outputs"]["displacement_max_m"]["value"] == pytest.approx(
            direct["displacement_max_m"], rel=1e-12
        )
    # published: softer or less damped supports change the floor force only a little
    changes = [
        abs(e["outputs"]["transmitted_force_range_N"]["change_percent"]) for e in result.findings["effects"]
    ]
    assert max(changes) < 2.0
    # a change is relative to the base value itself: the smallest floor force (negative) that grows
    # in size on a softer support reads as growing
    base_min = result.findings["base"]["transmitted_force_min_N"]
    softest = next(e for e in result.findings["effects"] if e["level_percent"] == pytest.approx(-30))
    o = softest["outputs"]["transmitted_force_min_N"]
    assert base_min < 0 and o["value"] < base_min and o["change_percent"] > 0
    assert o["change_percent"] == pytest.approx(100 * (o["value"] / base_min - 1))
    # the tornado: one bar per parameter between its two ends, each end labelled with its level
    import matplotlib

    matplotlib.use("Agg")
    ax = result.plots()["tornado_transmitted_force_min_N.png"]()
    assert [t.get_text() for t in ax.get_yticklabels()] == ["support.damping_ratio", "support.stiffness"]
    notes = [t.get_text().strip() for t in ax.texts]
    assert len(notes) == 4 and any(n.startswith("-30 % (+") for n in notes)


def test_sobol_indices_of_an_output_that_one_parameter_sets(tmp_path):
    """The machine's mass output is the mass parameter itself: S1 = ST = 1 for it, 0 for the rest."""
    path = write_study(
        tmp_path,
        """
        [study]
        name = "sobol-check"
        kind = "sobol"
        model = "press_on_support.toml"
        analysis = "support"
        samples = 64

        [[parameters]]
        path = "machine.mass"
        range = "±20 %"

        [[parameters]]
        path = "support.stiffness"
        range = "±20 %"

        [[outputs]]
        output = "machine_mass_kg"

        [[outputs]]
        output = "displacement_max_m"
        """,
    )
    result = run_study(load_study(path), str(tmp_path / "r.db"))
    assert len(result.variants) == 64 * 4
    mass = result.findings["indices"]["machine_mass_kg"]
    assert mass["machine.mass"]["S1"] == pytest.approx(1.0, abs=0.05)
    assert mass["machine.mass"]["ST"] == pytest.approx(1.0, abs=0.05)
    assert mass["support.stiffness"]["ST"] == pytest.approx(0.0, abs=1e-12)
    # quasi-static: the bed displacement is F/k, set by the stiffness, not the mass
    z = result.findings["indices"]["displacement_max_m"]
    assert z["support.stiffness"]["ST"] > 0.99 and z["machine.mass"]["ST"] < 0.01


def test_sobol_findings_of_the_ishigami_function_are_its_closed_form_indices():
    """The Sobol kind's findings on the Ishigami function, Y = sin x₁ + a sin² x₂ + b x₃⁴ sin x₁ over
    [−π, π]³ (a = 7, b = 0.1; Ishigami & Homma 1990; closed-form indices in Saltelli et al., *Global
    Sensitivity Analysis: The Primer*, 2008, §4.9): x₁ and x₃ interact, so first-order and total
    indices differ by 0.24 for each and cannot be swapped unnoticed. The study's evaluator is a
    stand-in that computes Y; the sampling, the estimator and the findings are the kind's own."""
    from types import SimpleNamespace

    from mechdyn.studies import kinds

    a, b, pi = 7.0, 0.1, math.pi
    V1, V2, V13 = b * pi**4 / 5 + b**2 * pi**8 / 50 + 0.5, a**2 / 8, 8 * b**2 * pi**8 / 225
    V = V1 + V2 + V13
    exact = {
        "x1": {"S1": V1 / V, "ST": (V1 + V13) / V},
        "x2": {"S1": V2 / V, "ST": V2 / V},
        "x3": {"S1": 0.0, "ST": V13 / V},
    }
    assert exact["x1"]["S1"] == pytest.approx(0.3139, abs=1e-4) and exact["x3"]["ST"] == pytest.approx(
        0.2437, abs=1e-4
    )

    def evaluate(X):
        x1, x2, x3 = np.asarray(X).T
        y = np.sin(x1) + a * np.sin(x2) ** 2 + b * x3**4 * np.sin(x1)
        return [SimpleNamespace(status="ok", outputs={"y": float(v)}) for v in y]

    study = SimpleNamespace(
        name="ishigami",
        path=None,
        samples=4096,
        seed=11,
        parameters=[SimpleNamespace(name=n, low=-pi, high=pi) for n in ("x1", "x2", "x3")],
        watched=[SimpleNamespace(key="y")],
    )
    sobol = kinds.kind("sobol")
    X = sobol.design(study)
    assert X.shape == (4096 * 5, 3)
    got = sobol.findings(study, evaluate(X)).findings["indices"]["y"]
    for name, indices in exact.items():
        for which, value in indices.items():
            assert got[name][which] == pytest.approx(value, abs=0.02), (name, which)


def test_synthesis_finds_the_crank_of_a_stroke(tmp_path):
    """A slider-crank's stroke is twice its crank: the fit must find r = stroke / 2."""
    loaded = mechdyn.load(EXAMPLES / "slider_crank.toml")
    r0 = math.dist(loaded.model.points["O"], loaded.model.points["A"])
    path = write_study(
        tmp_path,
        f"""
        [study]
        name = "stroke-fit"
        kind = "synthesis"
        model = "slider_crank.toml"
        analysis = "mechanism"
        samples = 30
        population = 6
        options = {{ angles = 72 }}

        [[parameters]]
        path = "points.A.x"
        range = "±30 %"

        [[targets]]
        output = "stroke_m"
        equals = "{2 * r0 * 1.2 * 1000:.6f} mm"
        tolerance = "0.01 mm"
        """,
    )
    result = run_study(load_study(path), str(tmp_path / "r.db"))
    best = result.findings["best"]
    assert best["outputs"]["stroke_m"] == pytest.approx(2 * r0 * 1.2, abs=2e-5)


def test_optimization_keeps_its_constraint_and_finds_the_stiff_end(tmp_path):
    path = write_study(
        tmp_path,
        """
        [study]
        name = "opt-check"
        kind = "optimize"
        model = "press_on_support.toml"
        analysis = "support"
        samples = 24
        batch = 8

        [[parameters]]
        path = "support.stiffness"
        range = "±30 %"

        [[parameters]]
        path = "support.damping_ratio"
        range = "±30 %"

        [[objectives]]
        output = "displacement_max_m"
        goal = "minimize"

        [[constraints]]
        output = "transmitted_force_range_N"
        max = "86 tonf"
        """,
    )
    db = str(tmp_path / "r.db")
    result = run_study(load_study(path), db)
    best = result.findings["best"]
    assert all(c["holds"] for c in best["constraints"])
    # z ≈ F/k: the stiffest support found is near the top of the range
    assert best["parameters"]["support.stiffness"] > 1.1 * 4.5e8
    assert result.findings["trials"] == 24
    again = run_study(load_study(path), db)
    assert again.findings["trials"] == 24 and again.evaluated == 0


def test_a_pareto_front_is_not_dominated(tmp_path):
    path = write_study(
        tmp_path,
        """
        [study]
        name = "pareto-check"
        kind = "optimize"
        model = "fourbar.toml"
        analysis = "mechanism"
        samples = 24
        options = { angles = 72 }

        [[parameters]]
        path = "points.B.x"
        range = "±10 %"

        [[parameters]]
        path = "points.O4.y"
        range = ["-5 mm", "5 mm"]

        [[objectives]]
        output = "driving_torque_peak_Nm"

        [[objectives]]
        output = "shaking_force_max_N"
        """,
    )
    result = run_study(load_study(path), str(tmp_path / "r.db"))
    front = result.findings["pareto_front"]
    assert front
    keys = ["driving_torque_peak_Nm", "shaking_force_max_N"]
    pts = np.array([[d["outputs"][k] for k in keys] for d in front])
    ok = np.array([[v.outputs[k] for k in keys] for v in result.variants if v.status == "ok"])
    for p in pts:
        assert not np.any(np.all(ok <= p, axis=1) & np.any(ok < p, axis=1))
    # its ends are the front's best in each objective; its knee is the design nearest the ideal point
    # with each objective scaled to its range on the front (computed here from the front itself)
    ids = [d["variant"] for d in front]
    for j, k in enumerate(keys):
        assert result.findings["ends"][k] == ids[int(np.argmin(pts[:, j]))]
    scaled = (pts - pts.min(axis=0)) / np.where(np.ptp(pts, axis=0) > 0, np.ptp(pts, axis=0), 1.0)
    assert result.findings["knee"] == ids[int(np.argmin(np.hypot(*scaled.T)))]
    (table,) = [t for t in result.tables() if "Pareto front" in t.title]
    roles = {row[1]: row[0] for row in table.rows}
    assert "knee" in roles[result.findings["knee"]]
    assert f"best {keys[0]}" in roles[result.findings["ends"][keys[0]]]
    import matplotlib

    matplotlib.use("Agg")
    ax = result.plots()["pareto.png"]()
    assert any(line.get_label().startswith("knee (variant") for line in ax.get_lines())


# -- the results database: resume, kill -9, two processes ---------------------------------------


def test_running_a_study_again_reuses_every_variant(tmp_path):
    study = load_study(STUDIES / "press_support_influence.toml")
    db = str(tmp_path / "r.db")
    first = run_study(study, db)
    second = run_study(study, db)
    assert (first.evaluated, first.reused) == (7, 0)
    assert (second.evaluated, second.reused) == (0, 7)
    assert [v.outputs for v in first.variants] == [v.outputs for v in second.variants]
    with ResultStore(db) as store:
        vs = StudyStore(store).variants(study.name, curves=True)
    assert len(vs) == 7 and all(v.curves for v in vs)  # 7 ≤ [study] curves: every variant's curves


def test_a_stored_variant_is_recomputed_exactly_from_its_stored_inputs(tmp_path):
    study = load_study(STUDIES / "press_support_influence.toml")
    db = str(tmp_path / "r.db")
    run_study(study, db)
    with ResultStore(db) as store:
        variants = StudyStore(store).variants(study.name)
        for v in variants:
            assert recompute(store, v.id).outputs == v.outputs  # bit for bit, on the study's path
            one_by_one = recompute(store, v.id, batch=False).outputs
            assert one_by_one == pytest.approx(v.outputs, rel=1e-12)


KILL_STUDY = """
[study]
name = "kill-check"
kind = "lhs"
model = "press_on_support.toml"
analysis = "support"
samples = 400
chunk = 20
curves = 0

[[parameters]]
path = "support.stiffness"
range = "±30 %"

[[parameters]]
path = "excitation.mechanism.points.D.y"
range = "±2 %"

[[outputs]]
output = "transmitted_force_range_N"
"""


@pytest.mark.slow  # CI's heavy step (issue 48: the test command's minutes)
def test_kill_9_loses_nothing_and_the_finished_study_equals_an_uninterrupted_one(tmp_path):
    path = write_study(tmp_path, KILL_STUDY)
    killed, clean = str(tmp_path / "killed.db"), str(tmp_path / "clean.db")
    code = (
        "import sys, numpy as np\n"
        "from mechdyn.studies import load_study\nfrom mechdyn.studies import evaluate\n"
        "orig = evaluate.Evaluator.__call__\n"
        "def slow(self, X, curves=False):\n"
        "    import time; time.sleep(0.05); return orig(self, X, curves)\n"
        "evaluate.Evaluator.__call__ = slow\n"
        "from mechdyn.studies import run_study\n"
        f"run_study(load_study({str(path)!r}), {killed!r})\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=tmp_path)
    deadline = time.time() + 120
    stored = 0
    while time.time() < deadline and proc.poll() is None:
        time.sleep(0.2)
        if Path(killed).exists():
            try:
                with ResultStore(killed) as store:
                    stored = len(StudyStore(store).variants("kill-check"))
            except Exception:
                stored = 0
            if stored >= 60:
                break
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert 0 < stored < 401, "the study was not interrupted in the middle"
    resumed = run_study(load_study(path), killed)
    assert resumed.reused >= stored and resumed.evaluated + resumed.reused == 401
    uninterrupted = run_study(load_study(path), clean)
    with ResultStore(killed) as a, ResultStore(clean) as b:
        va, vb = StudyStore(a).variants("kill-check"), StudyStore(b).variants("kill-check")
    assert len(va) == len({v.key for v in va}) == 401
    by_key = {v.key: v for v in vb}
    for v in va:
        assert v.outputs == by_key[v.key].outputs
    assert [v.outputs for v in resumed.variants] == [v.outputs for v in uninterrupted.variants]


# -- Dask ----------------------------------------------------------------------------------------


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow  # a real Dask cluster started (over 10 s): CI's heavy step
def test_a_study_on_a_real_dask_scheduler_equals_the_in_process_run(tmp_path):
    path = write_study(tmp_path, KILL_STUDY.replace("samples = 400", "samples = 60"))
    port = _free_port()
    dask = Path(sys.executable).with_name("dask")
    cmd = [str(dask)] if dask.exists() else [sys.executable, "-m", "distributed.cli.dask_scheduler"]
    scheduler = subprocess.Popen(
        [*cmd, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"]
        if dask.exists()
        else [*cmd, "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    address = f"tcp://127.0.0.1:{port}"
    worker = subprocess.Popen(
        [str(dask), "worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        cwd=tmp_path,
    )
    try:
        from distributed import Client

        with Client(address, timeout=60) as c:
            c.wait_for_workers(1, timeout=60)
        on_dask = run_study(load_study(path), str(tmp_path / "dask.db"), dask=address)
    finally:
        worker.terminate()
        scheduler.terminate()
        worker.wait(30)
        scheduler.wait(30)
    in_process = run_study(load_study(path), str(tmp_path / "local.db"))
    assert on_dask.evaluated == in_process.evaluated == 61
    assert [v.outputs for v in on_dask.variants] == [v.outputs for v in in_process.variants]


# -- the command line and the study files --------------------------------------------------------


def test_the_study_command_prints_json_and_lists_exports_and_compares(tmp_path, capsys):
    from mechdyn.cli.main import main

    db = str(tmp_path / "r.db")
    assert (
        main(
            [
                "study",
                str(STUDIES / "press_support_influence.toml"),
                "--db",
                db,
                "--json",
                "--plots",
                str(tmp_path / "p"),
            ]
        )
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert {"study", "kind", "evaluated", "reused", "failed", "effects"} <= set(doc)
    assert doc["evaluated"] == 7 and doc["failed"] == 0
    assert (tmp_path / "p" / "tornado_transmitted_force_range_N.png").stat().st_size > 10_000
    assert (tmp_path / "p" / "curves_floor_force_z_N.png").stat().st_size > 10_000  # 7 variants overlaid
    assert main(["results", "list", "--study", "press-support-influence", "--db", db, "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert len(listed) == 7 and {"id", "status", "parameters", "outputs"} <= set(listed[0])
    assert listed[1]["parameters"]["support.stiffness"] == pytest.approx(0.9 * 4.5e8)
    ids = [str(listed[0]["id"]), str(listed[3]["id"])]
    assert main(["results", "compare", *ids, "--db", db, "--plots", str(tmp_path / "c")]) == 0
    out = capsys.readouterr().out
    assert "variants side by side" in out and "transmitted force range [tonf]" in out
    assert list((tmp_path / "c").glob("compare_*.png"))
    # after the run, the tables show the outputs in the units the study file asked for (JSON stays SI)
    from mechdyn.units import convert

    force = convert(listed[0]["outputs"]["transmitted_force_range_N"], "N", "tonf")
    row = re.compile(r"transmitted force range \[tonf\]\s+" + f"{force:.3f}")
    assert row.search(out), out
    assert main(["results", "list", "--study", "press-support-influence", "--db", db]) == 0
    out = capsys.readouterr().out
    assert "outputs in the study's units" in out and "transmitted force range [tonf]" in out
    assert f"{force:.2f}" in out and "displacement max [mm]" in out
    pq = tmp_path / "v.parquet"
    assert (
        main(["results", "export", "--study", "press-support-influence", "--db", db, "--parquet", str(pq)])
        == 0
    )
    import pandas as pd

    frame = pd.read_parquet(pq)
    assert len(frame) == 7 and "output:transmitted_force_range_N" in frame.columns


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("support.stiffness", "support.stifness"), r"no value at 'support.stifness'.*support.stiffness"),
        (
            ("transmitted_force_range_N", "transmitted_force_rang_N"),
            r"not an output of the support analysis.*did you mean",
        ),
        (('levels = ["-10 %", "-20 %", "-30 %"]', 'range = ["1 m", "2 m"]'), r"quantity in N/m"),
        (('kind = "oat"', 'kind = "sweep"'), r"kind.*(oat|literal)"),
    ],
)
def test_study_file_errors_name_the_file_and_the_field(tmp_path, capsys, change, message):
    from mechdyn.cli.main import main

    text = (STUDIES / "press_support_influence.toml").read_text().replace(*change, 1)
    path = write_study(tmp_path, text.replace("../press_on_support.toml", "press_on_support.toml"))
    assert main(["study", str(path), "--db", str(tmp_path / "r.db")]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and re.search(message, err, re.S)


def test_every_shipped_study_file_loads():
    files = sorted(STUDIES.glob("*.toml"))
    assert len(files) >= 3
    for f in files:
        assert all(s.parameters for s in load_studies(f))


@pytest.mark.slow  # three boxes of a constrained search: 8 s
def test_the_link_relocation_study_keeps_the_stroke_and_wider_boxes_do_no_worse(tmp_path, capsys):
    """The quick form (40 trials a box): each box starts from the base and the optimum of the box
    inside it, so a wider box never ends worse; every optimum keeps the stroke within 1 mm."""
    from mechdyn.cli.main import main

    path = STUDIES / "press_link_relocation.toml"
    assert main(["study", str(path), "--db", str(tmp_path / "r.db"), "--samples", "40", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["study"] == "press-link-relocation" and len(doc["studies"]) == 3
    forces = []
    for box in doc["studies"]:
        assert box["study"].endswith(" [samples 40]")  # the quick form, stored under its own name
        best = box["best"]
        assert abs(best["outputs"]["excitation.stroke_m"] - 1.4963) <= 1e-3 + 1e-4
        assert all(c["holds"] for c in best["constraints"])
        forces.append(best["outputs"]["transmitted_force_range_N"])
    assert forces == sorted(forces, reverse=True)
    assert doc["evaluated"] + doc["reused"] >= 3 * 40


def test_the_sobol_study_of_press_a_in_its_quick_form(tmp_path, capsys):
    """The slide carries almost all of the moving mass: its mass sets most of the floor force's
    fluctuation; the link masses hardly matter; the stroke depends on the geometry alone."""
    from mechdyn.cli.main import main

    path = STUDIES / "press_sobol.toml"
    assert main(["study", str(path), "--db", str(tmp_path / "r.db"), "--samples", "128", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["failed"] == 0 and doc["variants"] == 128 * 10
    force = doc["indices"]["transmitted_force_range_N"]
    slide = "slide mass"
    assert max(force, key=lambda n: force[n]["ST"]) == slide and force[slide]["ST"] > 0.7
    assert force["rocker mass"]["ST"] < 0.01
    stroke = doc["indices"]["excitation.stroke_m"]
    assert stroke[slide]["ST"] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.slow  # every variant checks its pitch curves (over 10 s): CI's heavy step
def test_the_rp1_sensitivity_against_the_published_directions(tmp_path):
    """SPEC §6: larger ε raises the gear and arm forces, the torque and the shaking force; smaller R
    raises the gear forces and lowers the torque; L changes no force. (Smaller |α|: published as
    raising the gear and arm forces, here it lowers them; and ε moves the shaking force more than d
    does: see the README.)"""
    from dataclasses import replace

    study = load_study(STUDIES / "rp1_sensitivity.toml")
    study = replace(study, options={"angles": 36}, curves=0, name="rp1-quick")
    result = run_study(study, str(tmp_path / "r.db"))
    assert result.failed == 0

    def change(parameter: str, percent: float, key: str) -> float:
        (e,) = [
            e
            for e in result.findings["effects"]
            if e["parameter"] == parameter and e["level_percent"] == pytest.approx(percent)
        ]
        return e["outputs"][key]["change_percent"]

    keys = [
        "tooth_force_max_N",
        "joint_force_peak_N.P1",
        "joint_force_peak_N.I1",
        "driving_torque_range_Nm",
        "shaking_force_y_range_N",
    ]
    for key in keys:
        assert (
            change("design.eccentricity_ratio", 10, key) > 0 > change("design.eccentricity_ratio", -10, key)
        )
    assert change("design.arm_radius", -10, "tooth_force_max_N") > 0
    assert change("design.arm_radius", -10, "driving_torque_range_Nm") < 0
    for key in keys:
        assert change("design.fork_length", 10, key) == pytest.approx(0.0, abs=1e-9)
    # the planets' unbalance m·d: the shaking force is proportional to d
    assert change("design.com_offset", 10, "shaking_force_x_range_N") == pytest.approx(10.0, rel=1e-6)


def test_tied_parameters_move_together_by_the_same_factor(tmp_path):
    """The two sides of RP-1 written body by body: the planets' masses tied, as one parameter."""
    tree = ModelTree(read(EXAMPLES / "transplanter_rp1.toml"))
    (p,) = Parameter.from_spec(tree, "bodies.planet 1.mass", levels=["10 %"], tie=["bodies.planet 2.mass"])
    assert len(p.locations) == 2
    values = p.location_values(p.levels[0])
    assert list(values.values()) == pytest.approx([1.1 * 1.0654, 1.1 * 1.0654])
    v = mechdyn.io.modelfile.load_source(tree.variant(p.file_values(p.levels[0]))).model
    assert [b.mass for b in v.bodies if b.name.startswith("planet")] == pytest.approx([1.1 * 1.0654] * 2)


def test_a_study_built_in_python_with_a_function_parameter(tmp_path):
    """A parameter that is any function model → model: the slider-crank's slider mass scaled; the
    largest inertia force along the stroke grows with the reciprocating mass, the stroke does not."""
    from dataclasses import replace

    from mechdyn.studies import Study, Watched

    source = read(EXAMPLES / "slider_crank.toml")
    base = mechdyn.load(EXAMPLES / "slider_crank.toml").model
    m0 = base.bodies[-1].mass

    def slider_mass(model, value):
        bodies = (*model.bodies[:-1], replace(model.bodies[-1], mass=value))
        return replace(model, bodies=bodies)

    p = Parameter.function("slider mass", slider_mass, m0, levels=(0.5 * m0, 2.0 * m0), unit="kg")
    study = Study(
        "function-parameter",
        "oat",
        source,
        "mechanism",
        (p,),
        (Watched("inertia_force_max_N", "N", ""), Watched("stroke_m", "m", "mm")),
        options={"angles": 72},
    )
    result = run_study(study, str(tmp_path / "r.db"))
    assert result.failed == 0 and len(result.variants) == 3
    forces = [v.outputs["inertia_force_max_N"] for v in result.variants]
    assert forces[1] < forces[0] < forces[2]
    assert len({round(v.outputs["stroke_m"], 12) for v in result.variants}) == 1
    assert base.bodies[-1].mass == m0  # the base model is untouched
    from mechdyn.studies.run import stored_study

    with pytest.raises(StudyError, match="built in Python"):  # no study file to rebuild it from
        stored_study(str(tmp_path / "r.db"), "function-parameter")


def test_a_factorial_study_stores_the_variants_that_fail_with_their_reason(tmp_path):
    path = write_study(
        tmp_path,
        """
        [study]
        name = "factorial-check"
        kind = "factorial"
        model = "fourbar.toml"
        analysis = "mechanism"
        options = { angles = 36 }

        [[parameters]]
        path = "points.B.x"
        levels = ["0 %", "5 %", "3900 %"]

        [[parameters]]
        path = "bodies.coupler.mass"
        levels = ["-10 %", "10 %"]

        [[outputs]]
        output = "driving_torque_peak_Nm"
        """,
    )
    result = run_study(load_study(path), str(tmp_path / "r.db"))
    assert len(result.variants) == 1 + 3 * 2
    # the counts add up: every variant evaluated now (none was stored before)
    assert (result.evaluated, result.reused) == (7, 0)
    again = run_study(load_study(path), str(tmp_path / "r.db"))
    assert (again.evaluated, again.reused, again.failed) == (0, 7, 2)
    failed = [v for v in result.variants if v.status == "failed"]
    assert result.failed == len(failed) == 2
    assert all(v.error and v.outputs["driving_torque_peak_Nm"] is None for v in failed)
    ok = [v for v in result.variants if v.status == "ok"]
    assert all(v.outputs["driving_torque_peak_Nm"] > 0 for v in ok)


def test_comparing_variants_keeps_their_curves(tmp_path, capsys):
    """A study too large to keep every curve: comparing two variants computes theirs and keeps them."""
    from dataclasses import replace

    from mechdyn.cli.main import main

    study = replace(load_study(STUDIES / "press_support_influence.toml"), curves=0, name="few-curves")
    db = str(tmp_path / "r.db")
    result = run_study(study, db)
    ids = [v.id for v in result.variants[1:3]]
    with ResultStore(db) as store:
        assert not any(StudyStore(store).variant(i).curves for i in ids)
    assert main(["results", "compare", *map(str, ids), "--db", db, "--plots", str(tmp_path / "c")]) == 0
    capsys.readouterr()
    with ResultStore(db) as store:
        assert all(StudyStore(store).variant(i).curves for i in ids)
    assert list((tmp_path / "c").glob("compare_*.png"))


def test_every_mount_stiffness_moves_together_and_the_modes_follow(tmp_path):
    """``mounts.*.stiffness``: all the mounts' stiffnesses (three axes each) by one factor; the
    natural frequencies scale with its square root (the mass is unchanged)."""
    source = read(EXAMPLES / "press_on_mounts.toml")
    tree = ModelTree(source)
    (k,) = Parameter.from_spec(tree, "mounts.*.stiffness", levels=["-19 %"])
    n_mounts = len(source.data["mounts"])
    assert len(k.locations) == 3 * n_mounts
    modes = [f"natural_frequencies_hz.{i}" for i in range(1, 7)]  # a list's items from 1
    ev = Evaluator(source, "support", [k], modes, {"cycles": 1})
    base, soft = (ev.one([x]) for x in (k.base, k.levels[0]))
    assert base.status == soft.status == "ok"
    for m in modes:
        assert soft.outputs[m] == pytest.approx(0.9 * base.outputs[m], rel=1e-9)
    loaded = mechdyn.io.modelfile.load_source(tree.variant(k.file_values(k.levels[0]))).model
    ref = mechdyn.load(EXAMPLES / "press_on_mounts.toml").model
    for a, b in zip(loaded.mounts, ref.mounts, strict=True):
        np.testing.assert_allclose(a.stiffness, 0.81 * np.asarray(b.stiffness), rtol=1e-12)


@pytest.mark.slow  # every kind's findings from the database alone: tests/test_study_kinds.py, by default
def test_a_stored_study_gives_its_findings_from_the_database_alone(tmp_path):
    """What a dashboard shows: the findings rebuilt from the stored variants, read-only, equal the
    run's own (one-at-a-time); for an optimization the stored best keeps its constraints."""
    from mechdyn.studies.run import stored_result

    db = str(tmp_path / "r.db")
    ran = run_study(load_study(STUDIES / "press_support_influence.toml"), db)
    again = stored_result(db, "press-support-influence")
    assert again.findings["effects"] == ran.findings["effects"]
    assert again.evaluated == 0 and len(again.variants) == 7
    path = write_study(
        tmp_path,
        """
        [study]
        name = "opt-stored"
        kind = "optimize"
        model = "press_on_support.toml"
        analysis = "support"
        samples = 12

        [[parameters]]
        path = "support.stiffness"
        range = "±30 %"

        [[objectives]]
        output = "displacement_max_m"

        [[constraints]]
        output = "transmitted_force_range_N"
        max = "86 tonf"
        """,
    )
    opt = run_study(load_study(path), db)
    stored = stored_result(db, "opt-stored")
    assert stored.findings["best"]["variant"] == opt.findings["best"]["variant"]
    assert all(c["holds"] for c in stored.findings["best"]["constraints"])


@pytest.mark.slow  # CI's heavy step (issue 48: the test command's minutes)
def test_a_study_shows_a_progress_bar_with_its_eta_on_a_terminal(tmp_path):
    """rich draws the bar (name, bar, %, time remaining) when the output is a terminal (forced here);
    `mechdyn study --json` prints JSON alone (see the command-line test)."""
    code = (
        "from mechdyn.studies import load_study, run_study\n"
        f"study = load_study({str(STUDIES / 'press_support_influence.toml')!r})\n"
        f"run_study(study, {str(tmp_path / 'r.db')!r}, progress=True)\n"
    )
    env = {**os.environ, "FORCE_COLOR": "1"}
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    assert "press-support-influence" in p.stderr and "━" in p.stderr and "-:--:--" in p.stderr


def test_the_curve_plots_label_the_base_design_and_only_it(tmp_path):
    # the bold "(base)" curve is the model as given, by its id: the first variant of an OAT study and
    # of a Latin hypercube (the base, then the sample); a study whose variants do not hold the base
    # design (a Sobol sample) has none
    import matplotlib

    matplotlib.use("Agg")
    oat = run_study(load_study(STUDIES / "press_support_influence.toml"), str(tmp_path / "r.db"))
    assert oat.base_id == oat.findings["base_variant"] is not None
    text = (STUDIES / "press_support_influence.toml").read_text()
    text = text.replace('kind = "oat"', 'kind = "lhs"\nsamples = 4\nseed = 3').replace(
        'name = "press-support-influence"', 'name = "press-lhs"'
    )
    text = text.replace('levels = ["-10 %", "-20 %", "-30 %"]', 'range = "±30 %"')
    path = tmp_path / "lhs.toml"
    path.write_text(text.replace('"../press_on_support.toml"', repr(str(EXAMPLES / "press_on_support.toml"))))
    sample = run_study(load_study(path), str(tmp_path / "r.db"))
    assert sample.base_id == sample.variants[0].id
    assert sample.variants[0].parameters == {p.name: p.base for p in sample.study.parameters}
    assert sample.findings["base"]["variant"] == sample.base_id
    # a sample states its answer: each output's range and the parameters ranked by |ρ| (Spearman)
    (ranking,) = [t for t in sample.tables() if "rank correlation" in t.title]
    assert [row[0] for row in ranking.rows] == [w.label for w in sample.study.watched]
    rho = sample.findings["rank_correlation"]["transmitted_force_range_N"]
    first = max(rho, key=lambda n: abs(rho[n]))
    assert ranking.rows[0][3].startswith(f"{first} {signed(rho[first], RHO_DIGITS)}")
    sobol = run_study(
        dataclasses.replace(load_study(path), name="press-sobol", kind="sobol", samples=2),
        str(tmp_path / "r.db"),
    )
    assert sobol.base_id is None and all(
        v.parameters != sample.variants[0].parameters for v in sobol.variants
    )
    for result, base in ((oat, oat.base_id), (sample, sample.base_id), (sobol, None)):
        ax = next(f() for k, f in result.plots().items() if k.startswith("curves_"))
        lines = {line.get_label(): line.get_linewidth() for line in ax.get_lines()}
        assert len(lines) == len(result.kept)
        bold = [k for k, w in lines.items() if w == 2.0]
        assert [k for k in lines if "(base)" in k] == bold == ([f"variant {base} (base)"] if base else [])


def test_an_output_that_names_no_number_is_refused_before_any_work(tmp_path):
    # a list without its entry, an entry counted from 0, a table without its name, a name it does not
    # hold: each would be empty for every variant; refused with the reason, nothing stored
    from mechdyn.store import ResultStore

    for output, why in (
        (
            "natural_frequencies_hz",
            r"'natural_frequencies_hz' is a list of 1: name one entry.*natural_frequencies_hz\.1",
        ),
        ("natural_frequencies_hz.0", r"its entries count from 1 \(natural_frequencies_hz\.1\)"),
        ("mount_force_peak_N", r"is a table: name one of its entries, mount_force_peak_N\.NAME \(support\)"),
        (
            "mount_force_peak_N.front",
            r"'mount_force_peak_N\.front' is not in the result \(mount_force_peak_N holds: support\)",
        ),
        ("machine_mass_kg.1", r"machine_mass_kg is a single value, it has no entries"),
    ):
        path = write_study(
            tmp_path,
            f"""
            [study]
            name = "empty-output"
            kind = "lhs"
            model = "press_on_support.toml"
            analysis = "support"
            samples = 2

            [[parameters]]
            path = "support.stiffness"
            range = "±10 %"

            [[outputs]]
            output = "{output}"
            """,
        )
        with pytest.raises(StudyError, match=why):
            run_study(load_study(path), str(tmp_path / "r.db"))
    with ResultStore(str(tmp_path / "r.db")) as store:
        assert StudyStore(store).studies() == []
    # the entry itself is read, variant by variant
    path.write_text(path.read_text().replace('"machine_mass_kg.1"', '"natural_frequencies_hz.1"'))
    result = run_study(load_study(path), str(tmp_path / "r.db"))
    assert all(v.outputs["natural_frequencies_hz.1"] > 4.0 for v in result.variants)


def test_only_a_bad_design_fails_a_variant_a_bug_stops_the_study(tmp_path):
    # a ModelError (the analysis refusing a design) is a failed variant with its message; any other
    # exception is a programming error: it stops the study instead of passing for a failed variant
    from dataclasses import replace

    from mechdyn.errors import ModelError

    path = write_study(
        tmp_path,
        """
        [study]
        name = "errors"
        kind = "lhs"
        model = "press_on_support.toml"
        analysis = "support"
        samples = 2

        [[parameters]]
        path = "support.stiffness"
        range = "±10 %"

        [[outputs]]
        output = "machine_mass_kg"
        """,
    )
    study = load_study(path)

    def refuse(model, x):
        raise ModelError("this design cannot be built", element="machine", field="mass")

    def bug(model, x):  # a shape mismatch: a ValueError from NumPy, not a bad design
        return np.zeros(2) + np.zeros(3)

    refused = replace(study, parameters=(Parameter.function("p", refuse, 1.0, low=0.5, high=1.5),))
    result = run_study(refused, str(tmp_path / "r.db"))
    assert result.failed == len(result.variants) == 3  # the base and two samples
    assert all("this design cannot be built" in v.error for v in result.variants)
    buggy = replace(study, name="bug", parameters=(Parameter.function("p", bug, 1.0, low=0.5, high=1.5),))
    with pytest.raises(ValueError, match="could not be broadcast"):
        run_study(buggy, str(tmp_path / "r.db"))


def test_a_factorial_study_states_main_effects_interactions_and_its_extremes(tmp_path):
    # 2 × 2 levels of mass and stiffness (±20 %): the machine's mass is additive in the mass alone
    # (effects ±0.2 m0, no stiffness effect, no interaction); the static deflection d = m g / k is a
    # product, so its cells are d0 (m/m0)(k0/k) and its interaction is d0 |Δm/m0| |Δ(k0/k)| / 4
    # (Montgomery, Design and Analysis of Experiments, ch. 5)
    from mechdyn.studies.run import stored_result

    path = write_study(
        tmp_path,
        """
        [study]
        name = "pad-grid"
        kind = "factorial"
        model = "press_on_support.toml"
        analysis = "support"

        [[parameters]]
        path = "machine.mass"
        levels = ["-20 %", "+20 %"]

        [[parameters]]
        path = "support.stiffness"
        levels = ["-20 %", "+20 %"]

        [[outputs]]
        output = "machine_mass_kg"
        unit = "t"

        [[outputs]]
        output = "static_deflection_m.support"
        unit = "mm"
        """,
    )
    db = str(tmp_path / "r.db")
    result = run_study(load_study(path), db)
    base = next(v for v in result.variants if v.position == 0)  # the model as given, evaluated first
    m0, d0 = 600e3, base.outputs["static_deflection_m.support"]
    mass = result.findings["factorial"]["machine_mass_kg"]
    assert mass["mean"] == pytest.approx(m0)
    np.testing.assert_allclose(mass["main"]["machine.mass"]["effects"], [-0.2 * m0, 0.2 * m0])
    assert mass["main"]["support.stiffness"]["spread"] == pytest.approx(0.0, abs=1e-6)
    assert mass["interactions"][0]["largest"] == pytest.approx(0.0, abs=1e-6)
    defl = result.findings["factorial"]["static_deflection_m.support"]
    m, r = np.array([0.8, 1.2]), 1 / np.array([0.8, 1.2])  # m / m0 and k0 / k at the two levels
    assert defl["mean"] == pytest.approx(d0 * m.mean() * r.mean())
    np.testing.assert_allclose(defl["main"]["machine.mass"]["means"], d0 * m * r.mean())
    np.testing.assert_allclose(defl["main"]["support.stiffness"]["means"], d0 * m.mean() * r)
    assert defl["interactions"][0]["largest"] == pytest.approx(d0 * 0.4 * abs(r[0] - r[1]) / 4)
    by_id = {v.id: v for v in result.variants}
    low, high = by_id[defl["lowest"]], by_id[defl["highest"]]
    assert low.parameters["machine.mass"] == pytest.approx(0.8 * m0)  # light on a stiff support
    assert high.parameters["machine.mass"] == pytest.approx(1.2 * m0)
    assert high.parameters["support.stiffness"] < low.parameters["support.stiffness"]
    # the tables say it in the study's units, and a stored study gives the same findings
    text = "\n".join(str(t) for t in result.tables())
    assert "main effects on static deflection · support" in text and "[mm]" in text and "[t]" in text
    assert "static_deflection_m" not in text  # the output in words, as its summary names it
    assert "two-way interactions" in text and "lowest and highest" in text
    assert stored_result(db, "pad-grid").findings["factorial"] == result.findings["factorial"]
    import matplotlib

    matplotlib.use("Agg")
    ax = result.plots()["main_effects_static_deflection_m_support.png"]()
    lines = {line.get_label(): line.get_ydata() for line in ax.get_lines()}
    np.testing.assert_allclose(lines["machine.mass"], 1e3 * d0 * m * r.mean())  # in mm, as asked
    # parallel coordinates: real values at each axis' ends, in the study's units, and a colour bar
    ax = result.plots()["parallel_coordinates.png"]()
    ends = [t.get_text() for t in ax.texts]
    assert "480 t" in ends and "720 t" in ends and any(t.endswith(" mm") for t in ends)
    (bar,) = [a for a in ax.figure.axes if a is not ax]
    assert bar.get_ylabel() == "static deflection · support [mm]"
