"""How the periodic steady state drives the train: the motor free on its torque–speed curve (the
default with a motor, what ``simulate`` integrates), a constant torque with every disk free, or the
reference disk held (a kinematic input). Closed forms of the free pair, Kloss's slope, the free
train's modes against the sweep's resonance, and ``simulate`` of the shipped turret at its running
speed."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mechdyn.drive import InductionMotor
from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, modal
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.floquet import linear_periodic
from mechdyn.gear_dynamics.loads import ConstantTorque, MotorTorque
from mechdyn.gear_dynamics.simulate import simulate
from mechdyn.gear_dynamics.steady import speed_sweep, steady_state
from mechdyn.registry import get

RA, RB, ZA, ZB = 0.0188, 0.047, 20, 50
J1, J2, K_MESH, C_MESH = 0.002, 0.03, 3e8, 800.0
TURRET = Path(__file__).resolve().parents[1] / "examples" / "turret_milling_startup.toml"


def _pair(**kw) -> GearSystem:
    dt = Drivetrain(
        [Disk("pinion", J1), Disk("gear", J2)],
        [
            GearMesh(
                "m", ("pinion", "gear"), teeth=(ZA, ZB), base_radii=(RA, RB), stiffness=K_MESH, damping=C_MESH
            )
        ],
        name="pair",
    )
    return GearSystem.from_drivetrain(dt, **kw)


def _motor(disk: str = "pinion", ratio: float = 1.0) -> MotorTorque:
    return MotorTorque(disk, InductionMotor.from_rating("3 kW", "3000 rpm", "2880 rpm", 2.8), ratio)


def test_a_free_pair_vibrates_on_its_own_mesh_mode_as_the_closed_form_says():
    """Constant stiffness, a sine transmission error, every disk free (``drive="torque"``): the mesh
    deflection is that of the pair's equivalent mass m = 1/(r_a²/J_a + r_b²/J_b) on the mesh spring,
    δ = (k + iωc) E / (k − ω² m + iωc) (e.g. Kahraman & Singh, *J. Sound Vib.* 142, 1990, eq. 3,
    linear): not the gear alone on it, as a held pinion makes it."""
    amp = 2e-6
    system = _pair(errors={"m": {"amplitude": amp}})
    m_free = 1.0 / (RA**2 / J1 + RB**2 / J2)
    m_held = J2 / RB**2
    for drive, m_eq in (("torque", m_free), ("speed", m_held)):
        speed = 0.9 * np.sqrt(K_MESH / m_free) / ZA  # near the free mesh mode
        s = steady_state(system, speed, reference="pinion", load={"gear": 30.0}, drive=drive, harmonics=4)
        w = ZA * speed
        # e = amp sin(ωt) sampled at 360 points and interpolated linearly: its first harmonic is the
        # sine's times sinc²(1/360) (the hat function's transform)
        E = amp / 2j * np.sinc(1 / 360) ** 2
        delta = (K_MESH + 1j * w * C_MESH) * E / (K_MESH - w**2 * m_eq + 1j * w * C_MESH)
        expected = 2 * abs(delta)  # half peak-to-peak of the real deflection e^(iωt) δ + c.c.
        # 1e-5: the peak read from the period's 1440 samples (1 − cos(π/1440) ≈ 2e-6) and the
        # interpolant's higher harmonics; the free and held answers differ by a factor of 3
        assert s.dte_amplitude[0] == pytest.approx(expected, rel=1e-5), drive
    assert "held" in steady_state(system, 50.0, reference="pinion", drive="speed").drive
    assert "constant torque" in steady_state(system, 50.0, reference="pinion").drive


def test_the_motor_slope_is_kloss_s_derivative_at_the_holding_torque_times_the_ratio_squared():
    """The motor's damping on its disk is ratio² · (−dT/dω) of Kloss's formula where it gives the torque
    that holds the load: dT/ds = 2 T_k s_k (s_k² − s²)/(s² + s_k²)², ω = ω_s (1 − s)."""
    curve = InductionMotor.from_rating("3 kW", "3000 rpm", "2880 rpm", 2.8)
    system = _pair()
    for ratio in (1.0, 2.5):
        motor = _motor(ratio=ratio)
        lin = linear_periodic(system, reference="pinion", boundary="motor", load={"gear": 60.0}, motor=motor)
        torque_shaft = 60.0 * RA / RB / ratio  # the load over the mesh ratio, then the motor's ratio
        assert lin.motor.torque(100.0) == pytest.approx(torque_shaft, rel=1e-12)
        w = lin.motor.shaft_speed(torque_shaft)
        assert float(curve.torque(w)) == pytest.approx(torque_shaft, rel=1e-10)
        s = 1.0 - w / curve.synchronous_speed
        Tk, sk = curve.pullout_torque, curve.pullout_slip
        dT_ds = 2 * Tk * sk * (sk**2 - s**2) / (s**2 + sk**2) ** 2
        assert lin.motor.damping(100.0) == pytest.approx(ratio**2 * dT_ds / curve.synchronous_speed, rel=1e-6)


def test_a_load_beyond_the_motor_s_pull_out_torque_is_refused_with_the_fix():
    with pytest.raises(ModelError, match=r"must give 400 .* reaches only 27\.85 .*pull-out"):
        steady_state(_pair(), 100.0, reference="pinion", load={"gear": 1000.0}, motor=_motor())


def test_drive_motor_without_a_motor_and_an_unknown_drive_are_refused():
    with pytest.raises(ModelError, match="needs the motor"):
        steady_state(_pair(), 100.0, reference="pinion", drive="motor")
    with pytest.raises(ModelError, match="drive 'sideways'"):
        speed_sweep(_pair(), [100.0], reference="pinion", drive="sideways")


def test_with_the_motor_the_linear_shooting_harmonic_balance_and_floquet_agree():
    """The rigid angle stays in the state (the motor's slope couples it): its multiplier 1 is set
    aside, the others inside the unit circle; shooting equals harmonic balance."""
    system = _pair(mesh_profiles={"m": {"fluctuation": 0.3, "contact_ratio": 1.6}})
    kw = {"reference": "pinion", "load": {"gear": 30.0}, "motor": _motor()}
    hb = steady_state(system, 120.0, harmonics=120, **kw)
    sh = steady_state(system, 120.0, method="shooting", substeps=8, **kw)
    assert hb.dynamic_factor == pytest.approx(sh.dynamic_factor, rel=2e-3)
    sweep = speed_sweep(system, [120.0], refine=0, **kw)
    assert 0.0 < sweep.spectral_radius[0] < 1.0


@pytest.fixture
def turret(turret_startup):
    return turret_startup[0]


def test_the_turret_s_sweep_resonates_where_the_free_train_s_first_mode_meets_the_mesh_frequency(turret):
    """The main resonance of the shipped sweep lies within 1 % of the free train's first mode over the
    mesh order (the file's 3280 rpm), not at the held motor's 2968 rpm; held, it moves there."""
    f1 = float(modal(turret.model).omega[0]) / (2 * np.pi)  # the free train's first flexible mode, Hz
    main = f1 * 60.0 / 19.0  # rpm of the motor where the 19-tooth mesh frequency meets it
    assert main == pytest.approx(3280.0, rel=5e-3)
    run = get("speed-sweep").run
    rpm = 2 * np.pi / 60
    near = {"speed_range": (3000 * rpm, 3500 * rpm), "points": 21, "no_stability": True}
    free = run(turret, **near).resonances()
    assert min(free["mesh 1"], key=lambda s: abs(s - main * rpm)) / rpm == pytest.approx(main, rel=0.01)
    held = run(turret, drive="speed", speed_range=(2800 * rpm, 3300 * rpm), points=21, no_stability=True)
    assert "held" in held.drive
    assert all(abs(s / rpm - main) > 0.05 * main for s in held.resonances()["mesh 1"])  # moved by 9 %


def test_the_turret_s_sweep_at_the_running_speed_gives_simulate_s_dynamic_factor(turret):
    """At the speed where the file's motor carries the running load, the sweep's K_v lies within 3 %
    of the time integration's (simulate from the static deflection at that speed, the last 20 mesh
    periods after the start has decayed), for both meshes."""
    dynamics = turret.settings.dynamics
    system = GearSystem.from_drivetrain(turret.model, **{**dynamics.system_options(), "backlash": {}})
    motor = dynamics.inputs()[0]
    from scipy.optimize import brentq

    load = 6.2  # N·m at the tool spindle (the file's drag and cutting torque)
    ratio = abs(system.speed_ratios("1")[system.coordinate_names.index("7")])
    ws = motor.motor.synchronous_speed
    w = brentq(lambda x: motor.motor.torque(x) - load * ratio, 0.9 * ws, ws * (1 - 1e-9))
    inputs = [motor, ConstantTorque("7", -load)]
    T_mesh = 2 * np.pi / (19 * w)
    sim = simulate(system, 0.08, inputs=inputs, initial_speed=w, reference="1", start="static", rtol=1e-9)
    last = sim.time > sim.time[-1] - 20 * T_mesh
    kv_sim = np.abs(sim.mesh_forces[:, last].T).max(axis=0) / np.abs(sim.static_mesh_forces)
    s = steady_state(system, w, reference="1", load={"7": load}, motor=motor, harmonics=120)
    assert s.dynamic_factor == pytest.approx(kv_sim, rel=0.03)
    assert "motor on disk '1'" in s.drive


def test_the_sweep_says_what_iso_s_curve_describes_beside_the_train_s_resonances(turret):
    """The train's resonances are the crossings of the mesh orders with the free train's modes (the
    file's 1640, 3280 and 4003 rpm); ISO's pair resonates at its own n_E1 over the pinion's ratio; the
    table and the plot say that the two describe different systems."""
    from mechdyn.gears import iso_dynamic_factor

    rpm = 2 * np.pi / 60
    result = get("speed-sweep").run(turret, points=12, no_stability=True)
    f = modal(turret.model).omega / (2 * np.pi)
    found = result.train_resonances()["mesh 1"]
    expected = sorted(
        (fk / (k * 19 / (2 * np.pi)))
        for fk in f
        for k in (1, 2)
        if 1200 * rpm <= fk / (k * 19 / (2 * np.pi)) <= 4500 * rpm
    )
    assert [c[3] for c in found] == pytest.approx(expected, rel=1e-6)
    assert [round(c[3] / rpm) for c in found] == [1640, 3280, 4003]
    pair = turret.settings.gear_pairs["mesh 1"]
    torque = float(np.mean(np.abs(result.static_force[:, 0]))) * pair.pinion.base_radius  # its line load
    n_e1 = iso_dynamic_factor(pair, 300.0, torque, inertias=(4.325686e-05, 5.293671e-05)).resonance_speed
    assert result.iso_resonance_speed[0] == pytest.approx(n_e1, rel=1e-9)  # the pinion turns with disk 1
    table = result.tables()[1]
    assert "not expected to agree" in table.note and "pair alone" in table.note
    doc = result.summary()["meshes"]["mesh 1"]
    assert doc["train_resonance_speeds_rad_s"] == pytest.approx(expected)
    assert doc["iso_resonance_speed_rad_s"] == pytest.approx(n_e1)
    ax = result.plots()["speed_sweep.png"]()
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("ISO 6336-1 K_v, the pair alone, resonant at 24265 rpm" in t for t in labels)
    assert {t.get_text() for t in ax.texts} >= {"mode 1 × 2", "mode 1 × 1", "mode 2 × 2"}


def test_an_unstable_orbit_is_drawn_dashed_and_never_counted_in_the_jump_band():
    """Inside a parametric instability tongue (mesh frequency near twice the free pair's mode, the
    stiffness varying by 60 %) the teeth-in-contact orbit is unstable: its K_v is drawn dashed and
    labelled so. A down sweep that differs from the up sweep only where one of them is unstable has no
    jump band."""
    import dataclasses

    system = _pair(
        mesh_profiles={"m": {"fluctuation": 0.6, "contact_ratio": 1.5}}, errors={"m": {"amplitude": 1e-6}}
    )
    wn = np.sqrt(K_MESH * (RA**2 / J1 + RB**2 / J2))
    speeds = np.linspace(1.6, 2.4, 9) * wn / ZA
    r = speed_sweep(system, speeds, reference="pinion", load={"gear": 30.0}, harmonics=32, refine=0)
    assert (~r.stable).any() and r.stable.any()
    ax = r.plots()["speed_sweep.png"]()
    dashed = [
        line for line in ax.get_lines() if line.get_linestyle() == "--" and line.get_label().startswith("_")
    ]
    assert dashed and np.isfinite(dashed[0].get_ydata()).sum() >= (~r.stable).sum()
    assert "dashed: unstable, not reached" in ax.get_legend().get_texts()[0].get_text()
    i = int(np.flatnonzero(~r.stable)[0])
    other = r.force_max.copy()
    other[i] *= 3.0  # the other sweep differs only at the unstable speed
    down = dataclasses.replace(r, force_max=other, direction="down")
    assert dataclasses.replace(r, down=down).hysteresis() == {"m": None}
    stable_down = dataclasses.replace(down, spectral_radius=np.zeros_like(r.spectral_radius))
    both_stable = dataclasses.replace(r, spectral_radius=np.zeros_like(r.spectral_radius), down=stable_down)
    assert both_stable.hysteresis()["m"] == (r.speeds[i], r.speeds[i])
