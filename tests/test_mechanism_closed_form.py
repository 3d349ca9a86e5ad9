"""The mechanism engine against closed forms: the slider-crank of examples/slider_crank.toml."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from mechdyn.mechanism.dynamics import inverse_dynamics
from mechdyn.mechanism.model import Body, Driver, Mechanism, Prismatic, Revolute

R, L, W = 0.1, 0.4, 100.0  # crank, rod (m), crank speed (rad/s)
M_CRANK, I_CRANK, M_ROD, I_ROD, M_SLIDER = 2.0, 0.002, 3.0, 0.04, 5.0


def slider_crank(gravity=(0.0, 0.0)) -> Mechanism:
    return Mechanism(
        points={"O": (0.0, 0.0), "A": (R, 0.0), "B": (R + L, 0.0)},
        bodies=(
            Body("crank", ("O", "A"), M_CRANK, I_CRANK),
            Body("rod", ("A", "B"), M_ROD, I_ROD),
            Body("slider", ("B",), M_SLIDER, 0.0),
        ),
        joints=(
            Revolute("O", ("ground", "crank"), "O"),
            Revolute("A", ("crank", "rod"), "A"),
            Revolute("B", ("rod", "slider"), "B"),
            Prismatic("guide", ("slider", "ground"), "B", 0.0),
        ),
        driver=Driver("crank", "O", "A", W),
        gravity=gravity,
    )


def closed_form(theta):
    """Exact slider-crank kinematics (e.g. Norton, Design of Machinery, ch. 4 and 7)."""
    s, c = np.sin(theta), np.cos(theta)
    root = np.sqrt(L**2 - (R * s) ** 2)
    x = R * c + root
    beta = np.arcsin(R * s / L)  # rod angle below the axis
    dbeta = W * R * c / (L * np.cos(beta))
    ddbeta = (-(W**2) * R * s + L * np.sin(beta) * dbeta**2) / (L * np.cos(beta))
    v = -R * W * s - L * np.sin(beta) * dbeta
    a = -R * W**2 * c - L * (np.cos(beta) * dbeta**2 + np.sin(beta) * ddbeta)
    return x, v, a, -beta, -dbeta, -ddbeta


@pytest.fixture(scope="module")
def result():
    return inverse_dynamics(slider_crank(), 360)


def test_positions_velocities_accelerations(result):
    k = result.kinematics
    x, v, a, phi, dphi, ddphi = closed_form(k.crank_angle)
    pos, vel, acc = k.point("slider", "B")
    np.testing.assert_allclose(pos[:, 0], x, atol=1e-13)
    np.testing.assert_allclose(vel[:, 0], v, atol=1e-10)
    np.testing.assert_allclose(acc[:, 0], a, atol=1e-8 * np.abs(a).max())
    rod = 3 * 1 + 2
    np.testing.assert_allclose(k.q[:, rod], phi, atol=1e-13)
    np.testing.assert_allclose(k.qd[:, rod], dphi, atol=1e-10)
    np.testing.assert_allclose(k.qdd[:, rod], ddphi, atol=1e-8 * np.abs(ddphi).max())


def test_driving_torque_from_virtual_work(result):
    # T ω = d/dt (Σ ½ m v² + ½ I φ̇²): the torque from the energy rate of the exact motion
    k = result.kinematics
    _, v, a, _, dphi, ddphi = closed_form(k.crank_angle)
    th = k.crank_angle
    # centres of mass: crank at R/2, rod at the middle of A and B
    ax_c, ay_c = -R / 2 * W**2 * np.cos(th), -R / 2 * W**2 * np.sin(th)
    vx_c, vy_c = -R / 2 * W * np.sin(th), R / 2 * W * np.cos(th)
    va = np.stack([-R * W * np.sin(th), R * W * np.cos(th)], -1)
    aa = np.stack([-R * W**2 * np.cos(th), -R * W**2 * np.sin(th)], -1)
    vg = (va + np.stack([v, np.zeros_like(v)], -1)) / 2
    ag = (aa + np.stack([a, np.zeros_like(a)], -1)) / 2
    dE = (
        M_CRANK * (vx_c * ax_c + vy_c * ay_c)
        + M_ROD * np.sum(vg * ag, -1)
        + I_ROD * dphi * ddphi
        + M_SLIDER * v * a
    )
    np.testing.assert_allclose(result.driving_torque, dE / W, atol=1e-9 * np.abs(dE / W).max())
    # and the shaking force is −Σ m a_G
    shake = -(
        M_CRANK * np.stack([ax_c, ay_c], -1) + M_ROD * ag + M_SLIDER * np.stack([a, np.zeros_like(a)], -1)
    )
    np.testing.assert_allclose(result.shaking_force, shake, atol=1e-9 * np.abs(shake).max())


def test_summary_of_the_slider_crank(result):
    s = result.summary()
    assert s["stroke_m"] == pytest.approx(2 * R, abs=1e-12)
    assert (s["bdc_deg"], s["tdc_deg"]) == (180.0, 0.0)  # the axis points away from the crank: "up"
    # inertia force at the dead centres, closed form: slider a = −Rω²(1 ± R/L)
    f0 = (
        M_SLIDER * R * W**2 * (1 + R / L)
        + M_CRANK * R / 2 * W**2
        + M_ROD * (R * W**2 + R * W**2 * (1 + R / L)) / 2
    )
    assert s["inertia_force_max_N"] == pytest.approx(f0, rel=1e-9)
    assert s["power_balance_residual_relative"] < 1e-12


def test_gravity_enters_the_frame_load():
    g = (0.0, -9.81)
    d = inverse_dynamics(slider_crank(g), 90)
    weight = -9.81 * (M_CRANK + M_ROD + M_SLIDER)
    # frame load = Σ m g − Σ m a_G
    np.testing.assert_allclose(d.shaking_force[:, 1], weight + d.inertia_force[:, 1], atol=1e-9)
    assert np.abs(d.power_balance_residual).max() < 1e-9 * np.abs(d.driving_torque * W).max()


def test_joint_loads_obey_newtons_third_law(result):
    for j in result.mechanism.joints:
        a, b = j.bodies
        fa, fb = result.joint_load(j.name, a), result.joint_load(j.name, b)
        np.testing.assert_allclose(fa[:, :2], -fb[:, :2], atol=1e-9 * np.abs(fa).max())


def test_speed_sign_and_angles():
    m = slider_crank()
    from dataclasses import replace

    rev = inverse_dynamics(replace(m, driver=Driver("crank", "O", "A", -W)), 36)
    assert rev.summary()["stroke_m"] == pytest.approx(2 * R)
    assert math.isclose(float(rev.angle[0]), 0.0, abs_tol=1e-12)


def test_process_force_enters_torque_and_power():
    # a constant force P opposing the slider over the whole cycle adds P v / ω to the torque
    from dataclasses import replace

    from mechdyn.mechanism.model import ProcessForce

    P = 500.0
    base = slider_crank()
    pushed = replace(
        base, process_forces=(ProcessForce("slider", "B", lambda th, s: (np.full_like(th, -P), 0.0 * th)),)
    )
    d0, d1 = inverse_dynamics(base, 120), inverse_dynamics(pushed, 120)
    _, v, _, _, _, _ = closed_form(d1.kinematics.crank_angle)
    # T ω + F·v = dE/dt with F·v = −P v: the motor supplies P v / ω more
    np.testing.assert_allclose(d1.driving_torque - d0.driving_torque, P * v / W, atol=1e-9 * P * R)
    assert np.abs(d1.power_balance_residual).max() < 1e-9 * np.abs(d1.driving_torque * W).max()
    # frame load = Σ external forces − Σ m a_G: the process force appears in it one to one
    np.testing.assert_allclose(d1.shaking_force[:, 0] - d0.shaking_force[:, 0], -P, atol=1e-9 * P)


@pytest.mark.parametrize("method", ["dyads", "newton"])
def test_speed_profile_on_a_lone_crank(method):
    # a rotor on its pivot: T = I_O θ̈ with I_O = I_G + m d², θ̇ = ω₀ (1 + ε sin ψ), θ̈ = θ̇ dθ̇/dψ
    from mechdyn.mechanism.model import Body, Driver, Mechanism, Revolute

    w0, eps, m, d, ig = 10.0, 0.2, 3.0, 0.05, 0.01

    def profile(psi):
        w = w0 * (1 + eps * np.sin(psi))
        return w, w * w0 * eps * np.cos(psi)

    rotor = Mechanism(
        points={"O": (0.0, 0.0), "T": (0.1, 0.0)},
        bodies=(Body("rotor", ("O", "T"), m, ig, (d, 0.0)),),
        joints=(Revolute("O", ("ground", "rotor"), "O"),),
        driver=Driver("rotor", "O", "T", w0, profile),
    )
    r = inverse_dynamics(rotor, 72, method=method)
    psi = r.kinematics.crank_angle
    w, a = profile(psi)
    np.testing.assert_allclose(r.crank_speed, w, rtol=1e-12)
    np.testing.assert_allclose(r.driving_torque, (ig + m * d**2) * a, atol=1e-12 * np.abs(a).max())
    # the frame takes −m a_G: centripetal and tangential parts
    aG = d * np.stack([-(w**2) * np.cos(psi) - a * np.sin(psi), -(w**2) * np.sin(psi) + a * np.cos(psi)], -1)
    np.testing.assert_allclose(r.shaking_force, -m * aG, atol=1e-12 * m * d * w0**2)
    # time is ∫ dψ / θ̇
    assert r.kinematics.time[1] == pytest.approx(
        float(np.trapezoid(1 / profile(np.linspace(0, psi[1], 2001))[0], np.linspace(0, psi[1], 2001))),
        rel=1e-6,
    )


@pytest.mark.parametrize("method", ["dyads", "newton"])
@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_a_speed_profile_is_read_at_the_crank_angle_from_the_datum(method, sense):
    # a rotor drawn at 60° whose angle datum is 20°: at the crank angle θ from the datum that the
    # results show, the speed is the profile's θ̇(θ) and T = I_O θ̈ with θ̈ = θ̇ dθ̇/dθ, whichever way it
    # turns (the profile was once read at the angle turned from the drawing: 40° off, mirrored when
    # turning clockwise)
    from scipy.integrate import quad

    from mechdyn.mechanism.model import Body, Driver, Mechanism, Revolute

    w0, eps, m, d, ig = 10.0 * sense, 0.2, 3.0, 0.05, 0.01
    draw, datum = math.radians(60.0), math.radians(20.0)

    def profile(theta):
        w = w0 * (1 + eps * np.sin(theta))
        return w, w * w0 * eps * np.cos(theta)

    u = np.array([math.cos(draw), math.sin(draw)])
    rotor = Mechanism(
        points={"O": (0.0, 0.0), "T": tuple(0.1 * u)},
        bodies=(Body("rotor", ("O", "T"), m, ig, tuple(d * u)),),
        joints=(Revolute("O", ("ground", "rotor"), "O"),),
        driver=Driver("rotor", "O", "T", w0, profile),
        angle_datum=datum,
    )
    r = inverse_dynamics(rotor, 72, method=method)
    np.testing.assert_allclose(r.angle, np.radians(np.arange(72) * 5.0), atol=1e-12)
    w, a = profile(r.angle)
    np.testing.assert_allclose(r.crank_speed, w, rtol=1e-12)
    np.testing.assert_allclose(r.driving_torque, (ig + m * d**2) * a, atol=1e-12 * np.abs(a).max())
    # the time to each sample from the drawing is ∫ dθ/θ̇ along the way it turns
    start = draw - datum
    for k in (5, 30, 61):
        turned = (sense * (r.angle[k] - start)) % (2 * math.pi)
        expected = quad(lambda x: 1 / abs(profile(start + sense * x)[0]), 0.0, turned)[0]
        assert r.kinematics.time[k] == pytest.approx(expected, rel=1e-6)


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_a_speed_profile_counts_from_the_located_bottom_dead_centre(sense):
    # angle_datum = "bdc": the profile is read from the slider's lowest position (180° from the
    # drawing here), which the motion finds first; both engines agree and the power balances
    def speed(theta):
        return sense * W * (1 + 0.3 * np.cos(theta))

    m = slider_crank()
    m = replace(m, angle_datum="bdc", driver=replace(m.driver, speed=sense * W, profile=speed))
    a = inverse_dynamics(m, 120, method="dyads")
    b = inverse_dynamics(m, 120, method="newton")
    for r in (a, b):
        assert r.summary()["bdc_deg"] == pytest.approx(0.0, abs=1e-9)
        np.testing.assert_allclose(r.crank_speed, speed(r.angle), rtol=1e-9)
        assert np.abs(r.power_balance_residual).max() < 1e-9 * np.abs(r.driving_torque * r.crank_speed).max()
    np.testing.assert_allclose(a.driving_torque, b.driving_torque, atol=1e-9 * np.abs(b.driving_torque).max())
    # the fastest point of the turn is at bottom dead centre, where the slider is lowest
    assert np.abs(a.crank_speed).argmax() == 0 and a.output_position.argmin() == 0


def test_speed_profile_keeps_power_balance_and_paths_agree():
    m = slider_crank()
    prof = replace_driver(
        m,
        lambda psi: (
            W * (1 + 0.3 * np.cos(2 * psi)),
            W * (1 + 0.3 * np.cos(2 * psi)) * W * -0.6 * np.sin(2 * psi),
        ),
    )
    a = inverse_dynamics(prof, 120, method="dyads")
    b = inverse_dynamics(prof, 120, method="newton")
    assert np.abs(a.power_balance_residual).max() < 1e-9 * np.abs(a.driving_torque * a.crank_speed).max()
    np.testing.assert_allclose(a.driving_torque, b.driving_torque, atol=1e-9 * np.abs(b.driving_torque).max())


def replace_driver(m, profile):
    from dataclasses import replace

    d = m.driver
    return replace(m, driver=replace(d, profile=profile))


def test_a_speed_profile_in_python_is_checked_or_derived():
    # the file route derives θ̈ = θ̇ dθ̇/dθ from its table; a profile given in Python is held to
    # the same law, or derived from the speed alone
    from mechdyn.errors import ModelError
    from mechdyn.mechanism.model import Driver

    def speed(psi):
        return W * (1 + 0.3 * np.cos(2 * psi))

    exact = replace_driver(slider_crank(), lambda psi: (speed(psi), speed(psi) * W * -0.6 * np.sin(2 * psi)))
    derived = replace_driver(slider_crank(), speed)
    a, b = inverse_dynamics(exact, 120), inverse_dynamics(derived, 120)
    np.testing.assert_allclose(b.driving_torque, a.driving_torque, atol=1e-6 * np.abs(a.driving_torque).max())
    assert np.abs(b.power_balance_residual).max() < 1e-9 * np.abs(b.driving_torque * b.crank_speed).max()
    # an acceleration that forgot the chain rule (dθ̇/dψ instead of θ̇ dθ̇/dψ) is refused with its size
    with pytest.raises(ModelError, match=r"does not follow from its speed.*\(mismatch (0\.9|1)"):
        Driver("crank", "O", "A", W, lambda psi: (speed(psi), W * -0.6 * np.sin(2 * psi)))
    with pytest.raises(ModelError, match="not periodic"):
        Driver("crank", "O", "A", W, lambda psi: W * (1 + 0.01 * psi))
    # clockwise: θ̈ = θ̇ dθ̇/dθ with θ̇ < 0, against the crank angle θ (counter-clockwise)
    Driver("crank", "O", "A", -W, lambda th: (-speed(th), -speed(th) * W * 0.6 * np.sin(2 * th)))
    with pytest.raises(ModelError, match="does not follow from its speed"):  # |θ̇| for θ̇ is mirrored
        Driver("crank", "O", "A", -W, lambda th: (-speed(th), speed(th) * W * 0.6 * np.sin(2 * th)))


def test_power_balance_of_a_balanced_rotor_reads_as_round_off():
    """A rotor turning about its centre of mass (the mean of three symmetric points, so off the pivot by
    a round-off) at constant speed: every power term is a round-off, and the residual once read as
    their ratio (1.0). Judged against the power that flows (at least the kinetic energy per radian)
    it is round-off."""
    from mechdyn.mechanism.model import Body, Driver, Mechanism, Revolute

    rotor = Mechanism(
        points={
            "A": (-0.8958109936825358, 1.8939466929405893),
            "O": (-1.021609701005447, 1.7305722205704264),
            "B": (-1.1474084083283582, 1.5671977482002635),
        },
        bodies=(Body("rotor", ("A", "O", "B"), 3.0, 0.01),),
        joints=(Revolute("O", ("ground", "rotor"), "O"),),
        driver=Driver("rotor", "O", "A", 1.5708),
    )
    r = inverse_dynamics(rotor, 72)
    assert np.abs(r.driving_torque).max() < 1e-12
    # at least E ω = ½ I ω² ω (the centre of mass is on the pivot to round-off)
    assert r.power_scale == pytest.approx(0.5 * 0.01 * 1.5708**3, rel=1e-9)
    assert r.summary()["power_balance_residual_relative"] < 1e-14
    # an unbalanced one is judged against the power that flows, and stays round-off too
    loaded = inverse_dynamics(slider_crank(), 120)
    assert loaded.power_scale >= np.abs(loaded.driving_torque * loaded.crank_speed).max()
    assert loaded.summary()["power_balance_residual_relative"] < 1e-12


def _lone_rotor(force=None):
    """A rotor pivoted at O = (0.4, 0.1), its centre of mass G a distance d along O→T, at constant ω."""
    from mechdyn.mechanism.model import Body, Driver, Mechanism, ProcessForce, Revolute

    o, t, d = np.array([0.4, 0.1]), np.array([0.7, 0.5]), 0.2  # |OT| = 0.5
    g = o + d * (t - o) / 0.5
    return Mechanism(
        points={"O": tuple(o), "T": tuple(t)},
        bodies=(Body("rotor", ("O", "T"), 2.0, 0.03, tuple(g)),),
        joints=(Revolute("O", ("ground", "rotor"), "O"),),
        driver=Driver("rotor", "O", "T", 3.0),
        process_forces=() if force is None else (ProcessForce("rotor", "T", force),),
    )


@pytest.mark.parametrize("method", ["dyads", "newton"])
def test_a_process_force_away_from_the_centre_of_mass_brings_its_moment(method):
    """F = (Fx, Fy) at T, 0.5 m from the pivot: the motor holds T_drive = −(r_T − r_O) × F (constant ω),
    the frame takes F − m a_G and, about O, the motor's reaction −T_drive."""
    fx, fy = 1200.0, -800.0
    rotor = _lone_rotor(lambda th, s: (np.full_like(th, fx), np.full_like(th, fy)))
    r = inverse_dynamics(rotor, 36, method=method)
    g = r.kinematics.q[:, :2]  # the centre of mass, on O→T
    phi = np.arctan2(g[:, 1] - 0.1, g[:, 0] - 0.4)  # direction O→T
    arm = 0.5 * np.stack([np.cos(phi), np.sin(phi)], -1)
    torque = -(arm[:, 0] * fy - arm[:, 1] * fx)
    np.testing.assert_allclose(r.driving_torque, torque, atol=1e-9 * 600)
    centripetal = -(3.0**2) * 0.2 * np.stack([np.cos(phi), np.sin(phi)], -1)  # a_G
    np.testing.assert_allclose(r.shaking_force, np.array([fx, fy]) - 2.0 * centripetal, atol=1e-9 * 1200)
    np.testing.assert_allclose(r.shaking_moment(about=(0.4, 0.1)), -torque, atol=1e-9 * 600)


def test_shaking_moment_about_a_point_moves_with_the_point():
    """An unbalanced rotor at constant ω: the frame takes the centrifugal force m ω² (G − O) at O and
    no torque, so its moment about any point P is (O − P) × m ω² (G − O): zero about O."""
    r = inverse_dynamics(_lone_rotor(), 36)
    g = r.kinematics.q[:, :2]
    phi = np.arctan2(g[:, 1] - 0.1, g[:, 0] - 0.4)
    f = 2.0 * 3.0**2 * 0.2 * np.stack([np.cos(phi), np.sin(phi)], -1)
    np.testing.assert_allclose(r.shaking_force, f, atol=1e-12 * 3.6)
    for p in [(0.0, 0.0), (0.4, 0.1), (-0.5, 0.8), (2.0, -1.0)]:
        lever = np.array([0.4, 0.1]) - np.array(p)
        expected = lever[0] * f[:, 1] - lever[1] * f[:, 0]
        np.testing.assert_allclose(r.shaking_moment(about=p), expected, atol=1e-12 * 10)


def _quick_return(output=None, ram=False):
    """An inverted slider-crank: the crank pin's block slides in a slot of a rocker (a moving guide);
    with ``ram``, a second slider on the frame driven by the rocker's tip."""
    from mechdyn.mechanism.model import Body, Driver, Mechanism, Prismatic, Revolute

    pts = {"O": (0.0, 0.0), "A": (0.1, 0.0), "O4": (0.0, -0.3), "R": (0.2, 0.3), "S": (0.5, 0.4)}
    bodies = [
        Body("crank", ("O", "A"), 1.0, 0.01),
        Body("block", ("A",), 0.5, 0.001),
        Body("rocker", ("O4", "A", "R"), 3.0, 0.05),
    ]
    joints = [
        Revolute("O", ("ground", "crank"), "O"),
        Revolute("A", ("crank", "block"), "A"),
        Prismatic("slot", ("block", "rocker"), "A", math.atan2(0.3, 0.1)),
        Revolute("O4", ("rocker", "ground"), "O4"),
    ]
    if ram:
        bodies += [Body("link", ("R", "S"), 1.0, 0.01), Body("ram", ("S",), 20.0, 0.1)]
        joints += [
            Revolute("R", ("rocker", "link"), "R"),
            Revolute("S", ("link", "ram"), "S"),
            Prismatic("ways", ("ram", "ground"), "S", 0.0),
        ]
    return Mechanism(
        points=pts,
        bodies=tuple(bodies),
        joints=tuple(joints),
        driver=Driver("crank", "O", "A", 5.0),
        output=output,
    )


def test_a_slider_on_a_moving_guide_is_not_taken_for_the_stroke():
    """The block in the rocker's slot once became the "stroke" (0.2 m, no word) when no output was set."""
    m = _quick_return()
    assert m.output_joint() is None
    assert "stroke_m" not in inverse_dynamics(m, 72).summary()
    # named, it is the output; a slider on the frame is the default one
    assert _quick_return(output=("block", "A")).output_joint().name == "slot"
    shaper = _quick_return(ram=True)
    assert shaper.output_joint().name == "ways"
    s = inverse_dynamics(shaper, 180).summary()
    assert s["stroke_m"] > 0 and s["return_stroke_deg"] < s["working_stroke_deg"]  # a quick return


def test_several_sliders_on_the_frame_ask_which_is_the_stroke():
    from dataclasses import replace

    from mechdyn.errors import ModelError
    from mechdyn.mechanism.model import Prismatic

    m = slider_crank()
    second = Prismatic("second", ("slider", "ground"), "B", 0.0)
    with pytest.raises(ModelError, match=r"2 sliders run on the frame .*output = \[body, point\]"):
        replace(m, joints=(*m.joints, second), output=None)
