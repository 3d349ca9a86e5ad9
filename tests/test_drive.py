"""The mechanism driven by a motor through gears and a flywheel (mechdyn.drive): energy balance,
rigid limit, an independent slider-crank ODE, Kloss's curve, flywheel sizing, start-up, the example
from the command line and bad input."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.drive import Drive, InductionMotor, TorqueSpeedCurve, drive_analysis, reduce_to_crank
from mechdyn.drive.forward import size_flywheel, steady_state
from mechdyn.errors import ModelError, ModelFileError, ModelWarning
from mechdyn.mechanism import Body, Driver, Mechanism, Prismatic, ProcessForce, Revolute, inverse_dynamics

R, L = 0.1, 0.4  # slider-crank: crank and rod, m
M_CRANK, J_CRANK = 2.0, 0.002  # kg, kg·m² about its centre (at R/2)
M_ROD, J_ROD = 3.0, 0.04  # kg, kg·m² about its centre (at L/2)
M_SLIDER = 5.0  # kg
F0 = 8e3  # N, the process force's peak


def _process(theta, position):
    """F_x = F0 sin²θ on the slider while it moves toward −x (0 < θ < π), against its motion."""
    s = np.sin(theta)
    return np.where(s > 0, F0 * s * s, 0.0), np.zeros_like(theta)


def slider_crank() -> Mechanism:
    return Mechanism(
        points={"O": (0.0, 0.0), "A": (R, 0.0), "B": (R + L, 0.0)},
        bodies=(
            Body("crank", ("O", "A"), M_CRANK, J_CRANK),
            Body("rod", ("A", "B"), M_ROD, J_ROD),
            Body("slider", ("B",), M_SLIDER),
        ),
        joints=(
            Revolute("O", ("ground", "crank"), "O"),
            Revolute("A", ("crank", "rod"), "A"),
            Revolute("B", ("rod", "slider"), "B"),
            Prismatic("guide", ("slider", "ground"), "B", 0.0),
        ),
        driver=Driver("crank", "O", "A", "100 rad/s"),
        process_forces=(ProcessForce("slider", "B", _process),),
    )


def motor() -> InductionMotor:
    return InductionMotor.from_rating("3 kW", "1500 rpm", "1420 rpm", 2.5, rotor_inertia="0.01 kg*m^2")


def closed_form_inertia(theta):
    """I(θ) of the slider-crank from its closed-form velocity coefficients (not mechdyn's kinematics):
    x_B = r cos θ + √(l² − r² sin² θ), rod angle sin β = −r sin θ / l."""
    s, c = np.sin(theta), np.cos(theta)
    root = np.sqrt(L * L - R * R * s * s)
    xb = -R * s - R * R * s * c / root
    beta = -R * c / root
    xg = -R * s + 0.5 * (xb + R * s)
    yg = 0.5 * R * c
    crank_about_pivot = J_CRANK + M_CRANK * (R / 2) ** 2
    return crank_about_pivot + M_ROD * (xg * xg + yg * yg) + J_ROD * beta * beta + M_SLIDER * xb * xb, xb


def closed_form_slope(theta, h=1e-20):
    """dI/dθ by the complex step (Squire and Trapp 1998): exact to round-off for an analytic I."""
    return np.imag(closed_form_inertia(theta + 1j * h)[0]) / h


@pytest.fixture(scope="module")
def press():
    return mechdyn.load(EXAMPLES / "press_driven.toml").model


@pytest.fixture(scope="module")
def press_result(press):
    return drive_analysis(press, 360, startup=False)


def test_energy_balance_over_a_periodic_cycle(press, press_result):
    """Motor work = process work + the train's losses over one steady cycle (no gravity in press A),
    to round-off; the process work is the forming force times the travel it acts over."""
    st, s = press_result.steady, press_result.summary()
    assert s["energy_balance_residual_relative"] < 1e-12
    assert s["gear_losses_per_stroke_J"] == st.loss_work
    assert abs(st.motor_work - (-st.process_work) - st.loss_work) / st.motor_work < 1e-10
    # ∮ F ds: 10 MN held over 20 mm and rising over 5 mm (the grid resolves the ramp's start to 0.5°)
    assert s["process_energy_per_stroke_J"] == pytest.approx(10e6 * (0.025 - 0.0025), rel=5e-3)


def test_a_huge_flywheel_gives_the_constant_speed_inverse_dynamics():
    """The rigid limit: the torque into the crank tends to the constant-speed driving torque of
    mechdyn.mechanism.inverse_dynamics, and the motor's torque to its mean."""
    mech = slider_crank()
    r = drive_analysis(Drive(mech, motor(), 15, "1e5 kg*m^2"), 360, startup=False)
    assert r.steady.fluctuation < 1e-5
    w = r.steady.mean_speed
    constant = inverse_dynamics(replace(mech, driver=replace(mech.driver, speed=w)), 360)
    T_id = constant.driving_torque  # at θ = k·1° (the datum is θ = 0, counter-clockwise: as turned)
    diff = np.abs(r.mechanism_torque - T_id).max() / np.abs(T_id).max()
    assert diff < 1e-4
    T_m = r.motor_torque
    assert np.ptp(T_m) / np.mean(T_m) < 1e-3


def test_slider_crank_forward_dynamics_matches_an_independent_ode():
    """mechdyn's steady state against dK/dθ = ½ I′ ω² + (I + J_a) θ̈, K = ½ (I(θ) + J_a) ω², with θ̈
    from the lossy stage's two cases in closed form (test_drive_train.one_stage_acceleration) and I
    from the closed-form kinematics, integrated by solve_ivp from mechdyn's starting speed."""
    from scipy.integrate import solve_ivp

    from test_drive_train import one_stage_acceleration

    mech, m = slider_crank(), motor()
    drive = Drive(mech, m, 15, "0.05 kg*m^2", efficiency=0.95)
    reduced = reduce_to_crank(mech, 720)
    theta = reduced.turned
    I_cf, _ = closed_form_inertia(theta)
    assert np.abs(reduced.inertia - I_cf).max() / I_cf.max() < 1e-10
    assert np.abs(reduced.inertia_slope - closed_form_slope(theta)).max() / I_cf.max() < 1e-8
    st = steady_state(drive, reduced)
    Ja = (0.05 + 0.01) * 15**2

    def rhs(th, K):
        inertia, xb = closed_form_inertia(th)
        w = math.sqrt(2 * K[0] / (inertia + Ja))
        fx, _ = _process(np.array(th), None)
        slope = float(closed_form_slope(np.array([th]))[0])
        rest = float(fx) * xb - 0.5 * slope * w * w
        acc = one_stage_acceleration(m.torque(15 * w), inertia, rest, 15, 0.95, 0.06)
        return [0.5 * slope * w * w + (inertia + Ja) * acc]

    K0 = 0.5 * (I_cf[0] + Ja) * st.speed[0] ** 2
    sol = solve_ivp(rhs, (0, 2 * math.pi), [K0], method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True)
    th = st.turned
    w_ode = np.sqrt(2 * sol.sol(th)[0] / (closed_form_inertia(th)[0] + Ja))
    agreement = np.abs(w_ode - st.speed).max() / st.mean_speed
    assert st.fluctuation > 0.02  # a real fluctuation is being compared
    assert agreement < 1e-7, agreement
    assert abs(sol.y[0, -1] - K0) / K0 < 1e-8  # the independent solution is periodic too


def test_kloss_curve_passes_through_the_rated_and_pullout_points():
    m = InductionMotor.from_rating("75 kW", "1500 rpm", "1480 rpm", 2.5)
    ws = 1500 * 2 * math.pi / 60
    wn = 1480 * 2 * math.pi / 60
    Tn = 75e3 / wn
    assert m.rated_torque == pytest.approx(Tn, rel=1e-12)
    assert m.torque(wn) == pytest.approx(Tn, rel=1e-12)
    assert m.torque(m.pullout_speed) == pytest.approx(2.5 * Tn, rel=1e-12)
    near = m.torque(np.array([0.999, 1.001]) * m.pullout_speed)
    assert (near < 2.5 * Tn).all()  # the pull-out point is the maximum
    assert m.torque(ws) == 0.0
    s = 0.03
    assert m.torque(ws * (1 + s)) == pytest.approx(-m.torque(ws * (1 - s)), rel=1e-12)  # generator


def test_a_tabulated_motor_interpolates_and_extends_its_last_segment():
    m = TorqueSpeedCurve.from_table([("0 rpm", "100 N*m"), ("900 rpm", "80 N*m"), ("1000 rpm", "0 N*m")])
    w = 1000 * 2 * math.pi / 60
    assert m.torque(0.45 * w) == pytest.approx(90.0)
    assert m.torque(0.9 * w) == pytest.approx(80.0)
    assert m.torque(1.05 * w) == pytest.approx(-40.0)
    assert m.no_load_speed == pytest.approx(w)


def test_flywheel_sizing_hits_the_target_fluctuation():
    mech, m = slider_crank(), motor()
    drive = Drive(mech, m, 15, 0.0)
    reduced = reduce_to_crank(mech, 720)
    J = size_flywheel(drive, reduced, 0.03)
    assert J > 0
    assert steady_state(drive.with_flywheel(J), reduced).fluctuation == pytest.approx(0.03, rel=1e-6)


def test_start_up_from_rest_reaches_the_steady_state():
    mech = slider_crank()
    with (
        pytest.warns(ModelWarning, match=r"peak torque is 0\.906 of its pull-out torque"),
        pytest.warns(ModelWarning, match=r"RMS torque is 1\.028 times its rated torque.*larger motor"),
    ):
        r = drive_analysis(Drive(mech, motor(), 15, "0.05 kg*m^2"), 360)  # a small flywheel: overloaded
    s = r.startup
    assert s is not None and s.speed[0] == 0.0
    assert s.deviation < 1e-3 and s.settled_at > s.engaged_at > 0
    assert r.summary()["startup_deviation_relative"] == s.deviation


def test_the_example_runs_from_the_command_line(tmp_path, capsys):
    from mechdyn.cli.main import main

    assert (
        main(["drive", str(EXAMPLES / "press_driven.toml"), "--no-startup", "--db", str(tmp_path / "x.db")])
        == 0
    )
    assert "speed fluctuation" in capsys.readouterr().out


def test_the_loads_at_the_real_speed_come_from_the_mechanism_with_its_speed_profile(press_result):
    """The torque the reduced model puts into the crank is the inverse dynamics' driving torque at the
    solved speed (round-off), and the mechanism with the speed profile runs its own inverse dynamics."""
    from mechdyn.drive import mechanism_at_speed

    assert press_result.summary()["torque_consistency_residual_relative"] < 1e-9
    profiled = mechanism_at_speed(press_result.reduced, press_result.steady)
    again = inverse_dynamics(profiled, 360)
    w = again.crank_speed
    assert np.ptp(w) / np.mean(w) == pytest.approx(press_result.steady.fluctuation, rel=1e-2)


def _write(tmp_path, motor_table: str, mechanism: str | None = None) -> str:
    mech = mechanism or str(EXAMPLES / "press_link_drive.toml")
    text = f"""
[model]
type = "drive"
[mechanism]
file = {mech!r}
[motor]
{motor_table}
[transmission]
ratio = 99
"""
    path = tmp_path / "bad.toml"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize(
    ("motor_table", "words"),
    [
        (
            'power = "90 kW"\nsynchronous_speed = "1500 rpm"\nrated_speed = "1485 rpm"\npullout_ratio = 0.8',
            ["[motor]", "pullout_ratio", "0.8"],
        ),
        ('power = "90 kW"\nsynchronous_speed = "1500 rpm"\npullout_ratio = 2.8', ["[motor]", "rated_speed"]),
        (
            'power = "90 kW"\nsynchronous_speed = "1500 rpm"\nrated_speed = "1500 rpm"\npullout_ratio = 2.8',
            ["[motor]", "rated_speed", "below the synchronous speed"],
        ),
        (
            'power = "90 kg"\nsynchronous_speed = "1500 rpm"\nrated_speed = "1485 rpm"\npullout_ratio = 2.8',
            ["[motor]", "power", "90 kg"],
        ),
    ],
)
def test_bad_file_input_names_the_file_field_value_and_fix(tmp_path, motor_table, words):
    path = _write(tmp_path, motor_table)
    with pytest.raises(ModelFileError) as err:
        mechdyn.load(path)
    text = str(err.value)
    assert path in text
    for w in words:
        assert w in text, text


def test_a_missing_mechanism_file_is_named(tmp_path):
    m = 'power = "90 kW"\nsynchronous_speed = "1500 rpm"\nrated_speed = "1485 rpm"\npullout_ratio = 2.8'
    path = _write(tmp_path, m, "no_such_press.toml")
    with pytest.raises(
        ModelFileError, match=r"\[mechanism\] → file.*no_such_press.toml.*relative to this file"
    ):
        mechdyn.load(path)


def test_a_bad_drive_built_in_python_names_the_field():
    with pytest.raises(ModelError, match="efficiency"):
        Drive(slider_crank(), motor(), 15, efficiency=1.5)
    with pytest.raises(ModelError, match="flywheel_shaft"):
        Drive(slider_crank(), motor(), 15, flywheel_shaft="belt")
