"""The branch of a backlash oscillator followed through its folds by pseudo-arclength continuation
(issue 43, point 4): the folds against a plain natural-parameter shooting sweep at fine steps, the
stability of the three branches (a real Floquet multiplier through +1 at each fold), folds that do
not depend on the sweep's grid, the jump band's edges from the folds, and the bisection kept as the
stated fallback.

The oscillator is the single-mesh pair with backlash of ``test_gear_dynamics_backlash_steady.py``
(Kahraman & Singh, *J. Sound Vib.* 142 (1990) 49–75: constant mesh stiffness, a transmission error
of 0.5 µm, 20 µm of backlash, light load): below its resonance the teeth-in-contact orbit bends over
into contact loss, softening like a Duffing oscillator, between about 0.739 and 0.875 ω_n.
"""

from __future__ import annotations

import numpy as np
import pytest

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics._stability import _spectral
from mechdyn.gear_dynamics.continuation import FOLD_RTOL, ContinuedBranch, follow
from mechdyn.gear_dynamics.floquet import linear_periodic, period_plan
from mechdyn.gear_dynamics.shooting import _shoot_nonlinear, _warm_start
from mechdyn.gear_dynamics.sweep import EDGE_RTOL, speed_sweep

RA, RB, ZA = 0.0188, 0.047, 20
WN = np.sqrt(3e8 * RB**2 / 0.03)  # the gear's mode with the pinion held, rad/s
W = WN / ZA  # the pinion speed whose mesh frequency is ω_n, rad/s
LOAD = 20.0  # N·m at the gear
KW = {"reference": "pinion", "drive": "speed", "load": {"gear": LOAD}, "refine": 0}
#: The stated tolerance of a fold against the fine natural sweep: its step, 2e-6 of ω_n.
REFERENCE_STEP = 2e-6


def _system() -> GearSystem:
    dt = Drivetrain(
        [Disk("pinion", 0.05), Disk("gear", 0.03)],
        [
            GearMesh(
                "m", ("pinion", "gear"), teeth=(ZA, 50), base_radii=(RA, RB), stiffness=3e8, damping=8000.0
            )
        ],
        name="pair",
    )
    return GearSystem.from_drivetrain(
        dt, errors={"m": {"amplitude": 0.5e-6, "samples": 24}}, backlash={"m": 2e-5}
    )


@pytest.fixture(scope="module")
def both():
    """Swept up and down over five speeds: the up sweep follows the contact branch to its fold and
    through it along the unstable branch to the other fold; the down sweep stops at that fold."""
    return speed_sweep(_system(), np.array([0.6, 0.7, 0.8, 0.9, 1.0]) * W, direction="both", **KW)


def _natural_end(start: float, steps: list[float], sense: int) -> tuple[float, float]:
    """A plain natural-parameter shooting sweep (Newton at each speed from the orbit of the one
    before, no arclength, no tangent) from the orbit at ``start`` ω_n, in the sense ``sense``, with
    each step of ``steps`` (fractions of ω_n) in turn from where the one before ends: the last speed
    whose orbit continues the branch (converged, stable, its DTE swing within 10 % of the one
    before) and the first that does not, in ω_n. The fold lies between them."""
    lin = linear_periodic(_system(), reference="pinion", load={"gear": LOAD})
    plan = period_plan(lin)
    speed = start * W
    _t, x, v, ok, _phi, _c = _shoot_nonlinear(lin, plan, speed, _warm_start(lin, plan, speed), 64)
    assert ok
    y, swing = np.concatenate([x[0], v[0]]), np.ptp(x[:, 0])
    for h in steps:
        while True:
            trial = speed + sense * h * W
            _t, x, v, ok, phi, _c = _shoot_nonlinear(lin, plan, trial, y, 64)
            good = ok and x.size and _spectral(phi, lin)[1] <= 1.0
            if not (good and abs(np.ptp(x[:, 0]) - swing) < 0.1 * swing):
                break
            speed, y, swing = trial, np.concatenate([x[0], v[0]]), np.ptp(x[:, 0])
    return speed / W, speed / W + sense * steps[-1]


def _bisected(monkeypatch, speeds: np.ndarray, direction: str):
    """The sweep with its continuation made to fail at once: the fallback, bisection, runs."""
    import mechdyn.gear_dynamics.sweep as sweep_module

    def fails(lin, plan, speed, state, **kwargs):
        none, per_mesh = np.zeros(0), np.zeros((0, 1))
        return ContinuedBranch(
            speeds=none,
            arclength=none,
            speed_tangent=none,
            multipliers=np.zeros((0, 2 * lin.m), complex),
            states=np.zeros((0, 2 * lin.m)),
            force_max=per_mesh,
            force_min=per_mesh,
            static_force=per_mesh,
            closure=none,
            iterations=np.zeros(0, int),
            cpu_seconds=none,
            kinds=(),
            end="made to fail",
            failed=True,
        )

    monkeypatch.setattr(sweep_module, "follow", fails)
    return speed_sweep(_system(), speeds, direction=direction, **KW)


@pytest.mark.slow  # a fine natural-parameter sweep, or a second continuation: 10-15 s
def test_folds_agree_with_a_fine_natural_sweep_and_beat_the_bisection(both, monkeypatch):
    """Each fold located by continuation lies between the last speed a plain natural-parameter
    shooting sweep at steps of 2e-6 ω_n continues the branch to and the next (measured: 0.8748546
    in [0.874854, 0.874856], 0.7392467 in [0.739246, 0.739248]): the stated tolerance is that step.
    The bisection of the ends to 1e-3 of the speed (the fallback, run here on the same sweep) puts
    the edges 2.8e-4 and 1.1e-5 ω_n off, outside those brackets."""
    upper, lower = max(both.fold_speeds) / W, min(both.fold_speeds) / W
    steps = [1e-2, 1e-3, 5e-5, REFERENCE_STEP]
    last, first_off = _natural_end(0.86, steps[1:], +1)  # up the contact branch to its fold
    assert last <= upper <= first_off
    last_down, first_off_down = _natural_end(0.9, steps, -1)  # down the separating branch to its fold
    assert first_off_down <= lower <= last_down
    bisected = _bisected(monkeypatch, np.array([0.6, 0.7, 0.8, 0.9, 1.0]) * W, "both")
    band = bisected.hysteresis()["m"]
    assert band is not None
    reference = (0.5 * (last_down + first_off_down), 0.5 * (last + first_off))
    for edge, fold, ref in zip(np.array(band) / W, (lower, upper), reference, strict=True):
        assert abs(fold - ref) <= REFERENCE_STEP < abs(edge - ref) <= EDGE_RTOL * edge
    assert "bisected" in " ".join(bisected.notes) and not any("bisect" in n for n in both.notes)
    assert all("bisection" not in p for p in both.solve_paths + both.down.solve_paths)


@pytest.mark.slow  # the fixture follows both branches of the backlash pair: 10 s
def test_the_middle_branch_is_unstable_the_outer_ones_stable(both):
    """Along the branch the up sweep followed: stable (every multiplier inside the unit circle, a
    complex pair) up to the first fold; at each fold a real multiplier is +1 (to 1e-3; measured
    7.5e-5 and 8.6e-6, the down sweep's 4.6e-7) and crosses it; between the folds a real multiplier
    above 1 (up to 1.83), so the middle branch is unstable; the down sweep's branch is stable up to
    its fold. Every speed the sweeps report is stable, and the plot draws the middle branch dashed."""
    (up,) = both.branches
    (down,) = both.down.branches
    first, second = up.fold_indices
    assert up.kinds[0] == "start" and up.kinds[-1] == "fold" and second == up.speeds.size - 1
    assert up.stable[:first].all() and down.stable[: down.fold_indices[0]].all()
    mu = up.leading_real_multiplier()
    assert abs(mu[first] - 1.0) < 1e-3 and abs(mu[second] - 1.0) < 1e-3
    assert abs(down.leading_real_multiplier()[down.fold_indices[0]] - 1.0) < 1e-3
    assert mu[first - 1] < 1.0 < mu[first + 1]  # the real multiplier crosses +1 there
    middle = slice(first + 1, second)
    assert (~up.stable[middle]).all() and (mu[middle] > 1.0).all() and mu[middle].max() > 1.5
    assert up.spectral_radius[middle] == pytest.approx(mu[middle], rel=1e-12)
    assert np.sign(up.speed_tangent[first - 1]) != np.sign(up.speed_tangent[first + 1])
    assert both.stable.all() and both.down.stable.all() and both.summary()["unstable_points"] == 0
    import matplotlib

    matplotlib.use("Agg")
    ax = both.plot().axes[0]
    dashed = [
        line for line in ax.get_lines() if line.get_linestyle() == "--" and "folds" in str(line.get_label())
    ]
    assert dashed and np.isfinite(dashed[0].get_ydata()).sum() >= second - first
    import matplotlib.pyplot as plt

    plt.close(ax.figure)


@pytest.mark.slow  # a fine natural-parameter sweep, or a second continuation: 10-15 s
def test_the_folds_do_not_depend_on_the_grid(both):
    """Swept up over another grid (seven speeds, none shared with the five of the fixture but the
    ends) the up sweep traces both folds again: each agrees with the fixture's to 1e-6 of the speed
    (measured 9e-10 and 4e-10: the folds are located to 1e-7 and their speed taken at the
    parabola's vertex)."""
    other = speed_sweep(
        _system(), np.array([0.6, 0.66, 0.72, 0.78, 0.84, 0.92, 1.0]) * W, direction="up", **KW
    )
    assert len(other.fold_speeds) == 2
    np.testing.assert_allclose(other.fold_speeds, both.fold_speeds, rtol=1e-6)
    assert FOLD_RTOL <= 1e-6


@pytest.mark.slow  # the fixture follows both branches of the backlash pair: 10 s
def test_the_band_s_edges_are_the_folds_not_the_grid(both):
    """What issue 43 asks: the jump band's edges are the folds located by continuation. The up sweep
    jumps at the upper fold, the down sweep at the lower; the band the result reports is those two
    speeds (none of them a grid speed), the summary lists the folds, the table says how each speed
    was found, and each speed states its CPU time."""
    low, high = both.hysteresis()["m"]
    lower, upper = both.fold_speeds
    assert both.jump_speeds == (high,) and both.down.jump_speeds == (low,)
    assert high == pytest.approx(upper, rel=1e-9) and low == pytest.approx(lower, rel=1e-6)
    assert not np.isclose(np.array([low, high])[:, None], np.array([0.6, 0.7, 0.8, 0.9, 1.0]) * W).any()
    meshes = both.summary()["meshes"]["m"]
    assert meshes["hysteresis_speeds_rad_s"] == [low, high]
    assert meshes["fold_speeds_rad_s"] == pytest.approx([lower, upper])
    tables = {t.title: t for t in both.tables()}
    branches = tables["branches followed through their folds by pseudo-arclength continuation"]
    assert [row[0] for row in branches.rows] == ["up", "down"] and "the folds" in branches.note
    how = tables["how each speed's periodic orbit was found (backlash), and its CPU time"]
    assert any("continuation to the branch's end" in row[1] for row in how.rows)
    assert np.isfinite(both.solve_cpu).all() and (both.solve_cpu >= 0).all()
    assert len(both.solve_paths) == both.speeds.size
    assert "solve_cpu_s" in both.to_frame().columns
    arrays = both.arrays()
    assert arrays["branch_0_speed_rad_s"][1] == "rad/s" and arrays["branch_0_cpu_s"][1] == "s"


def test_a_failed_continuation_falls_back_to_bisection_and_says_so(monkeypatch):
    """Where the continuation fails (here: made to), the branch's end is bisected to 1e-3 of the
    speed as before, and the result says so among its notes and in how each speed was found."""
    r = _bisected(monkeypatch, np.array([0.8, 0.9]) * W, "up")
    (jump,) = r.jump_speeds
    assert 0.8735 * W < jump < 0.8755 * W
    assert any("the continuation failed (made to fail)" in n for n in r.notes)
    assert any("bisection" in p for p in r.solve_paths) and not r.branches


def test_follow_reaches_the_speed_asked_for_where_there_is_no_fold():
    """Below the band the branch is single: the continuation gets to the speed asked for with a
    stable orbit, the one Newton finds there from the static deflection's run (to 1e-7)."""
    lin = linear_periodic(_system(), reference="pinion", load={"gear": LOAD})
    plan = period_plan(lin)
    speed = 0.6 * W
    _t, x, v, ok, _phi, _c = _shoot_nonlinear(lin, plan, speed, _warm_start(lin, plan, speed), 64)
    branch = follow(
        lin, plan, speed, np.concatenate([x[0], v[0]]), toward=0.65 * W, bounds=(0.6 * W, 0.7 * W)
    )
    assert not branch.failed and branch.kinds[-1] == "target" and branch.end == "at the speed asked for"
    assert (
        branch.speeds[-1] == pytest.approx(0.65 * W, rel=1e-12) and branch.stable.all() and not branch.folds
    )
    _t, x, v, ok, _phi, _c = _shoot_nonlinear(lin, plan, 0.65 * W, _warm_start(lin, plan, 0.65 * W), 64)
    assert ok
    y = np.concatenate([x[0], v[0]])
    assert np.abs(branch.states[-1] - y).max() <= 1e-7 * np.abs(y).max()
