"""Gear tooth and mesh stiffness (SPEC §4).

:class:`TruncatedTooth` is the published truncated-triangle tooth with its compliance terms;
:class:`SpurGear` derives it from ordinary gear data; :class:`GearPair` gives the contact ratio, the
stiffness of one tooth pair along the path of contact and the mesh stiffness over a mesh cycle;
:func:`iso_stiffness` is ISO 6336-1 Method B for comparison.
"""

from mechdyn.gears.geometry import SpurGear
from mechdyn.gears.iso6336 import IsoStiffness, iso_stiffness
from mechdyn.gears.mesh import GearPair, MeshCycle
from mechdyn.gears.tooth import TruncatedTooth, hertz_compliance, pair_compliance

__all__ = [
    "GearPair",
    "IsoStiffness",
    "MeshCycle",
    "SpurGear",
    "TruncatedTooth",
    "hertz_compliance",
    "iso_stiffness",
    "pair_compliance",
]
