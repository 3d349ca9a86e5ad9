"""The closed-form dyad path against the Newton engine, and design variants in one call."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

import mechdyn
from conftest import EXAMPLES
from mechdyn.errors import ModelError
from mechdyn.mechanism.dyads import NotDecomposable, cycle, plan
from mechdyn.mechanism.dynamics import inverse_dynamics
from mechdyn.mechanism.kinematics import AssemblyError
from mechdyn.mechanism.model import Prismatic
from test_mechanism_closed_form import slider_crank
from test_mechanism_fourbar import crank_rockers, fourbar


@pytest.fixture(scope="module")
def press():
    return mechdyn.load(EXAMPLES / "press_link_drive.toml").model


def test_plans(press):
    assert [s.kind for s in plan(slider_crank())] == ["crank", "rrp", "rigid", "rigid"]
    assert [s.kind for s in plan(fourbar(0.05, 0.2, 0.15, 0.18))] == ["crank", "rrr", "rigid", "rigid"]
    assert [(s.kind, s.target) for s in plan(press) if s.kind in ("rrr", "rrp")] == [
        ("rrr", "C"),
        ("rrp", "F"),
    ]


def _agree(m, n=180):
    a = inverse_dynamics(m, n, method="dyads")
    b = inverse_dynamics(m, n, method="newton")
    ka, kb = a.kinematics, b.kinematics
    # the same grid; "bdc" is located between the samples from each solver's own positions
    np.testing.assert_allclose(ka.angle, kb.angle, rtol=0, atol=1e-12)
    dq = ka.q - kb.q
    dq[:, 2::3] = np.angle(np.exp(1j * dq[:, 2::3]))  # rotations agree up to whole turns
    scale = np.abs(kb.q[:, 0::3]).max() + np.abs(kb.q[:, 1::3]).max()
    assert np.abs(dq).max() < 1e-10 * max(scale, 1.0)
    for x, y in (
        (ka.qd, kb.qd),
        (ka.qdd, kb.qdd),
        (a.driving_torque, b.driving_torque),
        (a.shaking_force, b.shaking_force),
        (a.multipliers, b.multipliers),
    ):
        np.testing.assert_allclose(x, y, atol=1e-9 * np.abs(y).max())


def test_dyads_agree_with_newton_on_the_examples(press):
    _agree(slider_crank((0.0, -9.81)))
    _agree(press, 360)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(crank_rockers())
def test_dyads_agree_with_newton_on_random_fourbars(m):
    _agree(m, 72)


def test_variants_in_one_call_equal_single_runs(press):
    rng = np.random.default_rng(7)
    # enough variants for the threaded kernel; a single design runs on the serial one
    D = np.asarray(press.points["D"]) + rng.normal(scale=0.02, size=(12, 2))
    C = np.asarray(press.points["C"]) + rng.normal(scale=0.02, size=(12, 2))
    batch = cycle(press, 120, points={"D": D, "C": C})
    for v in range(12):
        pts = dict(press.points) | {"D": tuple(D[v]), "C": tuple(C[v])}
        single = cycle(replace(press, points=pts), 120)
        np.testing.assert_allclose(batch.driving_torque[v], single.driving_torque[0], rtol=1e-12, atol=1e-6)
        np.testing.assert_allclose(batch.output_position[v], single.output_position[0], atol=1e-12)
        np.testing.assert_allclose(batch.angle[v], single.angle[0], atol=1e-12)
    s = batch.summary()
    assert s["stroke_m"].shape == (12,) and np.all(np.abs(s["stroke_m"] - 1.495) < 0.1)


def test_mass_variants_scale_the_loads(press):
    slide = np.array([50e3, 100e3, 150e3])
    b = cycle(press, 90, masses={"slide": slide}, store_points=False)
    # everything but the slide is the same, so the torque is affine in the slide mass
    d1, d2 = b.driving_torque[1] - b.driving_torque[0], b.driving_torque[2] - b.driving_torque[1]
    np.testing.assert_allclose(d1, d2, rtol=1e-9, atol=1e-6)


def test_topologies_that_do_not_decompose_fall_back_to_newton():
    m = slider_crank()
    inverted = replace(m, joints=(*m.joints[:3], Prismatic("guide", ("ground", "slider"), "B", 0.0)))
    with pytest.raises(NotDecomposable, match="the frame cannot slide"):
        plan(inverted)
    a = inverse_dynamics(inverted, 90)  # auto: Newton
    b = inverse_dynamics(m, 90)
    np.testing.assert_allclose(a.driving_torque, b.driving_torque, atol=1e-9 * np.abs(b.driving_torque).max())


def test_a_failing_variant(press):
    # a 50 mm rocker cannot follow the 630 mm crank: the second variant fails part of the way round
    C = press.points["C"]
    D = np.array([press.points["D"], (C[0] + 0.05, C[1])])
    with pytest.raises(
        AssemblyError, match=r"variant 1: cannot assemble at crank angle .*joint 'C' .*does not close"
    ):
        cycle(press, 60, points={"D": D})
    kept = cycle(press, 60, points={"D": D}, errors="nan")
    assert kept.assembled.tolist() == [True, False]
    assert np.isfinite(kept.summary()["stroke_m"][0])


def test_a_lean_batch_says_what_it_did_not_keep(press):
    from mechdyn.errors import ModelError

    lean = cycle(press, 30, store_points=False)
    assert lean.summary()["stroke_m"].shape == (1,)
    with pytest.raises(ModelError, match=r"motion of 'C' was not kept; run cycle\(..., store_points=True\)"):
        lean.point("C")
    with pytest.raises(ModelError, match="was not kept"):
        lean.q


def test_kinetostatics_with_process_forces_equal_the_jacobian_solve(press):
    # a forming force over part of the stroke, and gravity: the dyad-by-dyad joint forces must equal
    # the multipliers of the full Jacobian solve
    from mechdyn.mechanism.model import ProcessForce

    forming = ProcessForce("slide", "F", lambda th, s: (np.where(s < 0.2, 2e5, 0.0), 0.0 * th))
    m = replace(press, process_forces=(forming,), gravity=(-9.81, 0.0))
    a = inverse_dynamics(m, 180, method="dyads")
    b = inverse_dynamics(m, 180, method="newton")
    np.testing.assert_allclose(a.multipliers, b.multipliers, atol=1e-9 * np.abs(b.multipliers).max())
    assert np.abs(a.power_balance_residual).max() < 1e-9 * np.abs(a.driving_torque * a.crank_speed).max()
    for j in m.joints:  # Newton's third law from the kinetostatic forces
        fa, fb = a.joint_load(j.name, j.bodies[0]), a.joint_load(j.name, j.bodies[1])
        np.testing.assert_allclose(fa[:, :2], -fb[:, :2], atol=1e-9 * np.abs(fa).max())


def test_the_motion_solver_is_a_callable_and_the_loads_follow_from_any_of_them(press):
    # motion from interchangeable solvers; the loads are computed downstream, from whichever motion
    from mechdyn.mechanism import dyad_motion, kinematics, newton_motion

    calls = []

    def my_solver(mech, n):
        calls.append(n)
        return newton_motion(mech, n)

    a = inverse_dynamics(press, 36, method=dyad_motion)
    b = inverse_dynamics(press, 36, method=my_solver)
    assert calls == [36]
    np.testing.assert_allclose(b.driving_torque, a.driving_torque, atol=1e-9 * np.abs(a.driving_torque).max())
    for j in press.joints:
        fa, fb = a.joint_load(j.name, j.bodies[1]), b.joint_load(j.name, j.bodies[1])
        np.testing.assert_allclose(fb, fa, atol=1e-9 * np.abs(fa).max())
    with pytest.raises(ModelError, match="must be 'auto', 'dyads', 'newton' or a callable"):
        kinematics(press, 36, method="euler")


def test_the_obliquity_of_a_connecting_rod_and_the_guide_offset_against_closed_forms():
    """An in-line slider-crank leans its rod by asin(r/l) at most, its guide through the pivot; with
    the slider's guide offset by e the largest lean is asin((r + e)/l). One design and a batch agree."""
    import math

    m = mechdyn.load(EXAMPLES / "slider_crank.toml").model  # r = 0.1 m, l = 0.4 m
    one = inverse_dynamics(m, 360).summary()
    assert one["output_link_obliquity_max_deg"] == pytest.approx(math.degrees(math.asin(0.25)), rel=1e-12)
    assert one["guide_offset_m"] == pytest.approx(0.0, abs=1e-15)
    e = 0.05  # the slider's point, and with it the guide, moved off the pivot's line
    b = np.array([math.sqrt(0.4**2 - e**2) + 0.1, e])
    batch = cycle(m, 360, points={"B": np.array([m.points["B"], b])}, store_points=False).summary()
    assert batch["output_link_obliquity_max_deg"][0] == pytest.approx(
        one["output_link_obliquity_max_deg"], rel=1e-12
    )
    assert batch["guide_offset_m"][1] == pytest.approx(e, rel=1e-12)
    assert batch["output_link_obliquity_max_deg"][1] == pytest.approx(
        math.degrees(math.asin(0.15 / 0.4)), rel=1e-9
    )
