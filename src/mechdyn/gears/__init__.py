"""Gear tooth and mesh stiffness (SPEC §4).

:class:`TruncatedTooth` is the published truncated-triangle tooth with its compliance terms;
:class:`SpurGear` derives it from ordinary gear data (spur or helical, external or internal);
:class:`GearPair` gives the contact ratio, the stiffness of one tooth pair along the path of contact
and the mesh stiffness over a mesh cycle (:class:`MeshCycle`, with its harmonics and its periodic
profile); :class:`RingRim` is a ring gear's rim, a curved beam between its supports;
:func:`iso_stiffness` is ISO 6336-1 Method B for comparison, and :func:`iso_dynamic_factor` its
dynamic factor K_v.
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "DynamicFactor": "iso6336",
        "GearPair": "mesh",
        "IsoStiffness": "iso6336",
        "MeshCycle": "mesh",
        "RingRim": "ring",
        "SpurGear": "geometry",
        "TruncatedTooth": "tooth",
        "hertz_compliance": "tooth",
        "iso_dynamic_factor": "iso6336",
        "iso_stiffness": "iso6336",
        "pair_compliance": "tooth",
    },
)
