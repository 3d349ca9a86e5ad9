"""Gear pairs in the planar engine: pitch curves, closed forms, and the planting mechanism RP-1
against an independent per-angle force analysis (the published fifteen-unknown system)."""

from __future__ import annotations

import math
import sys
from dataclasses import replace

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.errors import ModelError
from mechdyn.mechanism import Body, Driver, GearJoint, Mechanism, Revolute, inverse_dynamics, kinematics
from mechdyn.mechanism.pitch import (
    circle,
    closing_centre_distance,
    conjugate,
    eccentric_circle,
    ellipse_about_focus,
    pitch_law,
    sampled,
)

sys.path.insert(0, str(EXAMPLES))
import transplanter_rp1 as rp1_script

from mechdyn.mechanism.planter import PlanterDesign, planter

BETA = math.degrees(PlanterDesign().beta)  # the arm in the drawing, deg


def _pair(curve, a, *, internal=False, profile=None, com2=None, gravity=(0.0, 0.0)):
    sign = -1.0 if internal else 1.0
    return Mechanism(
        points={"O1": (0.0, 0.0), "T1": (0.01, 0.0), "O2": (sign * a, 0.0)},
        bodies=(
            Body("g1", ("O1", "T1"), 1.0, 2e-3, "O1"),
            Body("g2", ("O2",), 3.0, 5e-3, com2 or "O2"),
        ),
        joints=(
            Revolute("A", ("ground", "g1"), "O1"),
            Revolute("B", ("ground", "g2"), "O2"),
            GearJoint("mesh", ("g1", "g2"), ("O1", "O2"), curve, internal=internal),
        ),
        driver=Driver("g1", "O1", "T1", 20.0, profile),
        gravity=gravity,
    )


@pytest.mark.parametrize("internal", [False, True])
def test_a_circular_pair_is_a_constant_ratio_and_its_torque_a_closed_form(internal):
    # θ̇ = 20(1 + 0.3 sin θ): T = (I1 + I2 k²) θ̈, the tangential tooth force I2 α2 / r2
    def profile(psi):
        w = 20.0 * (1 + 0.3 * np.sin(psi))
        return w, w * 20.0 * 0.3 * np.cos(psi)

    r1 = 0.02
    a = 0.03 if internal else 0.05
    r2 = a + r1 if internal else a - r1
    k = r1 / r2
    m = _pair(circle(r1), a, internal=internal, profile=profile)
    d = inverse_dynamics(m, 72)
    q = d.kinematics
    w1, w2 = q.qd[:, 2], q.qd[:, 5]
    np.testing.assert_allclose(w2, (k if internal else -k) * w1, rtol=1e-12)
    alpha1 = q.qdd[:, 2]
    np.testing.assert_allclose(d.driving_torque, (2e-3 + 5e-3 * k**2) * alpha1, atol=1e-9)
    force = d.joint_load("mesh", "g2")[:, :2]
    tangential = np.abs(5e-3 * q.qdd[:, 5] / r2)
    radial = tangential * math.tan(math.radians(20))
    np.testing.assert_allclose(np.linalg.norm(force, axis=1), np.hypot(tangential, radial), atol=1e-9)
    assert np.abs(d.power_balance_residual).max() < 1e-9 * np.abs(d.driving_torque * w1).max()


def test_elliptic_gears_about_their_foci_close_at_twice_the_semi_major_axis():
    e = ellipse_about_focus(0.03, 0.4)
    assert closing_centre_distance(e) == pytest.approx(0.06, rel=1e-12)
    law = pitch_law(e, 0.06)
    psi2, _ratio, _ = law(np.array([0.0, np.pi, 2 * np.pi]))
    assert psi2 == pytest.approx([0.0, -np.pi, -2 * np.pi], abs=1e-12)  # symmetric halves
    assert np.ptp(law(np.linspace(0, 2 * np.pi, 50))[1]) > 1.0  # a strongly varying ratio
    with pytest.raises(
        ModelError, match=r"does not close over one turn at centre distance 61 mm.*closes at 60 mm"
    ):
        pitch_law(e, 0.061)


def test_the_conjugate_rolls_without_slip():
    # arc lengths along the two pitch curves agree, over any part of a turn
    ecc = eccentric_circle(0.02, 0.003)
    a = closing_centre_distance(ecc)
    assert a != pytest.approx(0.04, rel=1e-4)  # two equal eccentric circles are not conjugates
    law = pitch_law(ecc, a)
    psi = np.linspace(0.0, 2.0, 4001)
    r1, dr1, _ = law.contact_radius(psi)
    _psi2, dpsi2, _ = law(psi)
    r2 = a - r1
    dr2 = -dr1 / dpsi2  # dr2/dψ2 along the mate
    s1 = np.trapezoid(np.hypot(r1, dr1), psi)
    s2 = np.trapezoid(np.hypot(r2, dr2) * np.abs(dpsi2), psi)
    assert s1 == pytest.approx(s2, rel=1e-9)
    th2, rr2 = conjugate(law, 2048)
    o = np.argsort(th2)
    mate = sampled(np.interp(2 * np.pi * np.arange(2048) / 2048, th2[o], rr2[o], period=2 * np.pi))
    assert mate.length() == pytest.approx(ecc.length(), rel=1e-5)
    assert ecc.convexity() > 0 and mate.convexity() > 0
    assert np.abs(law.pitch_tangent_lean(psi)).max() > math.radians(3)
    assert np.abs(pitch_law(circle(0.02), 0.05).pitch_tangent_lean(psi)).max() == 0


@pytest.fixture(scope="module")
def transplanter():
    return mechdyn.load(EXAMPLES / "transplanter_rp1.toml").model


def test_the_example_file_is_the_published_design(transplanter):
    assert rp1_script.toml_text() == (EXAMPLES / "transplanter_rp1.toml").read_text()
    built = inverse_dynamics(planter(), 36)
    loaded = inverse_dynamics(transplanter, 36)
    np.testing.assert_allclose(loaded.driving_torque, built.driving_torque, atol=1e-6)
    design = inverse_dynamics(mechdyn.load(EXAMPLES / "transplanter_rp1_design.toml").model, 36)
    np.testing.assert_allclose(design.driving_torque, built.driving_torque, rtol=0, atol=1e-12)


def test_the_planetary_train_keeps_power_and_reaction_balance(transplanter):
    d = inverse_dynamics(transplanter, 120)
    m, k = transplanter, d.kinematics
    power = np.abs(d.driving_torque * d.crank_speed).max()
    assert np.abs(d.power_balance_residual).max() < 1e-9 * power
    a = k.qdd.reshape(len(k.angle), -1, 3)[:, :, :2]
    expected = m.masses.sum() * np.asarray(m.gravity) - (m.masses[None, :, None] * a).sum(axis=1)
    np.testing.assert_allclose(d.shaking_force, expected, atol=1e-9 * np.abs(expected).max())
    # the planets swing, and return after a turn; the two sides run half a turn apart
    swing = np.ptp(k.q[:, 3 * m.body_index["planet 1"] + 2])
    assert math.radians(40) < swing < math.radians(80)
    f1, f2 = k.point("planet 1", "F1")[0], k.point("planet 2", "F2")[0]
    np.testing.assert_allclose(np.roll(f1, -60, axis=0), f2, atol=1e-8)  # to the Newton tolerance


def test_without_eccentricity_the_shaking_force_is_the_weight(transplanter):
    m = planter(PlanterDesign(eccentricity_ratio=0.0))
    d = inverse_dynamics(m, 36)
    np.testing.assert_allclose(d.shaking_force, [[0.0, -9.81 * m.masses.sum()]] * 36, atol=1e-9)
    assert np.abs(d.driving_torque).max() < 1e-9


def _mesh_geometry(m: Mechanism, k, i: int, j: GearJoint) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pitch point, unit pitch tangent and gear 1's outward normal of a mesh at sample i, from the
    motion and the pitch curve's formula (dr/dθ by a complex step, exact to round-off)."""
    idx = m.body_index
    q = k.q[i].reshape(-1, 3)
    phi_c = q[idx[j.carrier], 2]

    def on_carrier(p: str) -> np.ndarray:
        s = m.local(j.carrier, p)
        c, sn = math.cos(phi_c), math.sin(phi_c)
        return q[idx[j.carrier], :2] + np.array([c * s[0] - sn * s[1], sn * s[0] + c * s[1]])

    c1, c2 = on_carrier(j.points[0]), on_carrier(j.points[1])
    e = (c2 - c1) / np.linalg.norm(c2 - c1)
    phi1 = 0.0 if j.bodies[0] == "ground" else q[idx[j.bodies[0]], 2]
    theta = m.gear_laws[j.name].line_angle - (phi1 - phi_c)
    r = float(j.curve.radius(np.array([theta]))[0])
    dr = float(j.curve.radius(np.array([theta + 1e-30j]))[0].imag / 1e-30)
    t = dr * e + r * np.array([-e[1], e[0]])
    t /= np.linalg.norm(t)
    return c1 + r * e, t, np.array([t[1], -t[0]])


def _independent_forces(m: Mechanism, k, i: int) -> np.ndarray:
    """The published per-angle system: 15 unknowns — the tangential tooth force of the four meshes
    (F_n = F_t tan φ), the carrier's force on each of the four gears along and across the arm, the
    frame's force on the carrier, and the driving torque — from the Newton–Euler equations of the
    four gears and the carrier. Built here from the motion alone."""
    idx = m.body_index
    q, qdd = k.q[i].reshape(-1, 3), k.qdd[i].reshape(-1, 3)
    g = np.asarray(m.gravity)
    phi_c = q[idx["arm"], 2]
    arm_u = np.array([math.cos(math.radians(BETA) + phi_c), math.sin(math.radians(BETA) + phi_c)])
    arm_t = np.array([-arm_u[1], arm_u[0]])

    def point(body: str, p: str) -> np.ndarray:
        j = idx[body]
        s = m.local(body, p)
        c, sn = math.cos(q[j, 2]), math.sin(q[j, 2])
        return q[j, :2] + np.array([c * s[0] - sn * s[1], sn * s[0] + c * s[1]])

    def cross(r, f):
        return r[0] * f[1] - r[1] * f[0]

    gears = ["idler 1", "planet 1", "idler 2", "planet 2"]
    meshes = [j for j in m.joints if isinstance(j, GearJoint)]
    A = np.zeros((15, 15))
    b = np.zeros(15)
    row = {name: 3 * n for n, name in enumerate(gears)}
    row["arm"] = 12
    for n, j in enumerate(meshes):  # columns 0–3: F_t of each mesh, positive on gear 2
        P, t, normal = _mesh_geometry(m, k, i, j)
        u = t + math.tan(j.pressure_angle) * normal
        for body, sign in ((j.bodies[0], -1.0), (j.bodies[1], 1.0)):
            if body == "ground":
                continue
            r0 = row[body]
            G = q[idx[body], :2]
            A[r0 : r0 + 2, n] += sign * u
            A[r0 + 2, n] += sign * cross(P - G, u)
    for n, body in enumerate(gears):  # columns 4–11: the carrier's force on the gear (along, across)
        pivot = point("arm", {"idler 1": "I1", "planet 1": "P1", "idler 2": "I2", "planet 2": "P2"}[body])
        G = q[idx[body], :2]
        for c, direction in enumerate((arm_u, arm_t)):
            col = 4 + 2 * n + c
            A[row[body] : row[body] + 2, col] += direction
            A[row[body] + 2, col] += cross(pivot - G, direction)
            A[12:14, col] -= direction  # and its reaction on the carrier (centre of mass at O)
            A[14, col] -= cross(pivot - q[idx["arm"], :2], direction)
    A[12, 12] = A[13, 13] = 1.0  # columns 12, 13: the frame's force on the carrier at O
    A[14, 14] = 1.0  # column 14: the driving torque
    for body in [*gears, "arm"]:
        j = idx[body]
        mass, inertia = m.bodies[j].mass, m.bodies[j].inertia
        b[row[body] : row[body] + 2] = mass * (qdd[j, :2] - g)
        b[row[body] + 2] = inertia * qdd[j, 2]
    return np.linalg.solve(A, b)


def _published_law(m: Mechanism) -> Mechanism:
    """The mechanism with every mesh on the published linear law F_n = F_t tan φ."""
    joints = tuple(replace(j, flank="fixed") if isinstance(j, GearJoint) else j for j in m.joints)
    return replace(m, joints=joints)


def test_the_independent_fifteen_unknown_system_agrees_to_round_off(transplanter):
    m = _published_law(transplanter)
    d = inverse_dynamics(m, 24)
    k = d.kinematics
    meshes = [j for j in m.joints if isinstance(j, GearJoint)]
    for i in range(0, 24, 5):
        x = _independent_forces(m, k, i)
        assert x[14] == pytest.approx(d.driving_torque[i], rel=1e-10, abs=1e-12)
        for n, j in enumerate(meshes):
            force = d.joint_load(j.name, j.bodies[1])[i, :2]
            u = np.linalg.norm(force) / math.hypot(1.0, math.tan(j.pressure_angle))
            assert abs(x[n]) == pytest.approx(u, rel=1e-10, abs=1e-10)
        frame = d.joint_load("O", "arm")[i, :2]
        np.testing.assert_allclose(x[12:14], frame, rtol=1e-10, atol=1e-10)
        for n, name in enumerate(["I1", "P1", "I2", "P2"]):
            body = m.joints[[j.name for j in m.joints].index(name)].bodies[1]
            on_gear = d.joint_load(name, body)[i, :2]
            phi_c = k.q[i, 3 * m.body_index["arm"] + 2]
            b = math.radians(BETA) + phi_c
            along = np.array([math.cos(b), math.sin(b)])
            across = np.array([-along[1], along[0]])
            np.testing.assert_allclose(x[4 + 2 * n] * along + x[5 + 2 * n] * across, on_gear, atol=1e-10)


def test_bad_gear_pairs_are_refused():
    with pytest.raises(ModelError, match=r"element 'mesh'.*does not close"):
        _pair(eccentric_circle(0.02, 0.004), 0.05)
    with pytest.raises(ModelError, match="internal meshes are for circular gears only"):
        pitch_law(eccentric_circle(0.02, 0.004), 0.04, internal=True)
    with pytest.raises(ModelError, match="point 'X' is not in the drawing"):
        replace(
            _pair(circle(0.02), 0.05),
            joints=(GearJoint("mesh", ("g1", "g2"), ("O1", "X"), circle(0.02)),),
        )


def test_the_pair_report_flags_a_concave_pitch_curve():
    from mechdyn.mechanism.pitch import report

    lobed = sampled(0.02 * (1 + 0.3 * np.cos(3 * 2 * np.pi * np.arange(64) / 64)), "three lobes")
    assert lobed.convexity() < 0
    rep = report(pitch_law(lobed, closing_centre_distance(lobed)), math.radians(20))
    assert rep["convex"] is False and rep["mean_ratio"] == 1.0
    ok = report(
        pitch_law(eccentric_circle(0.02, 0.002), closing_centre_distance(eccentric_circle(0.02, 0.002))), 0.35
    )
    assert ok["convex"] and ok["pressure_angle_min_deg"] < 20.05 < ok["pressure_angle_max_deg"]


def test_the_teeth_push_apart_on_whichever_flank_is_loaded(transplanter):
    m = transplanter
    d = inverse_dynamics(m, 72)
    fixed = inverse_dynamics(_published_law(m), 72)
    k = d.kinematics
    rows = k.constraints.load_dependent_rows
    flipped = d.multipliers[:, rows] < 0
    assert flipped.any() and not flipped.all()  # the tangential force reverses during a turn
    for j in (g for g in m.joints if isinstance(g, GearJoint)):
        force = d.joint_load(j.name, j.bodies[1])[:, :2]
        for i in range(0, 72, 7):
            _, t, normal = _mesh_geometry(m, k, i, j)
            # on gear 2: the normal part pushes it away from gear 1, |F_t| tan φ, whatever F_t's sign
            assert force[i] @ normal == pytest.approx(
                abs(force[i] @ t) * math.tan(j.pressure_angle), abs=1e-9
            )
            assert force[i] @ normal >= 0
    # the motion, the torque and the momentum balance are the same; the bearings feel the flank
    power = np.abs(d.driving_torque * d.crank_speed).max()
    assert np.abs(d.power_balance_residual).max() < 1e-9 * power
    np.testing.assert_allclose(d.shaking_force, fixed.shaking_force, atol=1e-9)
    same = ~flipped.any(axis=1)
    on_idler, on_idler_fixed = d.joint_load("I1", "idler 1"), fixed.joint_load("I1", "idler 1")
    np.testing.assert_allclose(on_idler[same], on_idler_fixed[same], atol=1e-9)
    assert np.abs(on_idler[~same] - on_idler_fixed[~same]).max() > 1.0


def test_a_train_that_repeats_only_after_several_crank_turns_is_named():
    m = Mechanism(
        points={"O1": (0.0, 0.0), "T1": (0.01, 0.0), "O2": (0.05, 0.0), "C2": (0.06, 0.0)},
        bodies=(Body("g1", ("O1", "T1"), 1.0, 2e-3, "O1"), Body("g2", ("O2", "C2"), 3.0, 5e-3, "O2")),
        joints=(
            Revolute("A", ("ground", "g1"), "O1"),
            Revolute("B", ("ground", "g2"), "O2"),
            GearJoint("mesh", ("g1", "g2"), ("O1", "O2"), circle(0.02)),
        ),
        driver=Driver("g1", "O1", "T1", 20.0),
    )
    with pytest.raises(
        ModelError, match=r"gear 'g2' is turned by -240° .* repeats only after several crank turns"
    ):
        kinematics(m, 36)


def test_an_idler_that_would_have_to_be_two_gears_is_warned_about():
    from mechdyn.errors import ModelWarning

    m = planter()  # consistent: the sun's phase is solved for it (no warning; warnings are errors)
    joints = tuple(replace(j, orientation=math.radians(-35)) if j.name == "G1-G2" else j for j in m.joints)
    with pytest.warns(ModelWarning, match=r"gear 'idler 1' meshes in 'G1-G2' and 'G3-G2'.* 0\.87\d mm apart"):
        replace(m, joints=joints)
