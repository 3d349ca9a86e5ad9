"""Mesh clocking: how one mesh's stiffness cycle and transmission error stand against another's, in
Python (``GearSystem.from_drivetrain(phases=)``), in files (``[[meshes]] phase``) and in studies; a
single mesh's steady state only moves in time, two meshes' peak forces change, and the shipped study
finds the best phase."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import mechdyn
from mechdyn.cli.main import main
from mechdyn.drivetrain import Disk, Drivetrain, GearMesh
from mechdyn.errors import ModelError, ModelFileError, ModelWarning
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.steady import steady_state

ROOT = Path(__file__).resolve().parents[1]
WAVE = {"fluctuation": 0.4, "contact_ratio": 1.6}


def _pair(teeth=(20, 40)) -> Drivetrain:
    mesh = GearMesh("m", ("a", "b"), teeth=teeth, base_radii=(0.02, 0.04), stiffness=3e8, damping=600.0)
    return Drivetrain([Disk("a", 0.002), Disk("b", 0.02)], [mesh], name="pair")


@pytest.mark.parametrize(("phase", "cycles"), [(0.25, 0.25), (1.75, 0.75), (-0.25, 0.75), ("4.5 deg", 0.25)])
def test_a_clocked_mesh_reads_its_cycle_ahead_by_the_phase(phase, cycles):
    """k(τ) of the clocked mesh is the unclocked k(τ + φ), for φ in cycles or as gear a's angle
    (20 teeth: 4.5° is a quarter of a cycle), wrapped into one cycle."""
    plain = GearSystem.from_drivetrain(_pair(), mesh_profiles={"m": WAVE}, errors={"m": {"amplitude": 2e-6}})
    clocked = GearSystem.from_drivetrain(
        _pair(), mesh_profiles={"m": WAVE}, errors={"m": {"amplitude": 2e-6}}, phases={"m": phase}
    )
    tau = np.linspace(0.0, 2.0, 97)
    m0, m1 = plain.meshes[0], clocked.meshes[0]
    assert m1.phase == pytest.approx(cycles)
    np.testing.assert_allclose(m1.stiffness(tau), m0.stiffness(tau + cycles), rtol=1e-12)
    np.testing.assert_allclose(m1.transmission_error(tau), m0.transmission_error(tau + cycles), atol=1e-18)


def test_a_phase_between_samples_is_rounded_to_the_nearest_and_said():
    s = GearSystem.from_drivetrain(_pair(), mesh_profiles={"m": WAVE}, phases={"m": 0.1234})
    assert s.meshes[0].phase == pytest.approx(round(0.1234 * 360) / 360)


def test_a_bad_phase_is_named():
    with pytest.raises(ModelError, match="'phases'"):
        GearSystem.from_drivetrain(_pair(), mesh_profiles={"m": WAVE}, phases={"m": "3 kg"})
    with pytest.raises(ModelError, match="not a flexible gear mesh"):
        GearSystem.from_drivetrain(_pair(), mesh_profiles={"m": WAVE}, phases={"n": 0.5})


def test_one_mesh_clocked_only_moves_its_steady_state_in_time():
    """With a single mesh the clocking is a shift of the time origin: the steady state's forces are
    the unclocked ones a quarter of the period later (to rounding; compared off the profile's corners,
    where the error's rate jumps and a sample on a corner takes either side's), K_v the same."""
    kw = {"reference": "a", "load": {"b": 40.0}, "harmonics": 32, "points": 400}
    opts = {"mesh_profiles": {"m": WAVE}, "errors": {"m": {"amplitude": 2e-6}}}
    plain = steady_state(GearSystem.from_drivetrain(_pair(), **opts), 300.0, **kw)
    clocked = steady_state(GearSystem.from_drivetrain(_pair(), **opts, phases={"m": 0.25}), 300.0, **kw)
    off_corners = np.arange(400) % 10 != 0  # 360 samples a cycle: every tenth of 400 points is a corner
    shifted = np.roll(plain.mesh_force[:, 0], -100)
    np.testing.assert_allclose(clocked.mesh_force[off_corners, 0], shifted[off_corners], rtol=1e-9)
    np.testing.assert_allclose(clocked.deflection[:, 0], np.roll(plain.deflection[:, 0], -100), atol=1e-18)
    assert clocked.dynamic_factor == pytest.approx(plain.dynamic_factor, rel=1e-6)


PAIR_FILE = """
[model]
type = "drivetrain"
name = "two pairs"

[[disks]]
name = "a"
inertia = "2e-3 kg*m^2"
[[disks]]
name = "b"
inertia = "4e-3 kg*m^2"
[[disks]]
name = "c"
inertia = "8e-3 kg*m^2"

[[meshes]]
name = "m1"
disks = ["a", "b"]
teeth = [20, 20]
base_radii = ["20 mm", "20 mm"]
stiffness = "3e8 N/m"
stiffness_variation = { fluctuation = 0.4, contact_ratio = 1.6 }
[[meshes]]
name = "m2"
disks = ["b", "c"]
teeth = [20, 20]
base_radii = ["20 mm", "20 mm"]
stiffness = "3e8 N/m"
stiffness_variation = { fluctuation = 0.4, contact_ratio = 1.6 }
phase = 0.5
"""


def test_a_file_s_phase_reaches_the_system_and_is_saved(tmp_path):
    path = tmp_path / "clocked.toml"
    path.write_text(PAIR_FILE)
    loaded = mechdyn.load(path)
    system = GearSystem.from_drivetrain(loaded.model, **loaded.settings.dynamics.system_options())
    assert [m.phase for m in system.meshes] == [0.0, 0.5]
    again = tmp_path / "again.toml"
    mechdyn.save(loaded, again)
    assert mechdyn.load(again).settings.dynamics.meshes["m2"].phase == 0.5


def test_a_phase_on_a_mesh_without_a_cycle_is_refused_with_the_fix(tmp_path):
    text = (ROOT / "examples" / "turret_milling_startup.toml").read_text()
    text = text.replace('stiffness_variation = "gears"\nbacklash = "50 um"', 'backlash = "50 um"')
    text = text.replace('backlash = "50 um"', "").replace("phase = 0.0", "phase = 0.3")
    path = tmp_path / "flat.toml"
    path.write_text(text)
    with pytest.raises(
        ModelFileError, match=r"\[\[meshes\]\] #2 \(name = 'mesh 2'\) → phase: a clocking phase"
    ):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)
            mechdyn.load(path)


@pytest.mark.slow  # a long sweep (tens of seconds): CI's heavy step
def test_the_clocking_study_of_the_turret_finds_the_phase_that_lowers_both_dynamic_factors(tmp_path, capsys):
    """Eight phases of mesh 2 against mesh 1 over the main resonance: out of step by 5/8 of a cycle
    the largest K_v of mesh 2 falls from 2.87 to 1.81 and mesh 1's from 2.09 to 1.73; in step (the
    file's) is among the worst."""
    path = ROOT / "examples" / "studies" / "turret_mesh_clocking.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        assert main(["study", str(path), "--db", str(tmp_path / "c.db"), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["failed"] == 0 and doc["variants"] == 8
    best = doc["best"]
    assert float(best["given"]["mesh 2 clocking"]) == pytest.approx(0.625)
    k2 = best["outputs"]["meshes.mesh 2.dynamic_factor_max_ratio"]
    k1 = best["outputs"]["meshes.mesh 1.dynamic_factor_max_ratio"]
    assert k2 < 0.7 * 2.87 and k1 < 0.9 * 2.09
