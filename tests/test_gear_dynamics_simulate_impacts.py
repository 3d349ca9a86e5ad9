"""Back-side impacts in ``simulate``: the contact events of a gear pair whose teeth cross the whole
backlash within one integration step, and the orbit the run settles on against Newton shooting on the
event-located flow (:mod:`mechdyn.gear_dynamics._nonsmooth`), which uses the same contact law."""

from __future__ import annotations

import numpy as np
import pytest

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh
from mechdyn.gear_dynamics import ConstantTorque, GearSystem, simulate
from mechdyn.gear_dynamics.steady import steady_state

RA, RB, ZA, P = 0.0188, 0.047, 20, 24
WN = np.sqrt(3e8 * RB**2 / 0.03)  # the gear's mode with the pinion held, rad/s
C, AMP, B, LOAD = 8000.0, 2e-6, 2e-6, 20.0  # N·s/m, m, m, N·m: back-side impacts every mesh cycle
SPEED = 0.9 * WN / ZA  # rad/s of the pinion
T = 2 * np.pi / (ZA * SPEED)  # the mesh period, s
DRIVE, GAP, BACK = 0, 1, 2


def _system(j_pinion: float) -> GearSystem:
    dt = Drivetrain(
        [Disk("pinion", j_pinion), Disk("gear", 0.03)],
        [GearMesh("m", ("pinion", "gear"), teeth=(ZA, 50), base_radii=(RA, RB), stiffness=3e8, damping=C)],
        name="pair",
    )
    return GearSystem.from_drivetrain(dt, errors={"m": {"amplitude": AMP, "samples": P}}, backlash={"m": B})


def _run(system: GearSystem, periods: int, **kwargs):
    """At (nearly) constant speed: the pinion 3·10⁵ times heavier than the gear, driven by the load's
    torque over the ratio."""
    ratio = abs(system.speed_ratios("pinion")[1])
    return simulate(
        system,
        periods * T,
        inputs=[ConstantTorque("gear", LOAD), ConstantTorque("pinion", LOAD * ratio)],
        initial_speed=SPEED,
        reference="pinion",
        **kwargs,
    )


@pytest.mark.parametrize(
    ("method", "rtol", "atol"), [("DOP853", 1e-10, 1e-13), ("Radau", 1e-8, 1e-12), ("LSODA", 1e-8, 1e-12)]
)
@pytest.mark.parametrize("start", ["static", "rest"])
def test_impacts_across_the_backlash_are_located(method, rtol, atol, start):
    """The relative velocity at the impacts (about 0.02 m/s) carries the teeth across the 2 µm
    backlash in less than one of the steps the free flight allows: each boundary x = 0 and x = −b
    is an event of its own, and a restart a rounding error on the old side of the boundary it has
    just crossed does not count as a new crossing (it made DOP853 and Radau stop with "the contact
    chatters", the mode flipped back and forth at one instant). Every sample's mode agrees with the
    sign of x and x + b, to 1e-8 of the backlash; four changes a mesh cycle at most (drive → gap →
    back → gap → drive), each contact loss after the start with one back-side impact."""
    sim = _run(_system(1e4), 4, method=method, rtol=rtol, atol=atol, start=start, max_events=100)
    x, mode = sim.dte[0], sim.contact_modes[0]
    assert set(np.unique(mode)) == {DRIVE, GAP, BACK}
    outside = np.concatenate([-x[mode == DRIVE], x[mode == GAP], -B - x[mode == GAP], x[mode == BACK] + B])
    assert outside.max() <= 1e-8 * B
    assert sim.stats["contact_changes"] <= 4 * 4
    losses = [loss for loss in sim.contact_losses if loss.start > 0.0]  # (from rest: in the gap at 0)
    assert losses and all(loss.back_impacts == 1 for loss in losses)


def test_back_side_impacts_settle_on_the_orbit_of_newton_shooting():
    """The run settles on the periodic orbit Newton shooting finds on the event-located flow (the same
    contact law: f = k h + c ẋ_r while in contact, the mode switched where x crosses 0 or −b): after
    40 mesh periods the next one, sampled on the same instants, agrees to 2e-5 of the force and DTE
    swings (measured 1.9e-6 and 1.6e-6). Left out: the samples on the corners of the error profile,
    where its slope jumps (the simulated phase, read from the pinion's angle, is 2e-8 of a cycle
    behind the nominal one, so the damping force takes the slope of the segment before: c Δė ≈ 18 N,
    3e-3 of the swing)."""
    s = steady_state(
        _system(0.05), SPEED, reference="pinion", drive="speed", load={"gear": LOAD}, method="shooting"
    )
    assert s.converged
    assert s.deflection[:, 0].min() < -B  # back-side contact on the orbit
    sim = _run(_system(1e4), 41, method="DOP853", rtol=1e-10, atol=1e-13, output_step=T / s.time.size)
    N = s.time.size
    last = sim.time > sim.time[-1] - T * (1 - 0.5 / N)
    t = sim.time[last]
    k = np.round((t % T) / T * N).astype(int) % N
    assert np.unique(k).size == N
    assert set(np.unique(sim.contact_modes[0][last])) == {DRIVE, GAP, BACK}
    smooth = np.abs(k * P / N - np.round(k * P / N)) > 1e-9  # off the error's corners
    assert smooth.sum() >= N - P
    f = s.mesh_force[k, 0]
    assert np.abs(sim.mesh_forces[0][last] - f)[smooth].max() <= 2e-5 * np.ptp(f)
    e = sim.system.meshes[0].transmission_error(ZA * SPEED * t / (2 * np.pi))
    d = s.deflection[k, 0]
    assert np.abs(sim.dte[0][last] + e - d).max() <= 2e-5 * np.ptp(d)
