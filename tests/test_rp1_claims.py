"""RP-1 (reference machine D, SPEC §6): two claims of the validation page checked against the package.

1. The published shaking-force ranges, 68 N (forward, x) and 62 N (vertical, y) at 300 rpm, under the
   reading in which the centripetal acceleration of each planet's centre of mass about its pivot uses
   the planet's rate *relative to the carrier* instead of its absolute rate (the reading of
   ``tests/test_rp1_shaking_force.py``). The planets' centres of mass are the only part of the
   mechanism that is not balanced between the two point-symmetric sides (the arm's centre of mass is
   on the sun's axis, the idlers' and the planets' pivots cancel in pairs), and their offset from
   the pivot is d times a direction that d does not change: both ranges, under either reading, are
   exactly proportional to d, so the ratio x/y does not depend on d at all.

   | 300 rpm | x range / d | y range / d | x / y | d for 68 N (x) | d for 62 N (y) |
   |---|---|---|---|---|---|
   | absolute rate (the engine) | 1.0543 N/mm | 1.1128 N/mm | 0.9475 | 64.5 mm | 55.7 mm |
   | rate relative to the carrier | 2.3331 N/mm | 2.3742 N/mm | 0.9827 | 29.15 mm | 26.11 mm |
   | published | — | — | 68/62 = 1.0968 | — | — |

   The largest d the planet's inertia allows is √(I_o/m) = 32.0 mm. Under the relative reading the
   d that gives 68 N in x (29.15 mm) gives 69.2 N in y (+11.6 %), and the d that gives 62 N in y
   (26.11 mm) gives 60.9 N in x (−10.4 %); the best one d can do for both at once is ±5.5 % (d =
   27.55 mm). Both readings make y the larger range, the publication x. At 200 rpm every range is
   4/9 of the above (constant speed: the accelerations go with ω²): the relative reading would need
   d = 65.6 mm (x) and 58.8 mm (y), beyond 32 mm.

2. The direction in which a smaller |α| moves the forces, α = −35° ± 10 % (−38.5° and −31.5°), 200 rpm,
   120 angles (as the sensitivity study ``examples/studies/rp1_sensitivity.toml``). Definitions: tooth
   force = largest magnitude of the mesh force over the four gear pairs (``tooth_force_max_N``; here
   always the sun–idler mesh G1-G2); planet bearing = joint ``P1`` (carrier–planet 1, at the planet's
   pivot); idler bearing = joint ``I1`` (carrier–idler 1). The validation table's column once called
   "carrier force max" is ``joint_force_peak_N.I1``, the idler bearing (103.7 N nominal; the planet
   bearing P1, 80.2 N, has its own column now). Variants: the sun's phase solved for a consistent idler
   (the package's rule), the sun at α, the sun held at the nominal solved phase (−50.93°), the sun kept
   at the nominal offset from α (α − 15.93°); each with the default flank law and with ``flank =
   "fixed"`` (F_n = F_t tan φ, as published); the carrier turning clockwise. In every variant a smaller
   |α| *lowers* the tooth force, the planet bearing force and the idler bearing force; turning clockwise
   changes no figure at all.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import math
import warnings
from functools import cache
from unittest import mock

import numpy as np
import pytest

from mechdyn.errors import ModelWarning
from mechdyn.mechanism import GearJoint, inverse_dynamics
from mechdyn.mechanism.planter import PlanterDesign, planter
from test_rp1_shaking_force import _shaking_force

# ``mechdyn.mechanism.planter`` as an attribute is the function; the module holds the sun's rule
_planter_module = importlib.import_module("mechdyn.mechanism.planter")

RPM = 2 * math.pi / 60
D_MAX = math.sqrt(PlanterDesign().planet_inertia / PlanterDesign().planet_mass)  # I_o = I_G + m d² ≥ m d²
PUBLISHED_X, PUBLISHED_Y = 68.0, 62.0


# -- 1. the shaking force under the planet's rate relative to the carrier ---------------------------


@cache
def _ranges(d: float, rpm: float) -> dict[str, tuple[float, float]]:
    """x and y ranges of the shaking force (N): the engine's (absolute rate) and the relative reading."""
    speed = rpm * RPM
    result = inverse_dynamics(planter(dataclasses.replace(PlanterDesign(), speed=speed, com_offset=d)), 180)
    rel = _shaking_force(result, relative_rate=True)
    eng = result.shaking_force
    return {
        "absolute": (float(np.ptp(eng[:, 0])), float(np.ptp(eng[:, 1]))),
        "relative": (float(np.ptp(rel[:, 0])), float(np.ptp(rel[:, 1]))),
    }


OFFSETS = (0.004, 0.012, 0.020, 0.028, D_MAX * (1 - 1e-9))  # over 0 < d ≤ √(I_o/m)


def test_the_shaking_force_ranges_are_proportional_to_d_so_the_ratio_does_not_depend_on_d():
    # Shows: both readings give ranges exactly proportional to d (the slopes agree to 1e-6 over
    # 4–32 mm), so x/y is one number for each reading: 0.9475 (absolute rate) and 0.9827 (relative
    # rate) over every admissible d, never the published 68/62 = 1.097.
    for reading, slope, ratio in (
        ("absolute", (1.0543, 1.1128), 0.94749),
        ("relative", (2.3331, 2.3742), 0.98268),
    ):
        sx = np.array([_ranges(d, 300)[reading][0] / (d * 1e3) for d in OFFSETS])
        sy = np.array([_ranges(d, 300)[reading][1] / (d * 1e3) for d in OFFSETS])
        np.testing.assert_allclose(sx, sx[0], rtol=1e-6)
        np.testing.assert_allclose(sy, sy[0], rtol=1e-6)
        assert sx[0] == pytest.approx(slope[0], abs=1e-4) and sy[0] == pytest.approx(slope[1], abs=1e-4)
        r = sx / sy
        assert r.min() == pytest.approx(ratio, abs=1e-5) and r.max() == pytest.approx(ratio, abs=1e-5)
        assert r.max() < 0.9 * PUBLISHED_X / PUBLISHED_Y  # 1.0968: missed by 10 % (relative), 14 % (absolute)


def test_under_the_relative_rate_x_and_y_need_different_d_and_no_d_gives_both_within_5_percent():
    # Shows: the d that gives 68 N in x (29.15 mm) is not the d that gives 62 N in y (26.11 mm); at
    # either one the other range misses by 10–12 %; the best single d (27.55 mm) misses both by 5.5 %.
    sx, sy = (v / 20.0 for v in _ranges(0.020, 300)["relative"])  # N per mm, linear in d (test above)
    d_x, d_y = PUBLISHED_X / sx, PUBLISHED_Y / sy
    assert d_x == pytest.approx(29.146, abs=0.01) and d_y == pytest.approx(26.114, abs=0.01)
    assert d_x - d_y > 3.0 and max(d_x, d_y) < D_MAX * 1e3
    assert sy * d_x / PUBLISHED_Y - 1 == pytest.approx(0.1161, abs=5e-4)  # y at d_x: 69.2 N
    assert sx * d_y / PUBLISHED_X - 1 == pytest.approx(-0.1040, abs=5e-4)  # x at d_y: 60.9 N
    d = np.linspace(1e-3, D_MAX * 1e3, 200001)  # mm
    worst = np.maximum(np.abs(sx * d / PUBLISHED_X - 1), np.abs(sy * d / PUBLISHED_Y - 1))
    best = int(np.argmin(worst))
    assert worst[best] == pytest.approx(0.0549, abs=3e-4) and d[best] == pytest.approx(27.55, abs=0.02)
    assert worst.min() > 0.05
    # check the linear extrapolation at the best d with a build there
    x, y = _ranges(d[best] * 1e-3, 300)["relative"]
    assert x == pytest.approx(64.27, abs=0.02) and y == pytest.approx(65.40, abs=0.02)


def test_the_correct_model_stays_far_below_and_200_rpm_scales_by_four_ninths():
    # Shows: with the absolute rate (the engine) the largest admissible d gives 33.8 / 35.6 N at
    # 300 rpm; at 200 rpm every range is (200/300)² of the 300 rpm one, so the relative reading would
    # need d = 65.6 mm (x) and 58.8 mm (y), both beyond √(I_o/m) = 32.0 mm, with the same x/y 0.9827.
    x, y = _ranges(D_MAX * (1 - 1e-9), 300)["absolute"]
    assert x == pytest.approx(33.75, abs=0.02) and y == pytest.approx(35.63, abs=0.02)
    for reading in ("absolute", "relative"):
        np.testing.assert_allclose(
            _ranges(0.020, 200)[reading], np.array(_ranges(0.020, 300)[reading]) * 4 / 9, rtol=1e-9
        )
    rx, ry = _ranges(0.020, 200)["relative"]
    assert (rx, ry) == (pytest.approx(20.739, abs=0.002), pytest.approx(21.104, abs=0.002))
    d_x, d_y = 20.0 * PUBLISHED_X / rx, 20.0 * PUBLISHED_Y / ry
    assert d_x == pytest.approx(65.58, abs=0.02) and d_y == pytest.approx(58.76, abs=0.02)
    assert min(d_x, d_y) > D_MAX * 1e3


# -- 2. the direction of the forces with a smaller |α| ----------------------------------------------

_SUN_NOMINAL = math.radians(-50.933681)  # the phase the package solves for α = −35° (checked below)

# the sun's installation angle from (curve, a, β, planet's angle α): planter() has no field for it,
# so a variant swaps the rule the package uses (sun_orientation) while it builds
SUN_RULES = {
    "solved": None,  # the package's own: each idler the exact mate of both its neighbours
    "at alpha": lambda curve, a, beta, planet: planet,
    "fixed phase": lambda curve, a, beta, planet: _SUN_NOMINAL,
    "fixed offset": lambda curve, a, beta, planet: planet + _SUN_NOMINAL - math.radians(-35.0),
}


@cache
def _mechanism(alpha_deg: float, sun: str, clockwise: bool):
    design = dataclasses.replace(
        PlanterDesign(), alpha=math.radians(alpha_deg), speed=(-1 if clockwise else 1) * 200 * RPM
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ModelWarning)
        if SUN_RULES[sun] is None:
            mech = planter(design)
        else:
            with mock.patch.object(_planter_module, "sun_orientation", SUN_RULES[sun]):
                mech = planter(design)
    idler_warned = any("meshes in" in str(w.message) for w in caught if issubclass(w.category, ModelWarning))
    return mech, idler_warned


@cache
@functools.cache  # the figures of a case are read by several tests (read-only)
def _figures(alpha_deg: float, sun: str = "solved", flank: str = "load", clockwise: bool = False) -> dict:
    mech, _ = _mechanism(alpha_deg, sun, clockwise)
    if flank == "fixed":
        joints = tuple(
            dataclasses.replace(j, flank="fixed") if isinstance(j, GearJoint) else j for j in mech.joints
        )
        with warnings.catch_warnings():  # the idler warning of _mechanism, once more
            warnings.simplefilter("ignore", ModelWarning)
            mech = dataclasses.replace(mech, joints=joints)
    s = inverse_dynamics(mech, 120).summary()
    peak = s["joint_force_peak_N"]
    # the sun–idler meshes (G1-G2, and G1-G4 on side 2) carry the largest tooth force
    assert s["tooth_force_max_N"] == pytest.approx(peak["G1-G2"], rel=1e-12)
    assert peak["P1"] == pytest.approx(peak["P2"], rel=1e-9) and peak["I1"] == pytest.approx(
        peak["I2"], rel=1e-9
    )
    return {
        "tooth": s["tooth_force_max_N"],
        "planet bearing": peak["P1"],
        "idler bearing": peak["I1"],
        "torque range": s["driving_torque_range_Nm"],
        "shaking x": s["shaking_force_x_range_N"],
        "shaking y": s["shaking_force_y_range_N"],
    }


# (sun, flank): figures at α = −38.5° and −31.5° (smaller |α|), N and N·m, 200 rpm, 120 angles
EXPECTED = {
    ("solved", "load"): {
        "tooth": (64.491, 60.061),
        "planet bearing": (81.765, 78.560),
        "idler bearing": (107.557, 99.815),
        "torque range": (1.4446, 1.4253),
        "shaking x": (9.358, 9.371),
        "shaking y": (9.896, 9.891),
    },
    ("solved", "fixed"): {
        "tooth": (64.491, 60.061),
        "planet bearing": (60.166, 57.814),
        "idler bearing": (114.405, 106.119),
        "torque range": (1.4446, 1.4253),
        "shaking x": (9.358, 9.371),
        "shaking y": (9.896, 9.891),
    },
    ("at alpha", "load"): {
        "tooth": (60.140, 55.031),
        "planet bearing": (77.546, 73.701),
        "idler bearing": (99.380, 90.646),
        "torque range": (1.4011, 1.3751),
        "shaking x": (9.136, 9.032),
        "shaking y": (9.672, 9.614),
    },
    ("at alpha", "fixed"): {
        "tooth": (60.140, 55.031),
        "planet bearing": (56.968, 54.212),
        "idler bearing": (106.300, 96.994),
        "torque range": (1.4011, 1.3751),
        "shaking x": (9.136, 9.032),
        "shaking y": (9.672, 9.614),
    },
    ("fixed phase", "load"): {
        "tooth": (63.848, 60.731),
        "planet bearing": (81.128, 79.225),
        "idler bearing": (106.306, 101.093),
        "torque range": (1.4402, 1.4276),
        "shaking x": (9.361, 9.359),
        "shaking y": (9.888, 9.886),
    },
    ("fixed phase", "fixed"): {
        "tooth": (63.848, 60.731),
        "planet bearing": (59.690, 58.309),
        "idler bearing": (113.173, 107.382),
        "torque range": (1.4402, 1.4276),
        "shaking x": (9.361, 9.359),
        "shaking y": (9.888, 9.886),
    },
    ("fixed offset", "load"): {
        "tooth": (64.843, 59.699),
        "planet bearing": (82.117, 78.203),
        "idler bearing": (108.249, 99.133),
        "torque range": (1.4466, 1.4237),
        "shaking x": (9.360, 9.370),
        "shaking y": (9.893, 9.887),
    },
    ("fixed offset", "fixed"): {
        "tooth": (64.843, 59.699),
        "planet bearing": (60.427, 57.547),
        "idler bearing": (115.085, 105.443),
        "torque range": (1.4466, 1.4237),
        "shaking x": (9.360, 9.370),
        "shaking y": (9.893, 9.887),
    },
}


def test_the_package_solves_the_sun_at_the_nominal_phase_and_only_that_rule_gives_one_idler():
    # Shows: the solved sun phase for α = −35° is −50.93° (the "fixed phase" variant's value); every
    # other rule makes each idler two different gears (the model warns), the solved one does not.
    curve_args = _planter_module.geometry(PlanterDesign())
    assert curve_args[3] == pytest.approx(_SUN_NOMINAL, abs=1e-6)
    for sun in SUN_RULES:
        for alpha in (-38.5, -31.5):
            assert _mechanism(alpha, sun, False)[1] is (sun != "solved")


# the package's own rule with the load's flank in the default run; its other flank and the other three
# sun rules in CI's heavy step
@pytest.mark.parametrize(
    ("sun", "flank"),
    [k if k == ("solved", "load") else pytest.param(*k, marks=pytest.mark.slow) for k in EXPECTED],
)
def test_a_smaller_alpha_lowers_the_tooth_and_bearing_forces_in_every_variant(sun, flank):
    # Shows: for this sun rule and flank law, α −38.5° → −31.5° (smaller |α|) lowers the largest
    # tooth force, the planet bearing (carrier–planet, P1) and the idler bearing (carrier–idler, I1):
    # the published "raises" is not reproduced by any of them; the torque range falls by 0.9–1.9 % and
    # the shaking-force ranges move by at most 1.2 %.
    big, small = _figures(-38.5, sun, flank), _figures(-31.5, sun, flank)
    for name, (at_big, at_small) in EXPECTED[(sun, flank)].items():
        tol = 2e-4 if name == "torque range" else 2e-3
        assert big[name] == pytest.approx(at_big, abs=tol), name
        assert small[name] == pytest.approx(at_small, abs=tol), name
    for name in ("tooth", "planet bearing", "idler bearing"):
        assert small[name] < big[name] - 1.0, name  # lowered, by 1.4–9.6 N
    assert small["torque range"] < big["torque range"]
    for name in ("shaking x", "shaking y"):
        assert small[name] == pytest.approx(big[name], rel=0.012)


def test_the_study_carrier_force_is_the_idler_bearing():
    # Shows: the sensitivity table's idler bearing column (once "carrier force max": 103.7 N nominal;
    # 107.6 / 99.8 N in the α row) is joint I1, the carrier–idler bearing; the carrier–planet bearing
    # P1 peaks at 80.2 N, its own column now.
    nominal = _figures(-35.0)
    assert nominal["idler bearing"] == pytest.approx(103.727, abs=2e-3)
    assert nominal["planet bearing"] == pytest.approx(80.200, abs=2e-3)
    assert nominal["tooth"] == pytest.approx(62.312, abs=2e-3)
    assert (
        round(_figures(-38.5)["idler bearing"], 1) == 107.6
        and round(_figures(-31.5)["idler bearing"], 1) == 99.8
    )


@pytest.mark.parametrize("alpha", [-38.5, -31.5])
def test_turning_the_carrier_clockwise_changes_no_figure(alpha):
    # Shows: at constant speed every acceleration goes with ω², so reversing the carrier leaves each
    # force, the torque range and the shaking force as they were (to round-off): clockwise rotation
    # cannot turn the α direction round.
    assert _mechanism(alpha, "solved", True)[0].driver.speed < 0
    ccw, cw = _figures(alpha), _figures(alpha, clockwise=True)
    for name in ccw:
        assert cw[name] == pytest.approx(ccw[name], rel=1e-9), name
