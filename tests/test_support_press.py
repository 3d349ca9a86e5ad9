"""Press A on its supports (the examples), the mechanism's load in the machine, and bad input."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.errors import ModelError, ModelFileError
from mechdyn.mechanism import inverse_dynamics
from mechdyn.support import (
    PLANAR,
    Mount,
    MountedMachine,
    PeriodicLoad,
    Placement,
    RigidBody,
    modes,
    periodic_response,
    startup_response,
)

TONF = 9806.65


@pytest.fixture(scope="module")
def on_support():
    return mechdyn.load(EXAMPLES / "press_on_support.toml").settings


@pytest.fixture(scope="module")
def on_mounts():
    return mechdyn.load(EXAMPLES / "press_on_mounts.toml").settings


def test_press_on_its_support_transmits_the_inertia_force_quasi_statically(on_support):
    # published (SPEC §2): F_T follows F in size and phase; fluctuation 86 against 83 tonf;
    # bed displacement about +1.24 / −0.56 mm
    r = periodic_response(on_support.machine, on_support.load)
    F, FT, z = r.exciting_force, r.transmitted_force, r.vertical_displacement
    assert np.ptp(F) / TONF == pytest.approx(83.8, abs=0.1)  # the mechanism's fluctuation
    assert np.ptp(FT) / TONF == pytest.approx(86.0, abs=0.1)
    assert np.corrcoef(F, FT)[0, 1] > 0.999  # in phase
    assert int(np.argmax(FT)) == int(np.argmax(F))
    assert 1.1e-3 < z.max() < 1.35e-3 and -0.75e-3 < z.min() < -0.5e-3
    # 15 rpm against a 4.36 Hz support: quasi-static, z ≈ F/k to a few per cent
    assert np.abs(z - F / 4.5e8).max() < 0.05 * np.ptp(z)


def test_the_load_of_the_press_is_its_shaking_force_along_the_slide(on_support):
    d = on_support.dynamics
    up = np.array([math.cos(d.mechanism.output_joint().axis), math.sin(d.mechanism.output_joint().axis)])
    load = on_support.load
    # the samples follow the crank at 15 rpm from the one nearest bottom dead centre (0.0004° past it)
    assert load.period == pytest.approx(4.0)
    np.testing.assert_allclose(np.degrees(load.angle), np.arange(360) + 0.000392, atol=1e-6)
    np.testing.assert_allclose(load.value(load.time(360))[:, 2], d.shaking_force @ up, atol=1e-6)


def test_the_mechanism_moment_is_carried_to_the_machine_origin():
    # a slider-crank placed off the origin: the machine moment = r × F + the drawing's moment
    spec = mechdyn.load(EXAMPLES / "slider_crank.toml").settings
    d = inverse_dynamics(spec.mechanism, 72)
    place = Placement((0.5, -0.2, 1.3), (0.0, 0.0, 1.0), (-1.0, 0.0, 0.0))
    load = PeriodicLoad.from_mechanism(d, place)
    f = load.value(load.time(72))
    F = d.shaking_force[:, :1] * place.x_axis + d.shaking_force[:, 1:] * place.y_axis
    order = np.argsort(np.mod(d.kinematics.time - d.kinematics.time[0], load.period))
    np.testing.assert_allclose(f[:, :3], F[order], atol=1e-6 * np.abs(F).max())
    ez = np.cross(place.x_axis, place.y_axis)
    M = d.shaking_moment()[:, None] * ez + np.cross(place.origin, F)
    np.testing.assert_allclose(f[:, 3:], M[order], atol=1e-6 * np.abs(M).max())


def test_press_on_four_mounts(on_mounts, on_support):
    mm = on_mounts.machine
    r = periodic_response(mm, on_mounts.load)
    assert np.abs(r.force_balance_residual).max() < 1e-6 * np.abs(r.floor_force).max()
    # the slide runs on the vertical line through the centre of mass: the bounce is the 1-DOF model
    # (to the rounding of the mounts' damping in the file, 4.11e5 for 4.108e5 N·s/m)
    one = periodic_response(on_support.machine, on_support.load)
    np.testing.assert_allclose(
        r.transmitted_force, one.transmitted_force, atol=1e-6 * np.abs(one.transmitted_force).max()
    )
    # the links push sideways and rock the machine: the mounts share the vertical force unequally
    fz = r.mount_forces[:, :, 2]
    assert np.abs(r.floor_force[:, 0]).max() > 1e3
    assert not np.allclose(fz[:, 0], fz[:, 1])
    md = modes(mm)
    assert md.frequencies_hz.size == 6 and md.frequencies_hz[0] > 1.0
    assert set(md.dominant) == {"x", "y", "z", "rx", "ry", "rz"}
    # the spatial model of a layout symmetric about x–z equals the planar one for this in-plane load
    planar = replace(mm, dofs=PLANAR)
    rp = periodic_response(planar, on_mounts.load)
    np.testing.assert_allclose(rp.floor_force, r.floor_force, atol=1e-6 * np.abs(r.floor_force).max())


def test_start_up_of_the_press_reaches_the_steady_state(on_mounts):
    mm, load = on_mounts.machine, on_mounts.load
    # the sway–pitch modes (1.6–1.8 Hz) die out slowest: 12 periods take them below 1e-6
    start = startup_response(mm, load, 12)
    last = start.time >= start.time[-1] - load.period
    steady = periodic_response(mm, load, time=start.time[last])
    assert (
        np.abs(start.displacement[last] - steady.displacement).max()
        < 1e-6 * np.abs(steady.displacement).max()
    )


# -- bad input --------------------------------------------------------------------------------


def _body():
    return RigidBody(1000.0, (0.0, 0.0, 0.5), (100.0, 100.0, 100.0))


def test_negative_stiffness_is_refused():
    with pytest.raises(ModelError, match=r"element 'left', field 'stiffness'.*every component must be ≥ 0"):
        Mount("left", (0, 0, 0), (1e5, -1e5, 1e6))
    with pytest.raises(ModelError, match=r"field 'stiffness'.*must be positive"):
        MountedMachine.single_dof(1000.0, -1e6, 0.05)


def test_mounts_that_cannot_carry_the_body_are_refused():
    # the centre of mass beyond the mounts: the far mount would be pulled
    body = RigidBody(1000.0, (2.0, 0.0, 0.5), (100.0, 100.0, 100.0))
    mounts = [
        Mount(n, (x, y, 0.0), (1e5, 1e5, 1e6))
        for n, x, y in (("a", -1, -1), ("b", 1, -1), ("c", -1, 1), ("d", 1, 1))
    ]
    with pytest.raises(ModelError, match=r"element 'a'.*pulled up.*anchored = true"):
        MountedMachine(body, mounts)
    anchored = [replace(m, anchored=True) for m in mounts]
    MountedMachine(body, anchored)  # bolted down, it stands


@pytest.mark.parametrize(
    ("mounts", "motion"),
    [
        # all on one line along x: nothing resists rolling about x
        (
            [Mount(n, (x, 0.0, 0.0), (1e5, 1e5, 1e6)) for n, x in (("a", -1), ("b", 0), ("c", 1))],
            "rolling about x",
        ),
        # vertical springs only: nothing holds the machine sideways
        (
            [Mount(n, (x, y, 0.0), (0, 0, 1e6)) for n, x, y in (("a", -1, -1), ("b", 1, -1), ("c", 0, 1))],
            "along",
        ),
    ],
)
def test_an_unstable_layout_is_refused(mounts, motion):
    with pytest.raises(ModelError, match=f"do not resist .*{motion}.*unstable"):
        MountedMachine(_body(), mounts)


def test_a_rotation_without_inertia_is_refused():
    mounts = [Mount(n, (x, 0.0, 0.0), (1e5, 1e5, 1e6)) for n, x in (("a", -1), ("b", 1))]
    with pytest.raises(ModelError, match="moment of inertia about y is zero"):
        MountedMachine(RigidBody(1000.0), mounts, PLANAR)


def _write(tmp_path, text):
    p = tmp_path / "m.toml"
    p.write_text('[model]\ntype = "support"\n' + text)
    return p


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            '[machine]\nmass = "1 t"\n[support]\nstiffness = "1e6 N/m"\ndamping_ratio = 0.05\n'
            '[excitation]\nmechanism = "nope.toml"\n',
            "[excitation] → mechanism: 'nope.toml': no such file",
        ),
        (
            '[machine]\nmass = "1 t"\n[support]\nstiffness = "1e6 N/m"\ndamping_ratio = 0.05\n'
            '[excitation]\nperiod = "1 s"\nforce_z = ["1 N", "2 N"]\nharmonics = [[1, "1 N", "0 deg"]]\n',
            "give exactly one of mechanism",
        ),
        (
            '[machine]\nmass = "1 t"\n[support]\nstiffness = "1e6 N"\ndamping_ratio = 0.05\n'
            '[excitation]\nperiod = "1 s"\nforce_z = ["1 N", "2 N"]\n',
            "[support] → stiffness: '1e6 N' is in N",
        ),
        (
            '[machine]\nmass = "1 t"\n[excitation]\nperiod = "1 s"\nforce_z = ["1 N", "2 N"]\n',
            "give either [support]",
        ),
        (
            '[machine]\nmass = "1 t"\n[[mounts]]\nname = "a"\nposition = ["0 m", "0 m", "0 m"]\n'
            'stiffness = ["1 N/m", "1 N/m", "-1 N/m"]\n'
            '[excitation]\nperiod = "1 s"\nforce_z = ["1 N", "2 N"]\n',
            "[[mounts]] #1 (name = 'a') → stiffness",
        ),
        (
            '[machine]\nmass = "1 t"\n[support]\nstiffness = "1e6 N/m"\ndamping_ratio = 0.05\n'
            '[excitation]\nperiod = "1 s"\nharmonics = [[0, "1 N", "0 deg"]]\n',
            "[excitation]: harmonic order 0 must be ≥ 1",
        ),
    ],
)
def test_file_errors_name_the_table_and_field(tmp_path, text, message):
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(_write(tmp_path, text))
    assert message in str(info.value)


def test_a_file_with_samples_and_one_with_harmonics(tmp_path):
    base = '[machine]\nmass = "1 t"\n[support]\nstiffness = "1e6 N/m"\ndamping_ratio = 0.05\n'
    s = mechdyn.load(
        _write(tmp_path, base + '[excitation]\nperiod = "0.5 s"\nforce_z = ["0 N", "1 kN", "0 N", "-1 kN"]\n')
    ).settings
    np.testing.assert_allclose(s.load.value(s.load.time(4))[:, 2], [0, 1e3, 0, -1e3], atol=1e-9)
    h = mechdyn.load(
        _write(tmp_path, base + '[excitation]\nperiod = "0.5 s"\nharmonics = [[1, "1 kN", "-90 deg"]]\n')
    ).settings
    np.testing.assert_allclose(h.load.value(s.load.time(4))[:, 2], [0, 1e3, 0, -1e3], atol=1e-9)


def test_a_crank_with_a_speed_profile_loads_the_machine_at_its_own_times():
    # the samples are equal steps of crank angle, not of time: the load is resampled in time
    spec = mechdyn.load(EXAMPLES / "slider_crank.toml").settings
    w0 = spec.mechanism.driver.speed

    def profile(psi):
        return w0 * (1 + 0.2 * np.cos(psi)), -0.2 * w0**2 * (1 + 0.2 * np.cos(psi)) * np.sin(psi)

    mech = replace(spec.mechanism, driver=replace(spec.mechanism.driver, profile=profile))
    d = inverse_dynamics(mech, 720)
    load = PeriodicLoad.from_mechanism(d, Placement((0, 0, 0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
    assert load.period == pytest.approx(abs(mech.driver.time(np.array([2 * np.pi]))[0]))
    t = np.mod(d.kinematics.time - d.kinematics.time[np.argmin(d.angle)], load.period)
    f = load.value(t)
    scale = np.abs(d.shaking_force).max()
    np.testing.assert_allclose(f[:, 0], d.shaking_force[:, 0], atol=1e-4 * scale)
    np.testing.assert_allclose(f[:, 2], d.shaking_force[:, 1], atol=1e-4 * scale)


def test_a_process_force_stays_inside_the_machine():
    # the slide's forming force comes back through the bed: the machine's load is unchanged
    from mechdyn.mechanism import ProcessForce

    spec = mechdyn.load(EXAMPLES / "slider_crank.toml").settings

    def forming(angle, position):
        return -2000.0 * (np.sin(angle) > 0.5), 300.0 * np.cos(angle)

    with_force = replace(spec.mechanism, process_forces=(ProcessForce("slider", "B", forming),))
    plain = PeriodicLoad.from_mechanism(inverse_dynamics(spec.mechanism, 72))
    worked = PeriodicLoad.from_mechanism(inverse_dynamics(with_force, 72))
    t = plain.time(72)
    np.testing.assert_allclose(worked.value(t), plain.value(t), atol=1e-6)
