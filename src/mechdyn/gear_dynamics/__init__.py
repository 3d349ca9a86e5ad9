"""Geared drivetrains in time: time-varying mesh stiffness, transmission error, backlash, motors.

:class:`GearSystem` turns a :class:`mechdyn.drivetrain.Drivetrain` into the equations of motion in its
reduced coordinates, each flexible mesh a :class:`MeshLink` (stiffness over the mesh cycle, static
transmission error, backlash). :func:`simulate` integrates it in time under the torque inputs of
:mod:`~mechdyn.gear_dynamics.loads` (constant, harmonic, step, ramp, tabulated, a motor of
:mod:`mechdyn.drive`, an emergency stop) and returns a :class:`SimulationResult`. :func:`speed_sweep`
gives the periodic steady state over a speed range (harmonic balance, shooting) with the dynamic mesh
force and the dynamic factor against ISO 6336-1's K_v; :func:`floquet` and :func:`stability_chart` the
Floquet multipliers of the time-periodic system, the parametric instabilities a Campbell diagram does
not show.
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        # -- system (time-domain core) --
        "GearSystem": "system",
        "MeshLink": "system",
        "rectangular_profile": "system",
        # -- time simulation --
        "simulate": "simulate",
        "static_deflection": "simulate",
        "SimulationResult": "result",
        "ContactLoss": "result",
        # -- torque inputs --
        "BrakeStop": "loads",
        "ConstantTorque": "loads",
        "HarmonicTorque": "loads",
        "MotorTorque": "loads",
        "RampTorque": "loads",
        "StepTorque": "loads",
        "TabulatedTorque": "loads",
        # -- periodic steady state over speed, Floquet stability --
        "speed_sweep": "sweep",
        "steady_state": "steady",
        "SpeedSweepResult": "sweep_result",
        "SteadyState": "steady",
        "floquet": "floquet",
        "monodromy": "propagators",
        "stability_chart": "floquet",
        "FloquetResult": "floquet",
        "StabilityChart": "floquet",
    },
)
