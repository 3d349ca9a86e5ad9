"""Rotating unbalance as the load on a machine on its mounts: the force and moment against U Ω² and
r × F, the floor force against the closed-form transmissibility, the speed sweep, the model file
through the command line, and bad input (issue 27, point 6)."""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.errors import ModelError, ModelFileError
from mechdyn.support import (
    Mount,
    MountedMachine,
    PeriodicLoad,
    RigidBody,
    Rotor,
    periodic_response,
    unbalance_sweep,
)

EXAMPLE = EXAMPLES / "pump_set_unbalance.toml"
RPM = 2 * math.pi / 60  # rad/s per rpm
M, K = 400.0, 1.6e6  # kg, N/m: ωn = 63.25 rad/s (10.07 Hz)
WN = math.sqrt(K / M)


def transmissibility(r: float, zeta: float) -> float:
    """T = √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)) (Rao, Mechanical Vibrations, §9.10; Harris & Piersol)."""
    return math.sqrt((1 + (2 * zeta * r) ** 2) / ((1 - r**2) ** 2 + (2 * zeta * r) ** 2))


# -- the load: U Ω² turning in the plane normal to the axis, its moment r × F ----------------------


@pytest.mark.parametrize(
    ("axis", "u", "v"),
    [
        ("x", (0, 0, 1), (0, -1, 0)),  # phase 0 points up; a positive speed turns it right-handed
        ("y", (0, 0, 1), (1, 0, 0)),
        ("z", (1, 0, 0), (0, 1, 0)),  # a vertical axis counts the phase from +x
    ],
)
def test_one_rotor_is_a_force_of_u_omega_squared_turning_about_its_axis(axis, u, v):
    rotor = Rotor("0.02 kg*m", "1480 rpm", axis)
    w = 1480 * RPM
    load = PeriodicLoad.from_unbalance(rotor)
    assert load.period == pytest.approx(60 / 1480, rel=1e-14)
    t = np.linspace(0, 3 * load.period, 301)
    f = load.value(t)
    theta = w * t
    expected = 0.02 * w**2 * (np.multiply.outer(np.cos(theta), u) + np.multiply.outer(np.sin(theta), v))
    np.testing.assert_allclose(f[:, :3], expected, atol=1e-9 * 0.02 * w**2)
    np.testing.assert_allclose(np.linalg.norm(f[:, :3], axis=1), 0.02 * w**2, rtol=1e-12)
    np.testing.assert_allclose(f[:, :3] @ rotor.axis, 0.0, atol=1e-9)  # in the plane of rotation
    np.testing.assert_allclose(f[:, 3:], 0.0, atol=1e-9)  # at the origin: no moment
    np.testing.assert_allclose(rotor.force(t), f, atol=1e-9 * 0.02 * w**2)


def test_the_phase_the_sense_and_a_direction_vector():
    w = 1000 * RPM
    a = np.array([1.0, 1.0, 0.0]) / math.sqrt(2)
    r = Rotor(0.01, -w, [2.0, 2.0, 0.0], phase="90 deg")  # any length: the direction is kept
    np.testing.assert_allclose(r.axis, a, rtol=1e-15)
    u, v = r.basis
    np.testing.assert_allclose(u, [0, 0, 1], atol=1e-15)  # up: a horizontal axis
    np.testing.assert_allclose(v, np.cross(a, u), atol=1e-15)
    t = np.linspace(0, 0.1, 57)
    theta = -w * t + math.pi / 2  # turning backwards, the heavy spot along v at t = 0
    F = 0.01 * w**2 * (np.multiply.outer(np.cos(theta), u) + np.multiply.outer(np.sin(theta), v))
    load = PeriodicLoad.from_unbalance(r)
    np.testing.assert_allclose(load.value(t)[:, :3], F, atol=1e-9 * 0.01 * w**2)


def test_units_are_converted_at_the_edge():
    a = Rotor("0.02 kg*m", "1480 rpm", "y", ("0 mm", "0 mm", "500 mm"), "30 deg")
    b = Rotor("20 kg*mm", 1480 * RPM, "y", (0.0, 0.0, 0.5), math.radians(30))
    for field in ("unbalance", "speed", "phase"):
        assert getattr(a, field) == pytest.approx(getattr(b, field), rel=1e-14)
    np.testing.assert_allclose(a.position, b.position)
    assert a.force_amplitude == pytest.approx(0.02 * (1480 * RPM) ** 2, rel=1e-14)


@pytest.mark.parametrize(("phase", "factor"), [(0.0, 2.0), (math.pi, 0.0), (math.pi / 2, math.sqrt(2))])
def test_two_rotors_add_in_phase_and_cancel_in_opposed_phase(phase, factor):
    w = 1480 * RPM
    F0 = 0.005 * w**2
    rotors = [Rotor(0.005, w, "x", name="a"), Rotor(0.005, w, "x", phase=phase, name="b")]
    load = PeriodicLoad.from_unbalance(rotors)
    f = load.value(np.linspace(0, load.period, 200, endpoint=False))
    np.testing.assert_allclose(np.linalg.norm(f[:, :3], axis=1), factor * F0, atol=1e-9 * F0)


def test_the_moment_of_an_offset_rotor_is_r_cross_f_and_opposed_rotors_make_a_couple():
    w = 3000 * RPM
    r1, r2 = np.array([0.8, -0.2, 0.6]), np.array([-0.4, -0.2, 0.6])
    one = PeriodicLoad.from_unbalance(Rotor(0.003, w, "x", r1))
    t = np.linspace(0, one.period, 97)
    f = one.value(t)
    np.testing.assert_allclose(f[:, 3:], np.cross(r1, f[:, :3]), atol=1e-9 * 0.003 * w**2)
    # a couple unbalance: no net force, a moment (r1 − r2) × F turning with the rotors
    pair = PeriodicLoad.from_unbalance(
        [Rotor(0.003, w, "x", r1, name="front"), Rotor(0.003, w, "x", r2, math.pi, name="rear")]
    )
    g = pair.value(t)
    np.testing.assert_allclose(g[:, :3], 0.0, atol=1e-9 * 0.003 * w**2)
    np.testing.assert_allclose(g[:, 3:], np.cross(r1 - r2, f[:, :3]), atol=1e-9 * 0.003 * w**2)
    assert np.linalg.norm(g[:, 3:], axis=1) == pytest.approx(1.2 * 0.003 * w**2, rel=1e-12)


@pytest.mark.parametrize(
    ("speeds", "period_turns", "orders"),
    [((1480, 2960), 1, (1, 2)), ((1000, 1500), 2, (2, 3)), ((1480, -1480), 1, (1, 1))],
)
def test_rotors_at_whole_number_ratios_share_one_period(speeds, period_turns, orders):
    rotors = [Rotor(0.001 * (k + 1), s * RPM, "y", name=f"r{k}") for k, s in enumerate(speeds)]
    load = PeriodicLoad.from_unbalance(rotors)
    assert load.period == pytest.approx(period_turns * 60 / abs(speeds[0]), rel=1e-12)
    assert set(np.nonzero(np.abs(load.coefficients).max(axis=1))[0]) == set(orders)
    t = np.linspace(0, 2 * load.period, 301)
    np.testing.assert_allclose(load.value(t), sum(r.force(t) for r in rotors), atol=1e-9 * 100)


def test_speeds_that_share_no_period_are_refused_naming_both_and_the_fix():
    rotors = [Rotor(0.001, "1480 rpm", "y", name="motor"), Rotor(0.001, "2961.3 rpm", "y", name="fan")]
    with pytest.raises(ModelError, match="whole-number ratio") as caught:
        PeriodicLoad.from_unbalance(rotors)
    message = str(caught.value)
    assert "'fan' at 2961.3 rpm" in message and "'motor' at 1480 rpm" in message
    assert "Round the speeds" in message and caught.value.field == "speed"


def test_a_scaled_load_keeps_its_rotors_scaled():
    load = PeriodicLoad.from_unbalance(Rotor(0.01, 100.0, "y"))
    double = load.scaled(2.0)
    assert double.rotors[0].unbalance == pytest.approx(0.02)
    np.testing.assert_allclose(PeriodicLoad.from_unbalance(double.rotors).coefficients, double.coefficients)
    assert load.scaled(-1.0).rotors == ()


# -- the floor force against the closed form --------------------------------------------------------


@pytest.mark.parametrize("r", [0.3, 0.9, 1.0, 1.6, 3.0])
@pytest.mark.parametrize("zeta", [0.02, 0.1, 0.4])
def test_floor_force_on_one_spring_damper_is_t_times_u_omega_squared(r, zeta):
    machine = MountedMachine.single_dof(M, K, zeta)
    w = r * WN
    rotor = Rotor(0.01, w, "y")  # a horizontal shaft: the vertical part of the force is kept
    sweep = unbalance_sweep(machine, rotor, [0.5 * w, w, 2 * w])
    i = sweep.running_index
    assert sweep.speed[i] == w
    T = transmissibility(r, zeta)
    assert sweep.transmissibility[i] == pytest.approx(T, rel=1e-10)
    assert sweep.unbalance_force[i] == pytest.approx(0.01 * w**2, rel=1e-12)
    assert sweep.floor_force[i] == pytest.approx(T * 0.01 * w**2, rel=1e-10)
    for k, s in enumerate(sweep.speed):
        assert sweep.floor_force[k] == pytest.approx(transmissibility(s / WN, zeta) * 0.01 * s**2, rel=1e-10)
    # the steady state over time agrees: F_T = k z + c ż, its amplitude located between the samples
    steady = periodic_response(machine, PeriodicLoad.from_unbalance(rotor), n_samples=256)
    assert np.ptp(steady.transmitted_force) / 2 == pytest.approx(T * 0.01 * w**2, rel=1e-4)
    # the mount rated on its own (mechdyn.mounts.isolation) is the same one degree of freedom
    own = sweep.mounts["support"]
    assert own["transmissibility_ratio"] == pytest.approx(T, rel=1e-9)
    assert own["frequency_ratio"] == pytest.approx(r, rel=1e-9)


def test_a_rigid_machine_on_four_mounts_bounces_with_the_one_dof_transmissibility():
    """A vertical rotating force through the centre of mass of a symmetric layout only bounces the
    machine: the vertical floor force is the one-degree-of-freedom one with Σk and Σc."""
    kz, cz = 4e5, 2e3
    body = RigidBody(M, (0.0, 0.0, 0.3), (30.0, 50.0, 60.0))
    corners = [(-0.5, -0.3), (0.5, -0.3), (-0.5, 0.3), (0.5, 0.3)]
    mounts = [
        Mount(f"m{i}", (x, y, 0.0), (1e5, 1e5, kz), (500.0, 500.0, cz)) for i, (x, y) in enumerate(corners)
    ]
    machine = MountedMachine(body, mounts)
    zeta = 4 * cz / (2 * math.sqrt(4 * kz * M))
    w = 1.7 * WN
    sweep = unbalance_sweep(machine, Rotor(0.01, w, "y", (0.0, 0.0, 0.3)), np.linspace(0, 3 * WN, 31))
    for s, fz, ez in zip(sweep.speed, sweep.floor_force_z, sweep.unbalance_force_z, strict=True):
        assert ez == pytest.approx(0.01 * s**2, rel=1e-12, abs=1e-12)
        assert fz == pytest.approx(transmissibility(s / WN, zeta) * 0.01 * s**2, rel=1e-9, abs=1e-12)
    assert sweep.transmissibility[0] == pytest.approx(1.0, rel=1e-12)  # quasi-static at speed 0
    # each mount rated on its own carries a quarter of the weight on a quarter of the stiffness
    for rated in sweep.mounts.values():
        assert rated["natural_frequency_hz"] == pytest.approx(WN / (2 * math.pi), rel=1e-9)
        assert rated["transmissibility_ratio"] == pytest.approx(transmissibility(1.7, zeta), rel=1e-9)


def test_the_sweep_scales_the_force_with_the_speed_squared_and_lists_the_resonances():
    machine = MountedMachine.single_dof(M, K, 0.05)
    rotors = [Rotor(0.004, 1480 * RPM, "y", name="motor"), Rotor(0.001, 2960 * RPM, "y", name="fan")]
    sweep = unbalance_sweep(machine, rotors, ["0 rpm", "500 rpm", "3000 rpm"])
    assert _rpm_list(sweep.speed) == pytest.approx([0, 500, 1480, 3000])
    ratio = sweep.unbalance_force[1:] / sweep.speed[1:] ** 2
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-6)  # two harmonics: located between samples
    # the motor's own order meets ωn at ωn, the fan's (order 2) at half of it
    np.testing.assert_allclose(sweep.resonance_speeds[:, 0], [WN / 2, WN], rtol=1e-12)
    s = sweep.summary()
    assert s["running_speed_rpm"] == pytest.approx(1480)
    assert s["unbalance_isolation_efficiency_percent"] == pytest.approx(
        100 * (1 - s["unbalance_transmissibility_ratio"])
    )
    assert "isolates" in s["unbalance_verdict"]
    frame = sweep.to_frame()
    assert list(frame["speed_rpm"]) == pytest.approx([0, 500, 1480, 3000])


def _rpm_list(w):
    return list(np.asarray(w) / RPM)


def test_a_vertical_rotor_on_the_one_dof_support_is_refused():
    machine = MountedMachine.single_dof(M, K, 0.05)
    with pytest.raises(ModelError, match=r'does not keep.*dofs = "spatial"'):
        unbalance_sweep(machine, Rotor(0.01, 100.0, "z"))


@pytest.mark.parametrize(
    ("kwargs", "field", "words"),
    [
        ({"unbalance": "0.02 kg"}, "unbalance", "[mass] * [length]"),
        ({"unbalance": 0.0}, "unbalance", "positive"),
        ({"speed": "0 rpm"}, "speed", "running speed"),
        ({"speed": "24.7 1/s"}, "speed", "says neither radians nor turns; give the speed in rpm, Hz"),
        ({"speed": "1e8 rad/s"}, "unbalance", "beyond any machine"),
        ({"axis": "w"}, "axis", '"x", "y" or "z"'),
        ({"axis": (0, 0, 0)}, "axis", "not all zero"),
        ({"position": ("1 m", "2 m")}, "position", "three lengths"),
    ],
)
def test_a_bad_rotor_is_refused_naming_the_field(kwargs, field, words):
    args = {"unbalance": "0.02 kg*m", "speed": "1480 rpm", "axis": "y"} | kwargs
    with pytest.raises(ModelError) as caught:
        Rotor(**args, name="fan")
    assert caught.value.element == "fan" and caught.value.field == field
    assert words in str(caught.value)


# -- the model file and the command line ------------------------------------------------------------


@pytest.fixture
def db(tmp_path, monkeypatch):
    path = tmp_path / "u.db"
    monkeypatch.setenv("MECHDYN_DB", str(path))
    monkeypatch.chdir(tmp_path)
    return path


def test_the_example_file_loads_its_rotors_and_speed_range():
    spec = mechdyn.load(EXAMPLE).settings
    rotors = spec.load.rotors
    assert [r.name for r in rotors] == ["motor rotor", "pump impeller"]
    assert rotors[0].unbalance == pytest.approx(645e-6) and rotors[1].unbalance == pytest.approx(488e-6)
    assert rotors[0].speed == pytest.approx(1480 * RPM)
    np.testing.assert_allclose(rotors[1].position, [0.45, 0.0, 0.45])
    assert spec.speed_range == pytest.approx((0.0, 3000 * RPM))
    assert spec.load.period == pytest.approx(60 / 1480)


def test_the_example_runs_from_the_command_line_with_its_verdict(db, capsys, tmp_path):
    plots = tmp_path / "plots"
    assert main(["support", str(EXAMPLE), "--json", "--plots", str(plots)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["warnings"] == []
    w = 1480 * RPM
    assert doc["running_speed_rpm"] == pytest.approx(1480)
    assert doc["unbalance_force_N"] == pytest.approx((645e-6 + 488e-6) * w**2, rel=1e-9)  # in phase
    assert doc["speed_range_rpm"] == pytest.approx([0.0, 3000.0])
    assert doc["unbalance_verdict"].startswith("amplifies")
    rated = doc["mount_isolation"]["motor end left"]
    assert rated["natural_frequency_hz"] == pytest.approx(150.05, abs=0.01)
    assert rated["transmissibility_ratio"] == pytest.approx(
        transmissibility(1480 / 60 / 150.05, 0.1), rel=1e-3
    )
    assert (plots / "unbalance_speed_sweep.png").stat().st_size > 10_000
    assert main(["support", str(EXAMPLE), "--cycles", "2"]) == 0
    out = capsys.readouterr().out
    assert "rotating unbalance at the running speed (1480 rpm)" in out
    assert "On its mounts the machine amplifies" in out and "Each mount on its own amplifies" in out
    assert "rotating unbalance over the speed range" in out and "largest floor force" in out


def test_the_support_analysis_of_rotors_follows_the_result_protocol():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechdyn.io import load_model
    from mechdyn.registry import get

    analysis = get("support")
    result = analysis.run(load_model(EXAMPLE), cycles=2)
    summary = result.summary()
    assert set(summary) <= set(analysis.output_units), set(summary) - set(analysis.output_units)
    json.dumps(summary)
    tables = result.tables(force_unit="kN")
    assert all(len(r) == len(t.columns) for t in tables for r in t.rows)
    assert any("[kN]" in c for t in tables for c in t.columns)
    assert {"sweep_speed_rpm", "sweep_floor_force_N", "sweep_transmissibility_ratio"} <= set(result.arrays())
    ax = result.plots()["unbalance_speed_sweep.png"]()
    assert ax.has_data() and "rpm" in ax.figure.axes[1].get_xlabel()
    plt.close("all")


def _bad_file(tmp_path, old, new):
    text = EXAMPLE.read_text()
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize(
    ("old", "new", "where", "words"),
    [
        (
            'speed = "1480 rpm"\naxis = "x"\nposition = ["0.45 m"',
            'speed = "2961.3 rpm"\naxis = "x"\nposition = ["0.45 m"',
            "[excitation] → [[rotors]] #2 (name = 'pump impeller') → speed",
            "Round the speeds to a simple ratio",
        ),
        ('unbalance = "645 g*mm"', 'unbalance = "645 g"', "unbalance", "e.g. '645 kg*m'"),
        (
            'axis = "x"',
            'axis = "w"',
            "[excitation] → [[rotors]] #1 (name = 'motor rotor') → axis",
            '"x", "y" or "z"',
        ),
        ('speed = "1480 rpm"', 'speed = "0 rpm"', "→ speed", 'give its running speed, e.g. "1480 rpm"'),
        ('speed = "1480 rpm"', 'speed = "24.6667 1/s"', "→ speed", "says neither radians nor turns"),
        (
            'speed_range = ["0 rpm", "3000 rpm"]',
            'speed_range = ["3000 rpm", "0 rpm"]',
            "[excitation]",
            'e.g. speed_range = ["0 rpm", "3000 rpm"]',
        ),
        ('speed_range = ["0 rpm", "3000 rpm"]', 'period = "1 s"', "[excitation]", "remove period"),
    ],
)
def test_a_bad_rotor_in_a_file_names_the_file_the_field_and_the_fix(tmp_path, capsys, old, new, where, words):
    path = _bad_file(tmp_path, old, new)
    with pytest.raises(ModelFileError) as caught:
        mechdyn.load(path)
    message = str(caught.value)
    assert str(path) in message and where in message and words in message, message
    # the command line says the same in one message, without a traceback
    assert main(["support", str(path), "--db", str(tmp_path / "r.db")]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and words in err and "Traceback" not in err


def test_a_rotor_table_and_a_mechanism_together_are_refused(tmp_path):
    shutil.copy(EXAMPLES / "press_link_drive.toml", tmp_path / "press_link_drive.toml")
    path = _bad_file(tmp_path, "[excitation]\n", '[excitation]\nmechanism = "press_link_drive.toml"\n')
    with pytest.raises(ModelFileError, match=r"give exactly one of .*\[\[excitation\.rotors\]\]"):
        mechdyn.load(path)
