"""Planar mechanisms: kinematics, inverse dynamics, shaking force and moment (SPEC §1).

Describe a mechanism by an assembly drawing (:class:`Mechanism` of :class:`Body`, :class:`Revolute`,
:class:`Prismatic`, a :class:`Driver`, optional gravity and :class:`ProcessForce`), or load a
``type = "mechanism"`` file with :func:`mechdyn.load`. :func:`kinematics` and
:func:`inverse_dynamics` analyse one revolution; :func:`cycle` runs many design variants at once.
Gear pairs (:class:`GearJoint`, circular or noncircular pitch curves from :mod:`.pitch`) make
geared linkages and planetary trains on a carrier.
"""

from mechdyn.mechanism.dyads import CycleBatch, NotDecomposable, cycle
from mechdyn.mechanism.dynamics import DynamicsResult, inverse_dynamics
from mechdyn.mechanism.kinematics import AssemblyError, KinematicsResult, SingularPositionError, kinematics
from mechdyn.mechanism.model import (
    GROUND,
    Body,
    Driver,
    GearJoint,
    Mechanism,
    Prismatic,
    ProcessForce,
    Revolute,
)

__all__ = [
    "GROUND",
    "AssemblyError",
    "Body",
    "CycleBatch",
    "Driver",
    "DynamicsResult",
    "GearJoint",
    "KinematicsResult",
    "Mechanism",
    "NotDecomposable",
    "Prismatic",
    "ProcessForce",
    "Revolute",
    "SingularPositionError",
    "cycle",
    "inverse_dynamics",
    "kinematics",
]
