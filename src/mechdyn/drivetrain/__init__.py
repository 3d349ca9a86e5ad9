"""Torsional vibration of geared drivetrains (SPEC §3).

Build a :class:`Drivetrain` from :class:`Disk`, :class:`Shaft`, :class:`GearMesh`,
:class:`GroundSpring` and :class:`GroundDamper` (or load a model file with :func:`mechdyn.load`), then
run :func:`modal`, :func:`campbell`, :func:`frf` or :func:`compare_rigid`. :func:`assemble` gives the
checked matrices; :func:`check_matrices` checks a hand-made pair.
"""

from mechdyn.drivetrain.assembly import Assembly, assemble, check_matrices
from mechdyn.drivetrain.campbell import CampbellResult, campbell
from mechdyn.drivetrain.compare import ModeComparison, compare_rigid, mac
from mechdyn.drivetrain.elements import Disk, GearMesh, GroundDamper, GroundSpring, Shaft
from mechdyn.drivetrain.modal import ModalResult, modal
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.drivetrain.response import FRFResult, ModalDamping, RayleighDamping, frf

__all__ = [
    "Assembly",
    "CampbellResult",
    "Disk",
    "Drivetrain",
    "FRFResult",
    "GearMesh",
    "GroundDamper",
    "GroundSpring",
    "ModalDamping",
    "ModalResult",
    "ModeComparison",
    "RayleighDamping",
    "Shaft",
    "assemble",
    "campbell",
    "check_matrices",
    "compare_rigid",
    "frf",
    "mac",
    "modal",
]
