"""The machine on its mounts loaded by a mechanism at its drive's real, fluctuating speed.

``[excitation] mechanism = "press_driven.toml"`` (a ``type = "drive"`` file): the shaking force and
moment of the drive's periodic steady state, sampled uniformly in time over the drive's period
(:meth:`mechdyn.support.PeriodicLoad.from_drive`). Regenerate the figures quoted here with
``mechdyn support examples/press_driven_on_mounts.toml --json``.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import mechdyn
from mechdyn.cli.main import main
from mechdyn.errors import ModelFileError
from mechdyn.mechanism.dynamics import inverse_dynamics
from mechdyn.support import PeriodicLoad, periodic_response
from mechdyn.support.schema import DriveExcitation

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.fixture(scope="module")
def driven():
    loaded = mechdyn.load(EXAMPLES / "press_driven_on_mounts.toml")
    assert isinstance(loaded.settings.excitation, DriveExcitation)
    return loaded


def at_constant_speed(excitation: DriveExcitation, speed: float) -> PeriodicLoad:
    """The same mechanism (forming force and all) turned at a constant crank speed, rad/s."""
    mech = excitation.mechanism
    driver = replace(mech.driver, speed=math.copysign(speed, mech.driver.speed), profile=None)
    dyn = inverse_dynamics(replace(mech, driver=driver), excitation.angles)
    return PeriodicLoad.from_mechanism(dyn, excitation.placement)


def exact_vertical_samples(result, placement) -> tuple[np.ndarray, np.ndarray]:
    """The drive's own samples of the vertical load (shaking force less the forming force, which stays
    in the machine), at their own times from the angle datum: equal steps of crank angle, not of time."""
    d = result.loads
    t = np.mod(d.kinematics.time - d.kinematics.time[np.argmin(d.angle)], result.steady.period)
    f2 = d.shaking_force.copy()
    for pf in d.mechanism.process_forces:
        fx, fy = pf.force(d.angle, d.output_position)
        f2 -= np.stack(np.broadcast_arrays(np.asarray(fx, float), np.asarray(fy, float)), axis=-1)
    return t, f2[:, 0] * placement.x_axis[2] + f2[:, 1] * placement.y_axis[2]


# -- (a) the rigid limit ---------------------------------------------------------------------------
def test_a_huge_flywheel_gives_the_constant_speed_floor_force(driven):
    e = driven.settings.excitation
    rigid = replace(e, drive=replace(e.drive, flywheel_inertia=e.drive.flywheel_inertia * 1e4))
    steady = rigid.result.steady
    assert steady.fluctuation < 1e-5  # 2.3e-6
    load = rigid.load()
    constant = at_constant_speed(rigid, steady.mean_speed)
    assert load.period == pytest.approx(constant.period, rel=1e-12)
    a, b = periodic_response(driven.model, load), periodic_response(driven.model, constant)
    span = float(np.ptp(b.floor_force[:, 2]))
    # the floor force along x, y, z at every instant: within 2e-5 of its range (3.9e-6 found, of the
    # order of the fluctuation left)
    assert np.abs(a.floor_force - b.floor_force).max() < 2e-5 * span
    ra, rb = a.summary()["floor_force_range_N"], b.summary()["floor_force_range_N"]
    assert ra == pytest.approx(rb, rel=1e-5, abs=1e-5 * span)


# -- (b) the example's flywheel --------------------------------------------------------------------
def test_the_fluctuating_speed_changes_the_floor_force_a_little(driven):
    e = driven.settings.excitation
    steady = e.result.steady
    assert 0.015 < steady.fluctuation < 0.025  # 1.92 %: 650 kg m² behind lossy gears
    machine, load = driven.model, driven.settings.load
    real = periodic_response(machine, load)
    constant = periodic_response(machine, at_constant_speed(e, steady.mean_speed))
    s_real, s_const = real.summary(), constant.summary()
    # at the same mean speed (15.02 rpm) the fluctuation lowers the floor force range by 0.39 %
    # (842.6 kN against 846.0 kN), and shifts it in time by up to 3.7 % of its range
    ratio = s_real["transmitted_force_range_N"] / s_const["transmitted_force_range_N"]
    assert ratio == pytest.approx(0.99605, abs=5e-4)
    shift = np.abs(real.floor_force - constant.floor_force).max() / s_const["transmitted_force_range_N"]
    assert 0.01 < shift < 0.06
    # the machine's force balance still holds at every instant (round-off, N)
    assert np.abs(real.force_balance_residual).max() < 1e-3
    # still quasi-static: the mounts pass the exciting force on, 3.1 % amplified (2.6 % at constant speed)
    assert 1.0 < s_real["transmitted_to_inertia_force_range"] < 1.05


def test_against_the_press_at_its_nominal_fifteen_strokes_a_minute(driven):
    # examples/press_on_mounts.toml turns the crank at exactly 15 rpm (period 4 s); the motor's slip
    # under this load gives 15.02 rpm, and the driven press's floor force range is 0.07 % lower
    # (842.6 kN against 843.2 kN): the fluctuation outweighs the faster mean speed
    nominal = mechdyn.load(EXAMPLES / "press_on_mounts.toml")
    a = periodic_response(driven.model, driven.settings.load).summary()
    b = periodic_response(nominal.model, nominal.settings.load).summary()
    assert nominal.settings.load.period == pytest.approx(4.0, rel=1e-12)
    assert driven.settings.load.period == pytest.approx(3.99361, rel=1e-5)
    assert a["transmitted_force_range_N"] / b["transmitted_force_range_N"] == pytest.approx(0.99934, abs=5e-4)


# -- (c) the load is periodic in time, with the drive's period -------------------------------------
def test_the_load_is_sampled_uniformly_in_time_over_the_drives_period(driven):
    e = driven.settings.excitation
    r, load = e.result, driven.settings.load
    assert load.period == r.steady.period  # 3.99361 s, not the 4 s of 15 rpm
    assert load.frequency == pytest.approx(1 / r.steady.period, rel=1e-15)
    assert load.n_samples == e.angles
    # t = 0 at the sample nearest the datum, bottom dead centre (located between the samples: 0.0004°)
    assert load.angle is not None and load.angle[0] == pytest.approx(0.0, abs=1e-5)
    t, exact = exact_vertical_samples(r, e.placement)
    span = float(np.ptp(exact))
    # the series passes through the drive's own samples at their own (unequal) times ...
    assert np.abs(load.value(t)[:, 2] - exact).max() < 1e-4 * span  # 1.8e-5 found (the spline in time)
    # ... which the same samples taken as equally spaced in time would miss by 2 % of the range
    order = np.argsort(t)
    as_if_uniform = PeriodicLoad.from_samples(r.steady.period, exact[order])
    assert np.abs(as_if_uniform.value(t[order])[:, 2] - exact[order]).max() > 0.01 * span
    # the moving parts' momentum is periodic, so the shaking force averages to zero over the period
    # in time (not in crank angle): 0.28 N against 374 N of a range of 820 kN
    assert abs(load.coefficients[0, 2]) < 1e-5 * span
    assert abs(as_if_uniform.coefficients[0, 2]) > 1e-4 * span


def test_the_support_run_reports_the_drive(driven):
    out = driven.settings.excitation_summary()
    assert out["speed_fluctuation_ratio"] == pytest.approx(0.01918, abs=1e-4)
    assert out["period_s"] == driven.settings.load.period
    assert {"stroke_m", "shaking_force_max_N", "shaking_force_max_constant_speed_N"} <= set(out)


# -- (d) bad input ---------------------------------------------------------------------------------
def _files(tmp_path: Path, mechanism: str, drive_edit=lambda s: s) -> Path:
    for name in ("press_link_drive.toml", "fourbar.toml"):
        (tmp_path / name).write_text((EXAMPLES / name).read_text())
    drive = (EXAMPLES / "press_driven.toml").read_text().replace("press_link_drive.toml", mechanism)
    (tmp_path / "my_drive.toml").write_text(drive_edit(drive))
    support = (EXAMPLES / "press_driven_on_mounts.toml").read_text()
    (tmp_path / "on_mounts.toml").write_text(support.replace('"press_driven.toml"', '"my_drive.toml"'))
    return tmp_path / "on_mounts.toml"


def test_a_forming_force_on_a_mechanism_without_a_slide_names_the_drive_file(tmp_path):
    path = _files(tmp_path, "fourbar.toml")
    with pytest.raises(ModelFileError, match=r"my_drive\.toml.*\[process\].*slide"):
        mechdyn.load(path)


def test_a_drive_that_stalls_names_both_files(tmp_path):
    path = _files(tmp_path, "press_link_drive.toml", lambda s: s.replace('"90 kW"', '"5 kW"'))
    loaded = mechdyn.load(path)  # loading computes nothing
    with pytest.raises(ModelFileError, match=r"on_mounts\.toml.*excitation.*my_drive\.toml stalls") as err:
        loaded.settings.load
    assert "mean torque" in str(err.value)
    assert main(["support", str(path)]) == 2


def test_a_period_with_a_drive_is_refused(tmp_path):
    path = _files(tmp_path, "press_link_drive.toml")
    path.write_text(path.read_text().replace("angles = 360", 'angles = 360\nperiod = "4 s"'))
    with pytest.raises(ModelFileError, match="remove period"):
        mechdyn.load(path)


def test_another_model_type_is_refused(tmp_path):
    path = _files(tmp_path, "press_link_drive.toml")
    path.write_text(path.read_text().replace('"my_drive.toml"', '"press_on_mounts.toml"'))
    (tmp_path / "press_on_mounts.toml").write_text((EXAMPLES / "press_on_mounts.toml").read_text())
    with pytest.raises(ModelFileError, match="'support' model; give a mechanism model file, or a drive"):
        mechdyn.load(path)
