"""Torsional vibration of geared drivetrains (SPEC §3)."""

from mechdyn.drivetrain.assembly import Assembly, assemble, check_matrices
from mechdyn.drivetrain.elements import Disk, GearMesh, GroundDamper, GroundSpring, Shaft
from mechdyn.drivetrain.modal import ModalResult, modal
from mechdyn.drivetrain.model import Drivetrain

__all__ = [
    "Assembly",
    "Disk",
    "Drivetrain",
    "GearMesh",
    "GroundDamper",
    "GroundSpring",
    "ModalResult",
    "Shaft",
    "assemble",
    "check_matrices",
    "modal",
]
