"""A foundation block on soil under the mounts (issue 46): the soil's closed forms (Gazetas 1991),
the two-body assembly (symmetric, semi-definite, rigid-body freedoms without the soil), the block on
its soil alone, the two-stage isolator in closed form, a very stiff soil giving back rigid ground,
the block's force balance, the model file and the press A floor tolerance study."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.errors import ModelError, ModelFileError
from mechdyn.support import Mount, MountedMachine, PeriodicLoad, RigidBody
from mechdyn.support.coupled import FoundationSystem
from mechdyn.support.floor import floor_vibration
from mechdyn.support.foundation import (
    Foundation,
    Soil,
    gazetas_radiation_damping,
    gazetas_static_stiffness,
    rectangular_block,
)
from mechdyn.support.response import harmonic_response

EXAMPLE = EXAMPLES / "press_on_mounts_foundation.toml"
STUDY = EXAMPLES / "studies" / "press_mounts_floor_tolerance.toml"


def _machine(dofs=("x", "y", "z", "rx", "ry", "rz")) -> MountedMachine:
    """A 20 t machine, centre of mass 1 m up, on four mounts at (±1.5, ±1, 0) with 5 % damping."""
    body = RigidBody(20e3, (0.1, -0.05, 1.0), (4e4, 5e4, 3e4))
    mounts = [
        Mount(f"m{i}", (sx * 1.5, sy * 1.0, 0.0), (3e6, 3e6, 1e7), (2e4, 2e4, 5e4))
        for i, (sx, sy) in enumerate(((-1, -1), (1, -1), (-1, 1), (1, 1)))
    ]
    return MountedMachine(body, mounts, dofs)


def _foundation(k=(4e8, 5e8, 6e8, 3e9, 4e9, 2e9), c=(1e6, 1e6, 2e6, 1e6, 1e6, 1e6)) -> Foundation:
    block, base = rectangular_block((5.0, 4.0, 1.5), 2400.0)
    return Foundation(block, base, k, c)


def _load() -> PeriodicLoad:
    # a vertical force and, through its offset, moments: harmonics 1 … 6 of 2 Hz
    return PeriodicLoad.from_harmonics(
        0.5, {h: 1e4 / h * complex(math.cos(h), math.sin(h)) for h in range(1, 7)}
    )


# -- the soil's closed forms -------------------------------------------------------------------------


def test_gazetas_static_stiffness_against_a_hand_computation():
    """A 6 m × 4 m footing (L = 3 m, B = 2 m, χ = B/L = 2/3) on G = 50 MPa, ν = 0.3; the numbers worked
    by hand from Gazetas (1991), Table 1, to seven digits, χ^0.75 = 0.7377879, χ^0.85 = 0.7084716:
    K_z = 2·5e7·3/0.7 · (0.73 + 1.54 · 0.7377879) = 4.285714e8 · 1.866193 = 7.997972e8 N/m;
    K_y = 2·5e7·3/1.7 · (2 + 2.5 · 0.7084716) = 1.764706e8 · 3.771179 = 6.655022e8 N/m;
    K_x = K_y − 0.2/0.45 · 5e7 · 3 · (1 − 2/3) = 6.655022e8 − 2.222222e7 = 6.432799e8 N/m;
    I_bx = 4/3 · 3 · 2³ = 32 m⁴, I_by = 4/3 · 2 · 3³ = 72 m⁴, J_t = 104 m⁴:
    K_rx = 5e7/0.7 · 32^0.75 (= 13.45434) · 1.5^0.25 (= 1.106682) · (2.4 + 1/3) = 2.907032e9 N·m/rad;
    K_ry = 3·5e7/0.7 · 72^0.75 (= 24.71721) · 1.5^0.15 (= 1.062707) = 5.628676e9 N·m/rad;
    K_t = 5e7 · 104^0.75 (= 32.56679) · (4 + 11/3^10) = 6.513662e9 N·m/rad."""
    K = gazetas_static_stiffness(5e7, 0.3, 6.0, 4.0)
    hand = [6.432799e8, 6.655022e8, 7.997972e8, 2.907032e9, 5.628676e9, 6.513662e9]
    assert K == pytest.approx(hand, rel=2e-6)
    # the same footing turned a quarter turn: x and y exchange
    assert gazetas_static_stiffness(5e7, 0.3, 4.0, 6.0) == pytest.approx(K[[1, 0, 2, 4, 3, 5]], rel=1e-14)


def test_a_square_footing_matches_the_disc_of_equal_area_and_gazetas_square_values():
    """A square 2B × 2B: Gazetas's K_z = 4.54 G B/(1 − ν) (his text), within 1 % of the disc of the
    same area, 4 G r/(1 − ν), r = 2B/√π (Boussinesq; Richart, Hall & Woods 1970, Table 7-2); sway equal
    both ways; rocking 3.6 G B³/(1 − ν) ± 4 % (the two fits for about x and about y differ by 3 %)."""
    G, nu, B = 8e7, 0.25, 1.5
    K = gazetas_static_stiffness(G, nu, 2 * B, 2 * B)
    assert K[2] == pytest.approx(4.54 * G * B / (1 - nu), rel=2e-3)
    r = 2 * B / math.sqrt(math.pi)
    assert K[2] == pytest.approx(4 * G * r / (1 - nu), rel=1e-2)
    assert K[0] == pytest.approx(K[1], rel=1e-14)
    assert K[3] == pytest.approx(3.6 * G * B**3 / (1 - nu), rel=4e-2)
    assert K[4] == pytest.approx(3.6 * G * B**3 / (1 - nu), rel=4e-2)


def test_the_radiation_dashpots_of_the_translations_and_the_soil_from_its_wave_speed():
    """C_z = ρ V_La A_b with V_La = 3.4 V_s/(π (1 − ν)), C_x = C_y = ρ V_s A_b (Gazetas 1991): for
    V_s = 200 m/s, ρ = 1900 kg/m³, ν = 1/3 and 6 m × 4 m, C_x = 1900·200·24 = 9.12e6 N·s/m and
    C_z = 9.12e6 · 3.4/(π·2/3) = 1.480523e7 N·s/m; G = ρ V_s² = 76 MPa. Rocking and torsion dashpots
    fall with the block's inertia (Richart, Hall & Woods: D_ψ ∝ 1/((1 + B_ψ)√B_ψ))."""
    soil = Soil.from_shear_wave_speed(200.0, 1 / 3, 1900.0)
    assert soil.shear_modulus == pytest.approx(7.6e7, rel=1e-14)
    c = gazetas_radiation_damping(soil, 6.0, 4.0)
    assert c[:3] == pytest.approx([9.12e6, 9.12e6, 1.480523e7], rel=1e-6)
    assert (c[3:] == 0).all()  # no block: no rotation dashpots
    light = gazetas_radiation_damping(soil, 6.0, 4.0, (1e5, 1e5, 1e5))
    heavy = gazetas_radiation_damping(soil, 6.0, 4.0, (1e8, 1e8, 1e8))
    K = gazetas_static_stiffness(soil.shear_modulus, soil.poisson_ratio, 6.0, 4.0)
    ratio_light = light[3:] / (2 * np.sqrt(K[3:] * 1e5))
    ratio_heavy = heavy[3:] / (2 * np.sqrt(K[3:] * 1e8))
    assert (ratio_heavy < ratio_light).all()


# -- the assembly -------------------------------------------------------------------------------------


def test_the_assembled_matrices_are_symmetric_semi_definite_and_free_without_the_soil():
    """M, K, C (12 × 12) symmetric, M and C semi-definite and K positive definite on its soil; the
    mounts alone leave exactly the six rigid-body motions of machine and block moving together."""
    system = FoundationSystem(_machine(), _foundation())
    M, K, C = system.mass_matrix, system.stiffness_matrix, system.damping_matrix
    assert M.shape == K.shape == C.shape == (12, 12)
    for A in (M, K, C):
        assert np.array_equal(A, A.T)
    assert np.linalg.eigvalsh(M).min() > 0
    assert np.linalg.eigvalsh(C).min() > -1e-9 * np.abs(C).max()
    assert np.linalg.eigvalsh(K).min() > 0
    S = system.soil_transform
    mounts_only = K - S.T @ system.foundation.soil_stiffness_matrix @ S
    w = np.linalg.eigvalsh(mounts_only)
    assert (np.abs(w) < 1e-8 * w.max()).sum() == 6
    # a rigid motion of the pair (translation t, small rotation θ about the origin) strains no mount
    t, th = np.array([1e-3, -2e-3, 5e-4]), np.array([1e-4, 3e-4, -2e-4])
    Gm, Gb = system.machine.body.center_of_mass, system.foundation.block.center_of_mass
    q = np.concatenate([t + np.cross(th, Gm), th, t + np.cross(th, Gb), th])
    assert np.abs(mounts_only @ q).max() < 1e-9 * np.abs(mounts_only).max() * np.abs(q).max()


def test_a_block_on_its_soil_springs_alone_bounces_at_the_square_root_of_k_over_m():
    """A machine of negligible mass on the block: the block's vertical frequency is √(k_z/m_b)/(2π);
    the machine's own one is far above."""
    block, base = rectangular_block((4.0, 3.0, 1.0), 2500.0)  # 30 t
    kz = 7.5e8
    f = Foundation(block, base, (1e9, 1e9, kz, 1e10, 1e10, 1e10))
    machine = MountedMachine.single_dof(1e-3, 1e3, 0.0)  # 1 g on 1 kN/m: 159 Hz
    fn = FoundationSystem(machine, f).natural_frequencies_hz
    assert fn[0] == pytest.approx(math.sqrt(kz / block.mass) / (2 * math.pi), rel=1e-6)


def test_the_two_stage_isolator_in_closed_form():
    """Machine m₁ on mounts k₁ on block m₂ on soil k₂, vertically: ω² are the roots of
    m₁m₂ω⁴ − (m₁(k₁ + k₂) + m₂k₁) ω² + k₁k₂ = 0 (Harris & Piersol, ch. 30, two-stage isolation)."""
    m1, k1, m2, k2 = 6e5, 4.5e8, 8.6e5, 3.2e9
    machine = MountedMachine.single_dof(m1, k1, 0.05)
    block = RigidBody(m2)
    f = Foundation(block, (0.0, 0.0, -1.5), (1e9, 1e9, k2, 1e10, 1e10, 1e10))
    fn = FoundationSystem(machine, f).natural_frequencies_hz
    w2 = np.sort(np.roots([m1 * m2, -(m1 * (k1 + k2) + m2 * k1), k1 * k2]).real)
    assert fn == pytest.approx(np.sqrt(w2) / (2 * math.pi), rel=1e-10)


def test_a_very_stiff_soil_gives_back_rigid_ground():
    """Soil 1e6 times stiffer than the mounts: the machine's response is the rigid-ground one to
    about 1e-5 and the floor barely moves."""
    machine, load = _machine(), _load()
    stiff = _foundation(k=(1e14, 1e14, 1e14, 1e15, 1e15, 1e15), c=(0.0,) * 6)
    system = FoundationSystem(machine, stiff)
    X = system.harmonic_response(load)[:, :6]
    X0 = harmonic_response(machine, load)
    assert np.abs(X - X0).max() < 1e-4 * np.abs(X0).max()
    floor = floor_vibration(machine, stiff, load)
    frame_scale = np.abs(2 * math.pi * 2.0 * X0).max()
    assert np.abs(floor.velocity).max() < 1e-4 * frame_scale


@pytest.mark.parametrize("dofs", [("x", "y", "z", "rx", "ry", "rz"), ("x", "z", "ry")])
def test_the_soil_takes_the_mounts_force_less_the_blocks_inertia(dofs):
    """Newton on the block, harmonic by harmonic: the force on the soil equals the force the mounts pass
    down less m_b a_b; and the mounts' force is the load less the machine's m a_G."""
    machine, load = _machine(dofs), _load()
    floor = floor_vibration(machine, _foundation(), load)
    kept = [k for k, d in enumerate("xyz") if d in dofs]
    mounts = floor.mount_force.sum(axis=1)
    expected = mounts - floor.foundation.block.mass * floor.block_acceleration
    scale = np.abs(mounts).max()
    assert np.abs(floor.soil_force[:, kept] - expected[:, kept]).max() < 1e-9 * scale
    # and the machine: Σ mount forces = F − m a_G
    system = floor.system
    omega = 2 * math.pi / load.period * load.orders()
    X = system.harmonic_response(load)
    a = np.zeros((X.shape[0], 3), dtype=complex)
    for k, d in enumerate("xyz"):
        if d in dofs:
            a[:, k] = -(omega**2) * X[:, dofs.index(d)]
    F = load.coefficients[:, :3]
    residual = mounts - (F - machine.body.mass * a)
    assert np.abs(residual[:, kept]).max() < 1e-9 * np.abs(F).max()


def test_the_floor_rating_follows_the_criteria_curves():
    """The floor's line spectrum is rated by floor_criteria: the worst ratio to VC-B is the largest over
    the points and directions, and VC-B is met exactly when that ratio is at most 1."""
    floor = floor_vibration(_machine(), _foundation(), _load())
    ratios = [c["band_ratio"]["VC-B"] for row in floor.ratings for c in row]
    s = floor.summary()
    assert s["floor_vc_b_ratio"] == pytest.approx(max(ratios), rel=1e-14)
    assert s["floor_vc_b_met"] == (max(ratios) <= 1.0)
    assert s["floor_criteria_band_ratio"]["VC-A"] == pytest.approx(s["floor_vc_b_ratio"] / 2, rel=1e-12)
    assert s["floor_velocity_band_max_m_per_s"] == pytest.approx(s["floor_vc_b_ratio"] * 25e-6, rel=1e-12)
    assert len(s["foundation_natural_frequencies_hz"]) == 12


def test_bad_foundations_are_refused():
    block, base = rectangular_block((4.0, 3.0, 1.0), 2400.0)
    with pytest.raises(ModelError, match="six values"):
        Foundation(block, base, (1e9, 1e9, -1.0, 1e9, 1e9, 1e9))
    with pytest.raises(ModelError, match="unrestrained"):
        FoundationSystem(_machine(), Foundation(block, base, (1e9, 1e9, 1e9, 0.0, 1e9, 1e9)))
    with pytest.raises(ModelError, match="poisson_ratio"):
        Soil(5e7, 0.5, 1900.0)


# -- the model file and the study ---------------------------------------------------------------------


def run_json(capsys, *argv):
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_the_press_on_its_foundation_rates_the_floor_and_rigid_ground_keeps_its_verdict(capsys, tmp_path):
    db = str(tmp_path / "r.db")
    s = run_json(capsys, "support", str(EXAMPLE), "--cycles", "1", "--db", db)
    assert "not modelled" not in s["floor_vibration_verdict"]
    assert "VC-B" in s["floor_vibration_verdict"]
    assert len(s["foundation_natural_frequencies_hz"]) == 12
    assert s["floor_vc_b_met"] == (s["floor_vc_b_ratio"] <= 1.0)
    assert 0.3 < s["floor_vc_b_ratio"] < 3.0  # the example is chosen near the limit
    assert s["soil_springs_from"].startswith("Gazetas")
    # the machine's own figures are the rigid-ground ones of the same machine
    r = run_json(capsys, "support", str(EXAMPLES / "press_on_mounts.toml"), "--cycles", "1", "--db", db)
    assert s["natural_frequencies_hz"] == pytest.approx(r["natural_frequencies_hz"], rel=1e-12)
    assert "needs a floor or foundation model" in r["floor_vibration_verdict"]
    assert "floor_vc_b_ratio" not in r


def test_the_foundation_table_refuses_a_soil_given_twice(tmp_path):
    from mechdyn.io.modelfile import load_model

    text = EXAMPLE.read_text().replace(
        'shear_modulus = "320 MPa"',
        'shear_modulus = "320 MPa"\nstiffness = ["1e9 N/m", "1e9 N/m", "1e9 N/m"]',
    )
    path = tmp_path / "bad.toml"
    path.write_text(
        text.replace('"press_link_drive.toml"', json.dumps(str(EXAMPLES / "press_link_drive.toml")))
    )
    with pytest.raises(ModelFileError, match="half-space"):
        load_model(path)


def test_the_press_floor_tolerance_study_gives_the_probability_with_its_interval(tmp_path):
    """The example study on a few samples: P(floor above VC-B) with its interval, and the soil ranked
    above the mounts (at 1 Hz, below the mounts' frequencies, the mounts pass the force through
    whatever their stiffness; the soil sets how far the block moves under it)."""
    from mechdyn.studies import load_study, run_study

    result = run_study(load_study(STUDY).quick(32), str(tmp_path / "r.db"))
    found = next(d for d in result.findings["limits"] if d["output"] == "floor_vc_b_ratio")
    p = found["probability"]
    assert 0.0 <= p["low"] <= p["value"] <= p["high"] <= 1.0
    assert 0.0 < p["value"] < 1.0
    assert found["ranking"]["ranked"][0] == "soil shear modulus"  # the probability's tolerance
    assert result.findings["outputs"]["floor_vc_b_ratio"]["ranking"]["ranked"][0] == "soil shear modulus"


@pytest.mark.parametrize("soil", ["half-space", "springs"])
def test_a_saved_foundation_loads_back_with_the_same_floor(tmp_path, soil):
    """mechdyn.save writes [foundation] and [foundation.soil] (the half-space it came from, or its
    springs and dashpots): the file loads back to the same floor figures, to the last bit."""
    import mechdyn
    from mechdyn.registry import get

    text = EXAMPLE.read_text().replace(
        '"press_link_drive.toml"', repr(str(EXAMPLES / "press_link_drive.toml"))
    )
    path = tmp_path / "press.toml"
    path.write_text(text)
    loaded = mechdyn.load(path)
    if soil == "springs":  # the same soil given as the springs and dashpots of its closed forms
        f = loaded.settings.foundation
        rows = {
            "stiffness": [f"{float(k)!r} N/m" for k in f.soil_stiffness[:3]],
            "rotational_stiffness": [f"{float(k)!r} N*m/rad" for k in f.soil_stiffness[3:]],
            "damping": [f"{float(c)!r} N*s/m" for c in f.soil_damping[:3]],
            "rotational_damping": [f"{float(c)!r} N*m*s/rad" for c in f.soil_damping[3:]],
        }
        head, _, _ = text.partition("[foundation.soil]")
        text = (
            head + "[foundation.soil]\n" + "\n".join(f"{k} = {json.dumps(v)}" for k, v in rows.items()) + "\n"
        )
        path.write_text(text)
        loaded = mechdyn.load(path)
    again = mechdyn.load(mechdyn.save(loaded, tmp_path / "saved.toml"))
    before, after = (get("support").run(x).summary() for x in (loaded, again))
    for key in ("floor_vc_b_ratio", "foundation_natural_frequencies_hz", "soil_stiffness_N_per_m"):
        assert after[key] == before[key], key
    assert (again.settings.foundation.soil is None) == (soil == "springs")
