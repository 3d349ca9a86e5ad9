"""The senses of rotation that the steady state must keep: a mesh whose gear a turns backwards runs
its stiffness cycle and error backwards (the phase's sign in the period plan), and a motor behind a
ratio gives its disk the ratio times its torque at the ratio times the disk's speed. Each against
the time integration (``simulate``), which takes the phase from the actual angles and the motor's
torque from its own speed."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from mechdyn.drive import InductionMotor
from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, Shaft
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.loads import ConstantTorque, MotorTorque
from mechdyn.gear_dynamics.simulate import simulate
from mechdyn.gear_dynamics.steady import steady_state

P = 40
LOAD = 10.0  # N·m drawn at the output (5 N·m at the motor disk: within the motor's starting torque)


def _saw(P: int, eps: float, skew: float) -> np.ndarray:
    """A stiffness cycle that rises slowly and falls fast: not the same run backwards."""
    u = np.arange(P) / P
    return 1.0 + eps * (np.mod(u + skew, 1.0) - 0.5)


def _train() -> GearSystem:
    """Motor — shaft — pinion ~ mesh 1 ~ idler ~ mesh 2 ~ output: mesh 2's gear a (the idler) turns
    against mesh 1's (the pinion)."""
    dt = Drivetrain(
        [Disk("motor", 0.004), Disk("pinion", 0.001), Disk("idler", 0.003), Disk("out", 0.02)],
        [
            Shaft("s", ("motor", "pinion"), 2e4, damping=2.0),
            GearMesh(
                "m1",
                ("pinion", "idler"),
                teeth=(20, 30),
                base_radii=(0.019, 0.0285),
                stiffness=3e8,
                damping=900.0,
            ),
            GearMesh(
                "m2",
                ("idler", "out"),
                teeth=(30, 40),
                base_radii=(0.0285, 0.038),
                stiffness=3e8,
                damping=900.0,
            ),
        ],
        name="opposite meshes",
    )
    return GearSystem.from_drivetrain(
        dt,
        mesh_profiles={"m1": _saw(P, 0.3, 0.0), "m2": _saw(P, 0.4, 0.3)},
        errors={
            "m1": 2e-6 * np.sin(2 * np.pi * np.arange(P) / P),
            "m2": 3e-6 * np.cos(4 * np.pi * np.arange(P) / P),
        },
    )


def _motor(ratio: float = 1.0) -> MotorTorque:
    return MotorTorque("motor", InductionMotor.from_rating("3 kW", "3000 rpm", "2880 rpm", 2.8), ratio)


def _running_speed(system: GearSystem, motor: MotorTorque) -> float:
    """The motor disk's speed, rad/s, at which ratio · T(ratio · ω) carries the load (Kloss)."""
    r = system.speed_ratios("motor")
    reflected = LOAD * abs(r[system.coordinate_names.index("out")])
    ws = motor.motor.synchronous_speed / motor.ratio
    return brentq(lambda w: motor.torque(0.0, w) - reflected, 0.9 * ws, ws * (1 - 1e-12))


@pytest.mark.slow  # two long time integrations: 7 s
def test_the_meshes_turning_opposite_ways_keep_their_cycles_senses_as_in_simulate():
    """Both mesh forces over a period of the steady state (the motor free on its curve) against
    simulate's last period at the same running speed: largest and smallest within 3e-3 of the swing.
    Mesh 2's cycle run the wrong way (its phase's sign lost) misses by 0.6-5 % of the swing."""
    system = _train()
    motor = _motor()
    speed = _running_speed(system, motor)
    s = steady_state(system, speed, reference="motor", load={"out": LOAD}, motor=motor, harmonics=64)
    assert s.harmonics_error < 1e-2
    sim = simulate(
        system,
        0.25,
        inputs=[motor, ConstantTorque("out", -LOAD)],  # two meshes: the output turns forwards
        initial_speed=speed,
        reference="motor",
        method="DOP853",
        rtol=1e-9,
        output_step=s.period / 400,
    )
    last = sim.time > sim.time[-1] - s.period
    assert sim.speeds[0, last].mean() == pytest.approx(speed, rel=1e-4)  # at the running speed
    for j in range(2):
        f = sim.mesh_forces[j][last]
        swing = np.ptp(s.mesh_force[:, j])
        assert abs(f.max() - s.mesh_force[:, j].max()) <= 3e-3 * swing
        assert abs(f.min() - s.mesh_force[:, j].min()) <= 3e-3 * swing


@pytest.mark.parametrize("ratio", [pytest.param(1.0, marks=pytest.mark.slow), 2.5])
def test_a_motor_behind_a_ratio_runs_where_its_torque_times_the_ratio_carries_the_load(ratio):
    """simulate from rest settles at the speed of Kloss's formula with the ratio on both speed and
    torque; the steady state's motor needs the load over the ratio at its shaft."""
    system = _train()
    motor = _motor(ratio)
    speed = _running_speed(system, motor)
    sim = simulate(system, 0.6, inputs=[motor, ConstantTorque("out", -LOAD)], start="rest", rtol=1e-8)
    settled = sim.time > 0.5
    assert sim.speeds[0, settled].mean() == pytest.approx(speed, rel=1e-4)
    s = steady_state(system, speed, reference="motor", load={"out": LOAD}, motor=motor, harmonics=8)
    reflected = LOAD * abs(system.speed_ratios("motor")[system.coordinate_names.index("out")])
    assert "motor on disk 'motor'" in s.drive
    from mechdyn.gear_dynamics.steady import _model

    lin = _model(system, "motor", {"out": LOAD}, None, motor)
    assert lin.motor.torque(speed) == pytest.approx(reflected / ratio, rel=1e-12)
    assert motor.motor.torque(lin.motor.shaft_speed(reflected / ratio)) == pytest.approx(reflected / ratio)
    assert lin.motor.shaft_speed(reflected / ratio) == pytest.approx(ratio * speed, rel=1e-9)
