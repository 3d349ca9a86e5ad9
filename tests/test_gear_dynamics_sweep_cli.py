"""``mechdyn speed-sweep`` on drivetrain files: the ``[speed_sweep]`` table's defaults and the options
over them, the running load from ``[[loads]]``, ISO 6336-1's K_v for a mesh given by gear data, the run
stored, bad input named, and the table written back by ``mechdyn.save``."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import mechdyn
from mechdyn.cli.main import main
from mechdyn.errors import ModelWarning
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.steady import speed_sweep
from mechdyn.registry import get
from mechdyn.units import convert

# a 20/40 spur pair by gear data between a motor disk and a load disk that draws 20 N·m
PAIR = """
[model]
type = "drivetrain"
name = "one pair by gear data"

[[disks]]
name = "motor"
inertia = "2e-3 kg*m^2"
[[disks]]
name = "load"
inertia = "8e-3 kg*m^2"

[gear_material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3

[[gear_pairs]]
name = "20/40"
pinion = { teeth = 20, module = "2 mm", face_width = "20 mm" }
gear = { teeth = 40, module = "2 mm", face_width = "20 mm" }

[[meshes]]
name = "mesh"
disks = ["motor", "load"]
gear_pair = "20/40"
damping = "800 N*s/m"

[[loads]]
kind = "constant"
disk = "load"
torque = "20 N*m"          # the load disk turns backwards: a positive torque resists it
"""

SWEEP = """
[speed_sweep]
speed_range = ["1000 rpm", "3000 rpm"]
points = 6
harmonics = 4
"""

META = {
    "run_id",
    "analysis",
    "model",
    "model_file",
    "model_sha256",
    "parameters",
    "warnings",
    "plots",
    "report",
}


def _write(tmp_path, text, name="pair.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _run(capsys, tmp_path, path, *options):
    assert main(["speed-sweep", str(path), "--json", "--db", str(tmp_path / "r.db"), *options]) == 0
    return json.loads(capsys.readouterr().out)


def _rad_s(rpm):
    return float(convert(rpm, "rpm", "rad/s"))


def test_the_command_runs_on_a_small_file_and_stores_its_run(tmp_path, capsys):
    doc = _run(capsys, tmp_path, _write(tmp_path, PAIR + SWEEP), "--plots", str(tmp_path / "plots"))
    documented = {o.key for o in get("speed-sweep").outputs}
    assert set(doc) - META == documented
    assert doc["analysis"] == "speed-sweep" and doc["reference"] == "motor"
    mesh = doc["meshes"]["mesh"]
    assert mesh["static_force_N"] > 0 and mesh["dynamic_factor_max_ratio"] >= 1.0
    assert {p.rsplit("/", 1)[-1] for p in doc["plots"]} == {"speed_sweep.png", "speed_sweep_dte.png"}
    assert main(["results", "list", "--json", "--db", str(tmp_path / "r.db")]) == 0
    runs = json.loads(capsys.readouterr().out)
    assert [r["analysis"] for r in runs] == ["speed-sweep"] and runs[0]["id"] == doc["run_id"]


def test_the_file_gives_the_defaults_and_the_options_override_them(tmp_path, capsys):
    path = _write(tmp_path, PAIR + SWEEP)
    doc = _run(capsys, tmp_path, path)
    assert doc["speed_min_rad_s"] == pytest.approx(_rad_s(1000.0))
    assert doc["speed_max_rad_s"] == pytest.approx(_rad_s(3000.0))
    assert doc["points"] >= 6 and "4 harmonics" in doc["method"]
    over = _run(
        capsys,
        tmp_path,
        path,
        *("--speed-range", "500 rpm", "800 rpm", "--points", "3", "--harmonics", "2", "--no-stability"),
    )
    assert over["speed_min_rad_s"] == pytest.approx(_rad_s(500.0))
    assert over["speed_max_rad_s"] == pytest.approx(_rad_s(800.0))
    assert "2 harmonics" in over["method"] and over["parameters"]["points"] == 3


def test_the_running_load_is_the_one_speed_sweep_takes_resisting(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        loaded = mechdyn.load(_write(tmp_path, PAIR + SWEEP))
    result = get("speed-sweep").run(loaded, no_stability=True)
    system = GearSystem.from_drivetrain(loaded.model)
    direct = speed_sweep(
        system, result.speeds, reference="motor", load={"load": 20.0}, harmonics=4, refine=0, stability=False
    )
    assert np.allclose(result.static_force, direct.static_force)
    # 20 N·m at the 40-tooth gear over its base radius
    r_b = loaded.settings.gear_pairs["mesh"].gear.base_radius
    assert abs(result.static_force[0, 0]) == pytest.approx(20.0 / r_b, rel=1e-9)


def test_a_mesh_from_gear_data_has_the_iso_curve(tmp_path, capsys):
    doc = _run(capsys, tmp_path, _write(tmp_path, PAIR + SWEEP), "--no-stability")
    iso = doc["meshes"]["mesh"]["iso_dynamic_factor_max_ratio"]
    assert np.isfinite(iso) and 1.0 < iso < 3.0


def test_a_file_without_a_speed_range_is_refused_with_the_fix(tmp_path, capsys):
    path = _write(tmp_path, PAIR, "bare.toml")
    assert main(["speed-sweep", str(path), "--db", str(tmp_path / "r.db")]) == 2
    err = capsys.readouterr().err
    assert "bare.toml: [speed_sweep] → speed_range: no speed range; add a [speed_sweep] table" in err
    assert "--speed-range" in err


@pytest.mark.parametrize(
    ("table", "field"),
    [
        ('speed_range = ["3000 rpm", "1000 rpm"]', "speed_range"),
        ('speed_range = ["1000 rpm", "3000 rpm"]\npoints = 1', "points"),
        ('speed_range = ["1000 rpm", "3000 rpm"]\nreference = "nowhere"', "reference"),
        ('speed_range = ["1000 mm", "3000 mm"]', "speed_range"),
        ('speed_range = ["1000 rpm", "3000 rpm"]\npionts = 5', "pionts"),
    ],
    ids=["range reversed", "too few points", "unknown disk", "not a speed", "misspelt field"],
)
def test_bad_speed_sweep_fields_are_named(tmp_path, capsys, table, field):
    path = _write(tmp_path, PAIR + "\n[speed_sweep]\n" + table + "\n", "bad.toml")
    assert main(["speed-sweep", str(path), "--db", str(tmp_path / "r.db")]) != 0
    err = capsys.readouterr().err
    assert "speed_sweep" in err and field in err, err


def test_save_writes_the_table_back(tmp_path):
    text = PAIR.replace(
        'gear_pair = "20/40"',
        'teeth = [20, 40]\nbase_radii = ["18.79 mm", "37.59 mm"]\nstiffness = "3e8 N/m"',
    )
    text = text.split("[gear_material]")[0] + "[[meshes]]" + text.split("[[meshes]]")[1]
    loaded = mechdyn.load(_write(tmp_path, text + SWEEP + 'reference = "motor"\nbacklash = false\n'))
    again = mechdyn.load(mechdyn.save(loaded, tmp_path / "saved.toml"))
    assert again.settings.speed_sweep == loaded.settings.speed_sweep
    assert again.settings.speed_sweep.speed_range == pytest.approx((_rad_s(1000.0), _rad_s(3000.0)))


def test_backlash_held_in_contact_says_so(tmp_path, capsys):
    text = PAIR.replace('damping = "800 N*s/m"', 'damping = "800 N*s/m"\nbacklash = "50 um"')
    doc = _run(capsys, tmp_path, _write(tmp_path, text + SWEEP), "--no-backlash", "--no-stability")
    assert doc["method"].startswith("harmonic balance")
    assert any("backlash of 'mesh' is ignored" in w for w in doc["warnings"])


def test_the_sweep_with_backlash_goes_the_way_the_file_or_the_option_says(tmp_path, capsys):
    text = PAIR.replace('damping = "800 N*s/m"', 'damping = "800 N*s/m"\nbacklash = "50 um"')
    sweep = SWEEP.replace('["1000 rpm", "3000 rpm"]', '["500 rpm", "700 rpm"]').replace("6", "3")
    path = _write(tmp_path, text + sweep + 'direction = "both"\n')
    with pytest.warns(ModelWarning, match="bore_diameter"):
        assert mechdyn.load(path).settings.speed_sweep.direction == "both"
    both = _run(capsys, tmp_path, path, "--no-stability")
    assert both["method"].startswith("shooting") and both["parameters"] == {"no_stability": True}
    # the teeth stay in contact at this light speed: the two branches are one, and said to be
    assert both["meshes"]["mesh"]["hysteresis_speeds_rad_s"] == []
    up = _run(capsys, tmp_path, path, "--no-stability", "--direction", "up")
    assert up["parameters"]["direction"] == "up" and "hysteresis_speeds_rad_s" not in up["meshes"]["mesh"]
    assert up["meshes"]["mesh"]["dynamic_factor_max_ratio"] == pytest.approx(
        both["meshes"]["mesh"]["dynamic_factor_max_ratio"], rel=1e-9
    )
    with pytest.raises(SystemExit):
        main(["speed-sweep", str(path), "--db", str(tmp_path / "r.db"), "--direction", "sideways"])
    assert "invalid choice: 'sideways'" in capsys.readouterr().err


def test_a_design_study_varies_the_mesh_damping_and_reads_the_dynamic_factor(tmp_path):
    """``speed-sweep`` in a study: each variant's stored output equals the analysis run on the
    changed file by itself, and more mesh damping lowers the largest dynamic factor (the sweep over the
    free pair's mesh resonance, near 4750 rpm)."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    pair = PAIR.replace('damping = "800 N*s/m"', 'damping = "800 N*s/m"\ntransmission_error = "5 um"')
    sweep = SWEEP.replace('["1000 rpm", "3000 rpm"]', '["3500 rpm", "6000 rpm"]')
    _write(tmp_path, pair + sweep)
    (tmp_path / "study.toml").write_text(
        """
[study]
name = "pair-damping"
kind = "oat"
model = "pair.toml"
analysis = "speed-sweep"
options = { no_stability = true }

[[parameters]]
path = "meshes.mesh.damping"
levels = ["+200 %"]

[[outputs]]
output = "meshes.mesh.dynamic_factor_max_ratio"
"""
    )
    db = str(tmp_path / "s.db")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        assert main(["study", str(tmp_path / "study.toml"), "--db", db, "--json"]) == 0
        with ResultStore(db, read_only=True) as store:
            variants = StudyStore(store).variants("pair-damping")
        assert len(variants) == 2 and all(v.status == "ok" for v in variants)
        damped = _write(tmp_path, pair.replace('"800 N*s/m"', '"2400 N*s/m"') + sweep, "damped.toml")
        alone = get("speed-sweep").run(mechdyn.load(damped), no_stability=True).summary()
    key = "meshes.mesh.dynamic_factor_max_ratio"
    by = {v.given["meshes.mesh.damping"]: dict(v.outputs)[key] for v in variants}
    assert by["2400 N*s/m"] == pytest.approx(alone["meshes"]["mesh"]["dynamic_factor_max_ratio"], rel=1e-9)
    assert 1.0 <= by["2400 N*s/m"] < by["800 N*s/m"]
