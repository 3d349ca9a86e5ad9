"""Periodic steady state of a gear pair with backlash where the teeth separate: the event-located flow's
Jacobian (saltation matrices) against finite differences, Newton's orbit against ``simulate``, the
up and down sweeps (the jump phenomenon), and the prominence rule of the listed resonances."""

from __future__ import annotations

import numpy as np
import pytest

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics._nonsmooth import BACK, DRIVE, GAP, NonsmoothFlow
from mechdyn.gear_dynamics.floquet import linear_periodic, period_plan
from mechdyn.gear_dynamics.shooting import _shoot_nonlinear, _warm_start
from mechdyn.gear_dynamics.steady import speed_sweep, steady_state
from mechdyn.gear_dynamics.sweep_result import _peaks

RA, RB, ZA, P = 0.0188, 0.047, 20, 24
WN = np.sqrt(3e8 * RB**2 / 0.03)  # the gear's mode with the pinion held, rad/s


def _cosine(eps: float) -> np.ndarray:
    i = np.arange(P) / P
    return 1.0 + eps * np.cos(2 * np.pi * i) + 0.3 * eps * np.sin(4 * np.pi * i)


def _system(c: float, amp: float, b: float, eps: float, J_pinion: float = 0.05) -> GearSystem:
    dt = Drivetrain(
        [Disk("pinion", J_pinion), Disk("gear", 0.03)],
        [GearMesh("m", ("pinion", "gear"), teeth=(ZA, 50), base_radii=(RA, RB), stiffness=3e8, damping=c)],
        name="pair",
    )
    return GearSystem.from_drivetrain(
        dt,
        mesh_profiles={"m": _cosine(eps)},
        errors={"m": {"amplitude": amp, "samples": P}},
        backlash={"m": b},
    )


def _at_nearly_constant_speed(big: GearSystem, load: float, speed: float, duration: float, **kw):
    """``simulate`` of a pair whose pinion is so heavy that it keeps its speed (the mesh phase the
    nominal one), driven by the load's torque over the ratio, from the static deflection (DOP853)."""
    from mechdyn.gear_dynamics.loads import ConstantTorque
    from mechdyn.gear_dynamics.simulate import simulate

    ratio = abs(big.speed_ratios("pinion")[1])
    inputs = [ConstantTorque("gear", load), ConstantTorque("pinion", load * ratio)]
    return simulate(
        big, duration, inputs=inputs, initial_speed=speed, reference="pinion", method="DOP853", **kw
    )


# contact loss each mesh cycle (light load, near the resonance); back-side impacts (small backlash)
LOSS = {"c": 3000.0, "amp": 1e-6, "b": 2e-5, "eps": 0.1, "load": 10.0, "f": 0.95}
IMPACT = {"c": 8000.0, "amp": 2e-6, "b": 2e-6, "eps": 0.0, "load": 20.0, "f": 0.9}


@pytest.mark.parametrize(("case", "modes"), [(LOSS, {GAP, DRIVE}), (IMPACT, {GAP, DRIVE, BACK})])
def test_monodromy_with_saltation_is_the_finite_difference_jacobian(case, modes):
    """The Jacobian of the period map carried by the variational equations with a saltation matrix at
    every contact change equals the central finite difference of the event-located flow (1e-6 of its
    largest entry, speeds scaled by the mesh frequency), and so do the Floquet multipliers; without
    the saltation the Jacobian is 1e-3 off or more and, with contact loss, the multipliers 1 % (the
    mesh's damping force jumps where the teeth meet or part)."""
    system = _system(case["c"], case["amp"], case["b"], case["eps"])
    lin = linear_periodic(system, reference="pinion", load={"gear": case["load"]})
    plan = period_plan(lin)
    speed = case["f"] * WN / ZA
    _t, x, v, ok, _, closure = _shoot_nonlinear(lin, plan, speed, _warm_start(lin, plan, speed), 16)
    assert ok and closure < 1e-7
    y = np.concatenate([x[0], v[0]])
    flow = NonsmoothFlow(lin, plan, speed, rtol=1e-12)
    _, end, crossings = flow.run(y)
    assert {c.new for c in crossings} == modes
    Phi = end[2:].reshape(2, 2)
    no_salt = NonsmoothFlow(lin, plan, speed, rtol=1e-12, saltation=False).run(y)[1][2:].reshape(2, 2)
    fd = np.zeros((2, 2))
    for i in range(2):
        h = 1e-5 * abs(y[i])
        up, dn = y.copy(), y.copy()
        up[i] += h
        dn[i] -= h
        fd[:, i] = (flow.run(up, variational=False)[1] - flow.run(dn, variational=False)[1]) / (2 * h)
    D = np.diag([1.0, 2 * np.pi / flow.T])  # speeds in units of x per period
    scaled = np.abs(np.linalg.solve(D, fd @ D)).max()
    assert np.abs(np.linalg.solve(D, (Phi - fd) @ D)).max() < 1e-6 * scaled
    mu = np.sort_complex(np.linalg.eigvals(fd))
    assert np.abs(np.sort_complex(np.linalg.eigvals(Phi)) - mu).max() < 1e-6 * np.abs(mu).max()
    assert np.abs(np.linalg.solve(D, (no_salt - fd) @ D)).max() > 1e-3 * scaled
    if case is LOSS:  # (in the impact case here the saltations happen to leave the multipliers alone)
        assert np.abs(np.sort_complex(np.linalg.eigvals(no_salt)) - mu).max() > 0.01 * np.abs(mu).max()


@pytest.mark.slow
def test_newton_through_contact_loss_is_the_orbit_simulate_settles_on():
    """Light load near the resonance: the teeth part once a mesh cycle. Newton's method (from a run
    from the static deflection) converges, and its orbit is the one ``simulate`` settles on after 68
    mesh periods at constant speed: the pinion 2·10⁵ times heavier than the gear (its speed varies by
    3e-9, so that it is the kinematic input of the steady state and the mesh phase its nominal one),
    driven by the load's torque over the ratio, the same stiffness, error and backlash; the last
    period, sampled on the same instants, agrees to 2e-5 of the force and DTE swings (measured
    2.3e-6 and 2.9e-6)."""

    c, amp, b, eps, load = 8000.0, 0.5e-6, 2e-5, 0.1, 20.0
    speed = 0.9 * WN / ZA
    system = _system(c, amp, b, eps)
    s = steady_state(system, speed, reference="pinion", drive="speed", load={"gear": load}, method="shooting")
    assert s.converged
    assert s.mesh_force[:, 0].min() < 0.0 and (s.deflection[:, 0] < 0).any()  # the teeth part
    big = _system(c, amp, b, eps, J_pinion=1e4)
    N, T = s.time.size, s.period
    sim = _at_nearly_constant_speed(big, load, speed, 68 * T, rtol=1e-10, atol=1e-13, output_step=T / N)
    last = sim.time > sim.time[-1] - T * (1 - 0.5 / N)
    t = sim.time[last]
    k = np.round((t % T) / T * N).astype(int) % N
    assert np.unique(k).size == N
    f = s.mesh_force[k, 0]
    assert np.abs(sim.mesh_forces[0][last] - f).max() <= 2e-5 * np.ptp(f)
    e = big.meshes[0].transmission_error(ZA * speed * t / (2 * np.pi))
    d = s.deflection[k, 0]
    assert np.abs(sim.dte[0][last] + e - d).max() <= 2e-5 * np.ptp(d)


@pytest.mark.slow
def test_up_and_down_sweeps_show_the_jump():
    """The softening backlash nonlinearity (Kahraman & Singh 1990): between about 0.72 and 0.87 ω_n
    the teeth-in-contact orbit and an orbit with contact loss both attract. Sweeping up the sweep
    stays in contact at 0.8 ω_n and jumps to the separating branch before 0.95 ω_n; sweeping down it
    stays on that branch at 0.8 ω_n and jumps back before 0.6 ω_n. Outside the band the two sweeps
    agree (1e-6 of the force), inside they differ by more than 50 %; every orbit closes to 1e-7."""
    system = _system(8000.0, 0.5e-6, 2e-5, 0.0)
    speeds = np.array([0.6, 0.8, 0.95]) * WN / ZA
    r = speed_sweep(
        system, speeds, reference="pinion", drive="speed", load={"gear": 20.0}, refine=0, direction="both"
    )
    d = r.down
    assert d is not None and r.direction == "up" and d.direction == "down"
    for sweep in (r, d):
        assert sweep.converged.all() and sweep.stable.all()
        assert np.nanmax(sweep.closure) < 1e-7
    i_up = np.searchsorted(r.speeds, speeds)
    i_dn = np.searchsorted(d.speeds, speeds)
    up, dn = r.force_amplitude[i_up, 0], d.force_amplitude[i_dn, 0]
    np.testing.assert_allclose(up[[0, 2]], dn[[0, 2]], rtol=1e-6)
    assert dn[1] > 1.5 * up[1]
    assert r.force_min[i_up[1], 0] > 0 and d.force_min[i_dn[1], 0] < 0  # in contact / parting
    (band,) = r.hysteresis().values()
    assert band is not None and band[0] <= speeds[1] <= band[1] < speeds[2]
    assert r.summary()["meshes"]["m"]["hysteresis_speeds_rad_s"] == list(band)
    note = r.tables()[0].note
    assert "'m' has two branches from" in note and "the table is the up sweep's" in note
    assert note.startswith("Computed by shooting with Newton's method on the backlash flow, continued")


def test_sweep_direction_is_checked_and_harmonic_balance_ignores_it():
    from mechdyn.errors import ModelError

    tight = GearSystem.from_drivetrain(
        _system(800.0, 1e-6, 1e-5, 0.1).drivetrain, errors={"m": {"amplitude": 1e-6, "samples": 8}}
    )
    with pytest.raises(ModelError) as err:
        speed_sweep(tight, [50.0], reference="pinion", drive="speed", direction="sideways")
    assert err.value.field == "direction"
    up = speed_sweep(tight, [50.0, 60.0], reference="pinion", drive="speed", refine=0)
    both = speed_sweep(tight, [50.0, 60.0], reference="pinion", drive="speed", refine=0, direction="both")
    np.testing.assert_array_equal(up.force_max, both.force_max)
    assert both.down is not None and both.hysteresis() == {"m": None}
    assert "Swept up and down, 'm' has one branch (no jump)." in both.tables()[0].note
    assert "Swept up and down" not in up.tables()[0].note


def test_resonances_leave_out_ripples():
    """A resonance peak over a baseline with a ripple of 0.1 %: only the peak is a resonance
    (prominence at least 2 % of its height), where every local maximum would list a dozen."""
    x = np.linspace(0.0, 2.0, 401)
    y = 1.0 + 10.0 * np.exp(-(((x - 1.0) / 0.1) ** 2)) + 1e-3 * np.sin(2 * np.pi * x / 0.05)
    assert _peaks(y).tolist() == [int(np.argmax(y))]
    inner = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1
    assert inner.size > 10
    assert _peaks(np.array([1.0, np.nan, 2.0, 1.0])).tolist() == [2]
    assert _peaks(np.zeros(5)).size == 0


@pytest.mark.slow  # a long sweep (tens of seconds): CI's heavy step
def test_past_a_flip_the_period_doubled_orbit_is_the_one_simulate_settles_on():
    """A stiffness varying by 30 % with the mesh frequency at twice the gear's mode: the orbit of one
    mesh period is unstable (a Floquet multiplier below −1, the principal parametric resonance), and
    the backlash bounds the growth on an orbit of two mesh periods with contact loss. Newton over two
    periods finds it, stable; ``simulate`` from the static deflection (pinion 3·10⁵ times the gear's
    inertia, driven by the load over the ratio) settles on it after 160 mesh periods: its last two
    periods' largest force within 1e-3 of the swing, its RMS within 2e-3. Below the tongue the orbit
    of one period stays."""

    c, amp, b, eps, load = 4000.0, 1e-6, 1e-4, 0.3, 100.0
    system = _system(c, amp, b, eps)
    kw = {"reference": "pinion", "drive": "speed", "load": {"gear": load}, "method": "shooting"}
    below = steady_state(system, 1.8 * WN / ZA, **kw)
    assert below.converged and below.periods == 1
    speed = 2.0 * WN / ZA
    s = steady_state(system, speed, **kw)
    assert s.converged and s.periods == 2 and s.time[-1] > s.period
    f = s.mesh_force[:, 0]
    half = f.size // 2
    assert np.abs(f[:half] - f[half:]).max() > 0.5 * np.ptp(f)  # the two periods differ
    assert f.min() <= 0.0  # the teeth part
    T = s.period
    big = _system(c, amp, b, eps, J_pinion=1e4)
    sim = _at_nearly_constant_speed(big, load, speed, 160 * T, rtol=1e-9, output_step=T / 200)
    last = sim.mesh_forces[0][sim.time > sim.time[-1] - 2 * T]
    assert abs(last.max() - f.max()) <= 1e-3 * np.ptp(f)
    # the RMS, not the least force: that is the damping's spike where the teeth part, between samples
    assert np.sqrt(np.mean(last**2)) == pytest.approx(np.sqrt(np.mean(f**2)), rel=2e-3)
    sweep = speed_sweep(
        system, np.array([1.8, 2.0]) * WN / ZA, refine=0, **{k: v for k, v in kw.items() if k != "method"}
    )
    # (continued from 1.8: the halved steps where the orbit of one period is still stable are kept)
    assert sweep.period_multiple[0] == 1 and sweep.period_multiple[-1] == 2 and sweep.stable.all()
    assert sweep.summary()["period_doubled_points"] == 1
    assert "the period-doubled orbit, of two mesh periods, is shown" in sweep.tables()[0].note


@pytest.mark.slow  # a long sweep (tens of seconds): CI's heavy step
def test_the_jump_band_s_edges_are_located_where_a_fine_sweep_jumps():
    """Swept up and down over five speeds, the band's edges come from the ends of the branches,
    located by bisection (to 1e-3 of the speed), not from the grid: each lies between the two speeds
    of a fine grid (steps of 0.25 % of ω_n) across which a fine sweep's force amplitude jumps."""
    from mechdyn.gear_dynamics.steady import EDGE_RTOL

    system = _system(8000.0, 0.5e-6, 2e-5, 0.0)
    kw = {"reference": "pinion", "drive": "speed", "load": {"gear": 20.0}, "refine": 0}
    coarse = speed_sweep(system, np.array([0.6, 0.7, 0.8, 0.9, 1.0]) * WN / ZA, direction="both", **kw)
    low, high = coarse.hysteresis()["m"]
    assert coarse.jump_speeds == (high,) and coarse.down.jump_speeds == (low,)
    for edge, fine_range, direction, lead in (
        (high, (0.86, 0.885), "up", [0.8]),  # from the contact branch below the band
        (low, (0.725, 0.75), "down", [0.8, 0.9]),  # from the separating branch above the band's top
    ):
        grid = np.arange(*fine_range, 0.0025) * WN / ZA
        fine = speed_sweep(system, np.append(grid, np.array(lead) * WN / ZA), direction=direction, **kw)
        # the fine grid's own speeds (those its bisection added left out): where the amplitude jumps
        amp = np.interp(grid, fine.speeds, fine.force_amplitude[:, 0])
        k = int(np.argmax(np.abs(np.diff(amp))))
        assert abs(amp[k + 1] - amp[k]) > 0.3 * amp.max()
        assert grid[k] - EDGE_RTOL * edge <= edge <= grid[k + 1] + EDGE_RTOL * edge
