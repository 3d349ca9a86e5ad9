"""Model updating against synthetic measurements of known models (issue 47, point 4).

The "machine" is a known model with perturbed values; its FRFs at the measurement points, spoiled
by 1 % multiplicative complex noise and a floor of 0.1 % of each channel's peak
(:func:`mechdyn.measurement.simulate_frf`), are identified (LSCF/LSFD with scatter), and the model
file with the nominal values is updated against the identified modes. Checks: the true values lie
within the stated 95 % intervals (in one draw here, in ≥ 90 % of 25 draws in the slow tests), the
residuals fall to the noise, a parameter the modes cannot see or separate is reported as such and held
at its prior, the dampers are updated from the damping ratios when asked, and the updated file is
written and read back.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

import mechdyn
from mechdyn.drivetrain import Disk, Drivetrain, GroundDamper, GroundSpring, Shaft
from mechdyn.measurement import identify_modes, simulate_frf, update_model
from mechdyn.measurement.updating import UpdateError
from mechdyn.studies.paths import PathError
from mechdyn.support import Mount, MountedMachine, PeriodicLoad, RigidBody

BETA = 1.0e-3  # s, stiffness-proportional damping of the mounts
DT_BETA = 5.0e-5  # s, of the drivetrain's shafts and ground spring (ζ 0.3 … 2.8 %)
CORNERS = {
    f"c{i}": (sx * 1.2, sy * 0.8, 0.0) for i, (sx, sy) in enumerate([(-1, -1), (1, -1), (-1, 1), (1, 1)])
}
MOUNT_PATHS = ["mounts.*.stiffness.x", "mounts.*.stiffness.y", "mounts.*.stiffness.z"]
MOUNT_TRUE = np.array([0.6e6, 0.7e6, 2.3e6])  # N/m; the model file says 0.5, 0.8 and 2.0 MN/m
SHAFT_PATHS = [f"shafts.s{i}.stiffness" for i in range(4)]
SHAFT_NOMINAL = np.array([2.0e5, 1.2e5, 3.0e5, 0.8e5])  # N·m/rad
SHAFT_TRUE = SHAFT_NOMINAL * np.array([1.15, 0.85, 1.25, 0.9])


def _machine(kx: float = 0.5e6, ky: float = 0.8e6, kz: float = 2.0e6) -> MountedMachine:
    body = RigidBody(2000.0, (0.05, -0.03, 0.4), (400.0, 700.0, 900.0))
    k = (kx, ky, kz)
    mounts = [Mount(name, xyz, k, tuple(BETA * v for v in k)) for name, xyz in CORNERS.items()]
    return MountedMachine(body, mounts)


def _drivetrain(k: np.ndarray = SHAFT_NOMINAL, parallel: float | None = None) -> Drivetrain:
    J = (0.8, 0.5, 1.2, 0.4, 0.9)
    disks = [Disk(f"d{i}", J[i]) for i in range(5)]
    shafts = [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i], damping=DT_BETA * k[i]) for i in range(4)]
    if parallel is not None:  # a second shaft beside s1: only the sum of the two is seen
        shafts.append(Shaft("s1b", ("d1", "d2"), parallel, damping=DT_BETA * parallel))
    ground = [GroundSpring("g", "d0", 1.0e5), GroundDamper("gc", "d0", DT_BETA * 1.0e5)]
    return Drivetrain(disks, [*shafts, *ground])


def _support_file(tmp_path):
    load = PeriodicLoad.from_harmonics(1 / 12.5, {1: 2.0e3})  # N, at 12.5 Hz
    return mechdyn.save(_machine(), tmp_path / "machine.toml", load=load)


def _support_modes(seed: int):
    outputs = tuple((p, d) for p in CORNERS for d in "xyz")
    meas = simulate_frf(
        _machine(*MOUNT_TRUE),
        outputs,
        (("c0", "z"), ("c3", "x")),
        np.arange(0.5, 40.0, 0.05),
        CORNERS,
        seed=seed,
    )
    return identify_modes(meas, f_min_hz=2.0, f_max_hz=30.0)


DT_MAP = {f"p{i}": f"d{i}" for i in range(5)}


def _drivetrain_modes(seed: int, model: Drivetrain | None = None):
    outputs = tuple((f"p{i}", "rz") for i in range(5))
    meas = simulate_frf(
        model or _drivetrain(SHAFT_TRUE),
        outputs,
        (outputs[0], outputs[3]),
        np.arange(0.5, 250.0, 0.05),
        DT_MAP,
        seed=seed,
    )
    return identify_modes(meas, f_min_hz=2.0, f_max_hz=200.0)


@pytest.fixture(scope="module")
def support_found():
    return _support_modes(seed=3)


@pytest.fixture(scope="module")
def shaft_found():
    return _drivetrain_modes(seed=7)


def _inside(update, truth):
    lo, hi = update.interval_95.T
    return (lo <= truth) & (truth <= hi)


def test_mount_stiffnesses_updated_from_a_tap_test(tmp_path, support_found):
    path = _support_file(tmp_path)
    up = update_model(path, support_found, MOUNT_PATHS, CORNERS)
    assert up.identifiable.all()
    # the true values within the stated 95 % intervals, which are narrow (a few ‰ of the value)
    assert _inside(up, MOUNT_TRUE).all()
    assert np.all(up.log_std < 0.01)
    np.testing.assert_allclose(up.value, MOUNT_TRUE, rtol=0.01)
    # the model's frequencies were 2–7 % off; after: within a few times the measured scatter
    assert np.abs(up.before.frequency_error).max() > 0.02
    assert up.chi2_after < 1e-3 * up.chi2_before
    assert np.abs(up.after.frequency_error).max() < 0.005
    assert len(up.after.pairs) == 6
    # the summary and the table in the file's units
    s = up.summary()
    assert s["mounts.*.stiffness.z"]["unit"] == "N/m"
    lo, hi = s["mounts.*.stiffness.z"]["interval_95"]
    assert lo < 2.3e6 < hi
    assert list(up.to_frame()["identifiable"]) == [True] * 3
    assert up.correlation.shape == (3, 3)
    np.testing.assert_allclose(np.diag(up.correlation), 1.0)
    # the posterior as uncertain inputs for mechdyn.uncertainty: lognormal, median the value
    space = up.input_space()
    assert [v.name for v in space.variables] == MOUNT_PATHS
    np.testing.assert_allclose(space.R, up.correlation, atol=1e-12)
    ax = up.plot()
    assert ax.get_ylabel() == "frequency error (%)"
    import matplotlib.pyplot as plt

    plt.close("all")


def test_shape_residuals_weighted_in_agree_with_the_frequencies(tmp_path, support_found):
    path = _support_file(tmp_path)
    freq = update_model(path, support_found, MOUNT_PATHS, CORNERS, starts=0)
    both = update_model(path, support_found, MOUNT_PATHS, CORNERS, starts=0, shape_weight=1.0)
    assert _inside(both, MOUNT_TRUE).all()
    # the shapes add information: the intervals do not widen beyond the Birge ratio's doing
    assert np.all(both.log_std <= freq.log_std * np.sqrt(both.birge_ratio / freq.birge_ratio) * 1.001)
    assert both.after.paired_mac.min() > 0.99


def test_mount_damping_updated_from_the_damping_ratios(tmp_path, support_found):
    # with damping_error the damping ratios are residuals too: the mounts' dampers become
    # identifiable (without it, a damping path has no effect on the residuals: see below)
    path = _support_file(tmp_path)
    damping = ["mounts.*.damping.x", "mounts.*.damping.y", "mounts.*.damping.z"]
    up = update_model(path, support_found, MOUNT_PATHS + damping, CORNERS, starts=0, damping_error=0.05)
    truth = np.concatenate([MOUNT_TRUE, BETA * MOUNT_TRUE])  # N/m, then N·s/m
    assert up.identifiable.all()
    assert _inside(up, truth).all()
    assert np.all(up.log_std[3:] < 0.1)  # the dampers to better than ±10 %
    # the damping ratios within the identification's accuracy (10 %), closer than before
    assert np.abs(up.after.damping_error).max() < 0.1
    assert np.abs(up.after.damping_error).mean() < 0.5 * np.abs(up.before.damping_error).mean()


def test_updated_model_file_written_and_read_back(tmp_path, support_found):
    path = _support_file(tmp_path)
    up = update_model(path, support_found, MOUNT_PATHS, CORNERS, starts=0)
    out = up.save(tmp_path / "updated.toml")
    machine = mechdyn.load(out).model
    for mount in machine.mounts:
        np.testing.assert_allclose(mount.stiffness, up.value, rtol=1e-12)
    # what was not updated is as it was (mass, positions, damping)
    base = mechdyn.load(path).model
    assert machine.body.mass == base.body.mass
    np.testing.assert_array_equal(machine.body.inertia, base.body.inertia)
    for a, b in zip(machine.mounts, base.mounts, strict=True):
        np.testing.assert_array_equal(a.position, b.position)
        np.testing.assert_array_equal(a.damping, b.damping)


def test_shaft_stiffnesses_of_a_five_disk_drivetrain_updated(tmp_path, shaft_found):
    path = mechdyn.save(_drivetrain(), tmp_path / "drivetrain.toml")
    up = update_model(path, shaft_found, SHAFT_PATHS, DT_MAP, starts=4)
    assert up.identifiable.all()
    assert _inside(up, SHAFT_TRUE).all()
    np.testing.assert_allclose(up.value, SHAFT_TRUE, rtol=0.02)
    assert up.chi2_after < 1e-2 * up.chi2_before


def test_a_parameter_no_measured_mode_sees_is_not_identifiable(tmp_path, shaft_found):
    # the shafts' damping does not move the undamped modes: zero sensitivity, held at its prior
    path = mechdyn.save(_drivetrain(), tmp_path / "drivetrain.toml")
    up = update_model(path, shaft_found, [*SHAFT_PATHS, "shafts.s2.damping"], DT_MAP, starts=0)
    assert list(up.identifiable) == [True, True, True, True, False]
    assert up.value[4] == up.prior[4] == DT_BETA * SHAFT_NOMINAL[2]
    assert np.isnan(up.interval_95[4]).all() and np.isnan(up.standard_uncertainty[4])
    assert "no measured mode sees it" in up.reasons[4]
    assert "not identifiable from these modes" in up.summary()["shafts.s2.damping"]["note"]
    assert _inside(up, np.append(SHAFT_TRUE, 0.0))[:4].all()


def test_two_stiffnesses_seen_only_as_their_sum_are_not_both_identifiable(tmp_path):
    # two shafts side by side between d1 and d2: the modes see k_s1 + k_s1b only
    nominal = _drivetrain(SHAFT_NOMINAL * [1, 0.5, 1, 1], parallel=0.6e5)
    path = mechdyn.save(nominal, tmp_path / "parallel.toml")
    truth = _drivetrain(SHAFT_TRUE * [1, 0.5, 1, 1], parallel=0.5 * SHAFT_TRUE[1])
    found = _drivetrain_modes(seed=9, model=truth)
    up = update_model(path, found, [*SHAFT_PATHS, "shafts.s1b.stiffness"], DT_MAP, starts=1)
    # one of the pair is held at its prior and named as collinear with the other; the other takes
    # the whole sum, the remaining shafts are found as before
    assert up.identifiable.sum() == 4
    held = int(np.flatnonzero(~up.identifiable)[0])
    assert held in (1, 4)
    assert "collinear" in up.reasons[held]
    assert up.value[held] == up.prior[held]
    assert np.abs(up.singular_values).min() < 1e-6
    k_sum = up.value[1] + up.value[4]
    np.testing.assert_allclose(k_sum, SHAFT_TRUE[1], rtol=0.02)
    others = [0, 2, 3]
    assert _inside(up, np.append(SHAFT_TRUE, 0.0))[others].all()


def test_bad_parameters_are_named(tmp_path, shaft_found):
    path = mechdyn.save(_drivetrain(), tmp_path / "drivetrain.toml")
    found = shaft_found
    with pytest.raises(PathError, match=r"shafts\.s9\.stiffness"):
        update_model(path, found, ["shafts.s9.stiffness"], DT_MAP)
    with pytest.raises(UpdateError, match="non-empty list"):
        update_model(path, found, "shafts.s1.stiffness", DT_MAP)
    with pytest.raises(UpdateError, match="give its model file"):
        update_model(_drivetrain(), found, SHAFT_PATHS, DT_MAP)
    with pytest.raises(UpdateError, match="search"):
        update_model(path, found, SHAFT_PATHS, DT_MAP, search=1.0)


def _coverage(update_one, truth, draws):
    hits = np.array([_inside(update_one(seed), truth) for seed in range(100, 100 + draws)])
    return hits.mean(axis=0)


@pytest.mark.slow
def test_mount_intervals_cover_the_truth_in_repeated_draws(tmp_path):
    path = _support_file(tmp_path)
    rate = _coverage(
        lambda s: update_model(path, _support_modes(s), MOUNT_PATHS, CORNERS, starts=2), MOUNT_TRUE, 25
    )
    assert rate.mean() >= 0.9 and rate.min() >= 0.8, rate


@pytest.mark.slow
def test_shaft_intervals_cover_the_truth_in_repeated_draws(tmp_path):
    path = mechdyn.save(_drivetrain(), tmp_path / "drivetrain.toml")
    rate = _coverage(
        lambda s: update_model(path, _drivetrain_modes(s), SHAFT_PATHS, DT_MAP, starts=2), SHAFT_TRUE, 25
    )
    assert rate.mean() >= 0.9 and rate.min() >= 0.8, rate
