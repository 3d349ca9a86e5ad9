"""Four-bars: closed forms, physical invariants over random linkages (hypothesis), and the errors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mechdyn.errors import ModelError
from mechdyn.mechanism.dynamics import inverse_dynamics
from mechdyn.mechanism.kinematics import AssemblyError, SingularPositionError, kinematics
from mechdyn.mechanism.model import Body, Driver, Mechanism, Revolute

THETA0 = math.radians(60)


def fourbar(a, b, c, d, w=10.0, masses=(1.0, 2.0, 1.5), gravity=(0.0, 0.0), theta0=THETA0):
    """Crank a about O2 = (0, 0), coupler b, rocker c about O4 = (d, 0), open branch in the drawing."""
    B = (a * math.cos(theta0), a * math.sin(theta0))
    C = _circle_cross(np.array(B), b, np.array([d, 0.0]), c, upper=True)
    pts = {"O2": (0.0, 0.0), "B": B, "C": tuple(C), "O4": (d, 0.0)}
    ma, mb, mc = masses
    return Mechanism(
        points=pts,
        bodies=(
            Body("crank", ("O2", "B"), ma, ma * a**2 / 12),
            Body("coupler", ("B", "C"), mb, mb * b**2 / 12),
            Body("rocker", ("C", "O4"), mc, mc * c**2 / 12),
        ),
        joints=(
            Revolute("O2", ("ground", "crank"), "O2"),
            Revolute("B", ("crank", "coupler"), "B"),
            Revolute("C", ("coupler", "rocker"), "C"),
            Revolute("O4", ("rocker", "ground"), "O4"),
        ),
        driver=Driver("crank", "O2", "B", w),
        gravity=gravity,
    )


def _circle_cross(p, r, q, s, upper):
    d = np.linalg.norm(q - p)
    x = (d**2 + r**2 - s**2) / (2 * d)
    h = math.sqrt(max(r**2 - x**2, 0.0))
    e = (q - p) / d
    n = np.array([-e[1], e[0]])
    return p + x * e + (h if upper else -h) * n


def exact(a, b, c, d, theta):
    """Coupler and rocker angles by circle intersection, and their rates (Norton, ch. 4 and 6)."""
    B = np.stack([a * np.cos(theta), a * np.sin(theta)], -1)
    C = np.array([_circle_cross(p, b, np.array([d, 0.0]), c, upper=True) for p in B])
    t3 = np.arctan2(C[:, 1] - B[:, 1], C[:, 0] - B[:, 0])
    t4 = np.arctan2(C[:, 1], C[:, 0] - d)
    return B, C, t3, t4


def test_fourbar_against_closed_forms():
    a, b, c, d, w = 0.05, 0.2, 0.15, 0.18, 12.0
    m = fourbar(a, b, c, d, w)
    k = kinematics(m, 360)
    th = k.crank_angle
    _, C, t3, t4 = exact(a, b, c, d, th)
    pos, _, _ = k.point("coupler", "C")
    np.testing.assert_allclose(pos, C, atol=1e-13)
    phi3 = k.q[:, 5] + t3[0] - k.q[0, 5]  # body rotation = link angle − its drawing angle
    np.testing.assert_allclose(np.unwrap(phi3), np.unwrap(t3), atol=1e-12)
    # velocity loop closure: ω3 = a ω2 sin(θ4 − θ2) / (b sin(θ3 − θ4)),
    # ω4 = a ω2 sin(θ2 − θ3) / (c sin(θ4 − θ3))
    w3 = a * w * np.sin(t4 - th) / (b * np.sin(t3 - t4))
    w4 = a * w * np.sin(th - t3) / (c * np.sin(t4 - t3))
    np.testing.assert_allclose(k.qd[:, 5], w3, atol=1e-11 * np.abs(w3).max())
    np.testing.assert_allclose(k.qd[:, 8], w4, atol=1e-11 * np.abs(w4).max())
    # accelerations against central differences of the exact rates (a check; the engine never differences)
    h = 1e-5
    _, _, t3p, t4p = exact(a, b, c, d, th + h)
    _, _, t3m, t4m = exact(a, b, c, d, th - h)
    w3p = a * w * np.sin(t4p - th - h) / (b * np.sin(t3p - t4p))
    w3m = a * w * np.sin(t4m - th + h) / (b * np.sin(t3m - t4m))
    alpha3 = (w3p - w3m) / (2 * h) * w
    np.testing.assert_allclose(k.qdd[:, 5], alpha3, atol=1e-6 * np.abs(alpha3).max())


@st.composite
def crank_rockers(draw):
    """Grashof crank–rockers: the crank is the shortest link and s + l < p + q with margin."""
    a = draw(st.floats(0.02, 0.08))
    others = draw(st.lists(st.floats(0.12, 0.4), min_size=3, max_size=3))
    b, c, d = others
    lengths = sorted([a, b, c, d])
    if lengths[0] + lengths[3] > 0.85 * (lengths[1] + lengths[2]):
        b, c, d = 0.25, 0.2, 0.22
    masses = draw(st.lists(st.floats(0.1, 5.0), min_size=3, max_size=3))
    g = draw(st.sampled_from([(0.0, 0.0), (0.0, -9.81)]))
    w = draw(st.sampled_from([5.0, -20.0, 60.0]))
    return fourbar(a, b, c, d, w, tuple(masses), g)


PROPS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@PROPS
@given(crank_rockers())
def test_invariants_of_random_fourbars(m):
    d = inverse_dynamics(m, 72)
    T = d.driving_torque
    scale = max(np.abs(T * m.driver.speed).max(), 1e-9)
    # power balance to round-off
    assert np.abs(d.power_balance_residual).max() <= 1e-9 * scale
    # frame reactions = Σ m g − Σ m a_G
    weight = np.asarray(m.gravity) * m.masses.sum()
    np.testing.assert_allclose(
        d.shaking_force, weight + d.inertia_force, atol=1e-9 * max(np.abs(d.shaking_force).max(), 1)
    )
    # Newton's third law at every joint
    for j in m.joints:
        fa, fb = d.joint_load(j.name, j.bodies[0]), d.joint_load(j.name, j.bodies[1])
        np.testing.assert_allclose(fa[:, :2], -fb[:, :2], atol=1e-9 * max(np.abs(fa).max(), 1))
    # the frame's moment (from the joint multipliers) equals the angular-momentum balance of the
    # whole mechanism about the origin, Σ r_G × m (g − a_G) − I α, from the kinematics alone
    k = d.kinematics
    nb = len(m.bodies)
    r = k.q.reshape(-1, nb, 3)[..., :2]
    a = k.qdd.reshape(-1, nb, 3)
    net = m.masses[None, :, None] * (np.asarray(m.gravity) - a[..., :2])
    balance = (r[..., 0] * net[..., 1] - r[..., 1] * net[..., 0]).sum(axis=1) - (m.inertias * a[..., 2]).sum(
        axis=1
    )
    np.testing.assert_allclose(
        d.shaking_moment((0.0, 0.0)), balance, atol=1e-9 * max(np.abs(balance).max(), 1e-6)
    )


@PROPS
@given(crank_rockers())
def test_branch_is_tracked_through_a_full_turn(m):
    k = kinematics(m, 120)
    pos, _, _ = k.point("coupler", "C")
    # the open branch keeps C above the line O2–O4 all the way round, and the motion is continuous
    assert (pos[:, 1] > 0).all()
    steps = np.linalg.norm(np.diff(np.vstack([pos, pos[:1]]), axis=0), axis=1)
    assert steps.max() < 0.2 * np.ptp(pos, axis=0).max() + 1e-9


def test_cannot_assemble_names_the_angle_and_the_joint():
    # a triple-rocker: the "crank" cannot turn all the way round
    with pytest.raises(AssemblyError, match=r"cannot assemble at crank angle .*° .*joint 'C'"):
        kinematics(fourbar(0.2, 0.15, 0.12, 0.25, theta0=math.radians(40)), 180)


def test_toggle_position_names_the_angle():
    # a change-point (parallelogram) linkage passes through a singular, collinear position
    with pytest.raises(
        SingularPositionError, match=r"singular \(toggle or dead-centre\) position at crank angle"
    ) as info:
        kinematics(fourbar(0.1, 0.3, 0.1, 0.3), 360)
    angle = float(str(info.value).split("crank angle ")[1].split("°")[0])
    assert min(abs(angle - 180), abs(angle), abs(angle - 360)) <= 1.0  # the collinear change points


def test_over_and_under_constrained_models_are_counted():
    m = fourbar(0.05, 0.2, 0.15, 0.18)
    from dataclasses import replace

    with pytest.raises(
        ModelError,
        match=r"over-constrained: 11 constraint equations .* for 9 coordinates "
        r"\(3 per body: crank, coupler, rocker\)",
    ):
        replace(m, joints=(*m.joints, Revolute("extra", ("coupler", "ground"), "C")))
    with pytest.raises(
        ModelError,
        match=r"under-constrained: 7 constraint equations for 9 coordinates .* 2 degree\(s\) of freedom",
    ):
        replace(m, joints=m.joints[:3])


def test_bad_model_references_are_named():
    m = fourbar(0.05, 0.2, 0.15, 0.18)
    from dataclasses import replace

    with pytest.raises(ModelError, match=r"element 'C', field 'point': point 'Q' is not in the drawing"):
        replace(m, joints=(*m.joints[:2], Revolute("C", ("coupler", "rocker"), "Q"), m.joints[3]))
    with pytest.raises(ModelError, match=r"element 'B', field 'bodies': body 'link' is not defined"):
        replace(m, joints=(m.joints[0], Revolute("B", ("crank", "link"), "B"), *m.joints[2:]))
    with pytest.raises(ModelError, match="must not be negative"):
        Body("x", ("B",), mass=-1.0)
