"""Planar mechanisms: kinematics, inverse dynamics, shaking force and moment (SPEC §1).

Describe a mechanism by an assembly drawing (:class:`Mechanism` of :class:`Body`, :class:`Revolute`,
:class:`Prismatic`, a :class:`Driver`, optional gravity and :class:`ProcessForce`), or load a ``type =
"mechanism"`` file with :func:`mechdyn.load`. :func:`kinematics` and :func:`inverse_dynamics` analyse
one revolution; :func:`cycle` (point and mass arrays over one model) and :func:`variants` (a sequence of
variant models) run many design variants at once, each variant with its status. Gear pairs
(:class:`GearJoint`, circular or noncircular pitch curves from :mod:`.pitch`) make geared linkages and
planetary trains on a carrier.
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "AssemblyError": "revolution",
        "Body": "model",
        "Counterweight": "model",
        "CycleBatch": "dyads",
        "DesignBatch": "designs",
        "Driver": "model",
        "DynamicsResult": "dynamics",
        "GROUND": "model",
        "GearJoint": "model",
        "KinematicsResult": "kinematics",
        "Mechanism": "model",
        "NotDecomposable": "dyads",
        "PlanterDesign": "planter",
        "Prismatic": "model",
        "ProcessForce": "model",
        "Revolute": "model",
        "SingularPositionError": "revolution",
        "cycle": "dyads",
        "inverse_dynamics": "dynamics",
        "dyad_motion": "kinematics",
        "kinematics": "kinematics",
        "newton_motion": "kinematics",
        "planter": "planter",
        "variants": "designs",
    },
)
