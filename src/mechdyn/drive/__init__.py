"""The mechanism driven by a motor through gears and a flywheel: forward dynamics of the one degree of
freedom, the speed fluctuation, the flywheel that holds it, the motor's torque and power.

Reduce a mechanism to its crank (:func:`reduce_to_crank`: I(φ), I′(φ), Q(φ) from the assembled
model), drive it (:class:`Drive` of an :class:`InductionMotor` or a :class:`TorqueSpeedCurve`, a gear
ratio or a train of :class:`Stage` (belts, meshes, each with its efficiency and shaft inertia), a
flywheel where it sits, a :class:`FormingForce`), and solve it: :func:`steady_state`, :func:`start_up`,
:func:`size_flywheel`, or all together with the loads at the real speed, :func:`drive_analysis`. A
``type = "drive"`` model file runs as ``mechdyn drive FILE``.
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "Drive": "model",
        "DriveResult": "result",
        "FormingForce": "model",
        "InductionMotor": "motor",
        "ReducedMechanism": "inertia",
        "StallError": "forward",
        "Stage": "train",
        "StartUp": "forward",
        "SteadyState": "forward",
        "TorqueSpeedCurve": "motor",
        "drive_analysis": "result",
        "mechanism_at_speed": "result",
        "reduce_to_crank": "inertia",
        "size_flywheel": "forward",
        "start_up": "forward",
        "steady_state": "forward",
    },
)
