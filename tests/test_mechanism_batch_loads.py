"""Every load of the batched evaluation equals the single-design engine's, variant by variant.

The batch (:func:`mechdyn.mechanism.cycle` with point arrays) computes each variant's driving
torque, frame force and moment, inertia force and output motion in one compiled pass; here each
variant is rebuilt as its own model and run through the general Newton engine
(:func:`inverse_dynamics` with ``method="newton"``), which shares none of that code, and every load
must agree at every angle: press A with its pivots moved, and random crank-rockers.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mechdyn
from conftest import EXAMPLES
from mechdyn.mechanism import cycle, inverse_dynamics
from test_mechanism_fourbar import crank_rockers


def _compare(mech, points, n=72):
    batch = cycle(mech, n, points=points)
    V = batch.angle.shape[0]
    assert batch.assembled.all()
    for v in range(V):
        variant = replace(mech, points={**mech.points, **{k: tuple(a[v]) for k, a in points.items()}})
        d = inverse_dynamics(variant, n, method="newton")
        # the single design's arrays are ordered by angle from the datum; the batch's by crank step
        order = np.argsort(batch.angle[v])
        np.testing.assert_allclose(batch.angle[v][order], d.angle, atol=1e-9)
        scale_t = np.abs(d.driving_torque).max()
        scale_f = np.abs(d.shaking_force).max()
        scale_m = np.abs(d.shaking_moment()).max() + scale_f
        np.testing.assert_allclose(batch.driving_torque[v][order], d.driving_torque, atol=1e-9 * scale_t)
        np.testing.assert_allclose(batch.shaking_force[v][order], d.shaking_force, atol=1e-9 * scale_f)
        np.testing.assert_allclose(batch.shaking_moment()[v][order], d.shaking_moment(), atol=1e-9 * scale_m)
        scale_i = np.abs(d.inertia_force).max()
        np.testing.assert_allclose(batch.inertia_force[v][order], d.inertia_force, atol=1e-9 * scale_i)
        if d.output_position is not None:
            # positions to the Newton engine's convergence (0.1 nm)
            np.testing.assert_allclose(batch.output_position[v][order], d.output_position, atol=1e-10)
        for j in mech.joints:  # every joint's force on its second body
            expected = d.joint_load(j.name, j.bodies[1])[:, :2]
            got = batch.joint_force(j.name)[v][order]
            np.testing.assert_allclose(
                got, expected, atol=1e-9 * np.abs(expected).max() + 1e-12, err_msg=j.name
            )
        # and the per-variant figures are the single design's
        single = d.summary()
        for key, values in batch.summary().items():
            if isinstance(values, dict):
                for name, peaks in values.items():
                    assert peaks[v] == pytest.approx(single[key][name], rel=1e-9), (v, key, name)
            else:
                assert values[v] == pytest.approx(single[key], rel=1e-9, abs=1e-9 * scale_f), (v, key)


def test_press_variants_load_for_load():
    press = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    rng = np.random.default_rng(7)
    points = {k: np.asarray(press.points[k]) + rng.normal(scale=0.02, size=(4, 2)) for k in ("C", "D")}
    _compare(press, points)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(crank_rockers(), st.floats(-0.01, 0.01), st.floats(-0.01, 0.01))
def test_random_fourbar_variants_load_for_load(m, dx, dy):
    # three variants: the design, its rocker pivot moved, and its coupler point moved
    O4, C = np.asarray(m.points["O4"]), np.asarray(m.points["C"])
    points = {
        "O4": np.array([O4, O4 + np.array([dx, dy]), O4]),
        "C": np.array([C, C, C + np.array([dy, dx])]),
    }
    _compare(m, points, n=48)


@pytest.mark.parametrize("datum", [0.3, "bdc"])
def test_variants_with_a_speed_profile_read_it_at_their_own_crank_angles(datum):
    # a speed profile is read at each variant's crank angle from the datum: variants drawn at other
    # crank angles (the crank tip moved round its circle) or with another bottom dead centre get their
    # own speeds, and each equals its single design
    from test_mechanism_closed_form import R, W, replace_driver, slider_crank

    m = replace_driver(replace(slider_crank(), angle_datum=datum), lambda th: W * (1 + 0.3 * np.cos(th)))
    tips = np.radians([0.0, 30.0, 100.0])
    _compare(m, {"A": R * np.stack([np.cos(tips), np.sin(tips)], axis=1)}, n=72)


def test_a_sequence_of_variant_models_is_one_batch_with_a_status_per_variant():
    from mechdyn.errors import ModelError
    from mechdyn.mechanism import Body, variants

    press = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    C = np.asarray(press.points["C"])
    heavier = replace(
        press, bodies=tuple(replace(b, mass=1.2 * b.mass, inertia=1.5 * b.inertia) for b in press.bodies)
    )
    moved = replace(
        press, points={**press.points, "D": tuple(np.asarray(press.points["D"]) + np.array([0.03, 0.01]))}
    )
    jammed = replace(press, points={**press.points, "D": (C[0] + 0.05, C[1])})  # a 50 mm rocker
    models = [press, heavier, jammed, moved]
    batch = variants(models, 72)
    assert (
        batch.status[2].startswith("variant 2: cannot assemble at crank angle")
        and "joint 'C'" in batch.status[2]
    )
    assert [s == "ok" for s in batch.status] == [True, True, False, True]
    summary = batch.summary()
    for v in (0, 1, 3):  # variant i is the single-design result of model i
        single = inverse_dynamics(models[v], 72, method="newton").summary()
        for key, values in summary.items():
            if isinstance(values, dict):
                for name, peaks in values.items():
                    assert peaks[v] == pytest.approx(single[key][name], rel=1e-9), (v, key, name)
            else:
                assert values[v] == pytest.approx(single[key], rel=1e-9, abs=1e-6), (v, key)
    # a model of another topology is refused by name
    other = replace(press, bodies=(*press.bodies[:-1], replace(press.bodies[-1], center_of_mass=(0.0, 0.0))))
    with pytest.raises(ModelError, match=r"variant 1 differs from variant 0 in its body"):
        variants([press, other], 72)
    assert Body  # the public names are importable


def test_variants_that_differ_only_in_a_mass_keep_their_inertias():
    """Models that differ only in a body's mass: the batch once scaled that body's inertia with it
    (1.8 % in the joint forces of a four-bar); variant i must stay the single design of model i."""
    from mechdyn.mechanism import variants

    fourbar = mechdyn.load(EXAMPLES / "fourbar.toml").model
    coupler = max(fourbar.bodies, key=lambda b: b.inertia)
    heavier = replace(
        fourbar,
        bodies=tuple(replace(b, mass=1.6 * b.mass) if b is coupler else b for b in fourbar.bodies),
    )
    models = [fourbar, heavier]
    batch = variants(models, 72)
    for v, model in enumerate(models):
        single = inverse_dynamics(model, 72, method="newton")
        order = np.argsort(batch.angle[v])
        for j in model.joints:
            expected = single.joint_load(j.name, j.bodies[1])[:, :2]
            np.testing.assert_allclose(
                batch.joint_force(j.name)[v][order],
                expected,
                atol=1e-9 * np.abs(expected).max(),
                err_msg=j.name,
            )
        np.testing.assert_allclose(
            batch.driving_torque[v][order],
            single.driving_torque,
            atol=1e-9 * np.abs(single.driving_torque).max(),
        )


def test_variants_of_a_geared_mechanism_run_design_by_design_with_their_status():
    # RP-1's gears do not decompose into dyads: the batch runs each design on the general engine
    from mechdyn.mechanism import DesignBatch, variants

    rp1 = mechdyn.load(EXAMPLES / "transplanter_rp1.toml").model
    heavier = replace(rp1, bodies=tuple(replace(b, mass=1.1 * b.mass) for b in rp1.bodies))
    batch = variants([rp1, heavier], 36)
    assert isinstance(batch, DesignBatch) and batch.status == ("ok", "ok")
    single = inverse_dynamics(heavier, 36).summary()
    s = batch.summary()
    assert s["driving_torque_peak_Nm"][1] == pytest.approx(single["driving_torque_peak_Nm"], rel=1e-12)
    assert s["joint_force_peak_N"]["O"][1] == pytest.approx(single["joint_force_peak_N"]["O"], rel=1e-12)
    assert s["driving_torque_peak_Nm"][1] > s["driving_torque_peak_Nm"][0]
    assert list(batch.to_frame()["status"]) == ["ok", "ok"]


def test_a_batch_takes_its_motion_solver_as_one_design_does():
    from mechdyn.mechanism import DesignBatch, newton_motion, variants

    press = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    moved = replace(
        press, points={**press.points, "C": tuple(np.asarray(press.points["C"]) + np.array([0.01, 0.0]))}
    )
    compiled = variants([press, moved], 36)
    general = variants([press, moved], 36, method=newton_motion)
    assert isinstance(general, DesignBatch) and general.status == ("ok", "ok")
    a, b = compiled.summary(), general.summary()
    for key in ("driving_torque_peak_Nm", "stroke_m", "tdc_deg", "shaking_moment_range_Nm"):
        np.testing.assert_allclose(b[key], a[key], rtol=1e-9, err_msg=key)
