"""Mount stiffness from the drawing: pads, bolted joints and anchors, other mount types, materials,
an FE reference and calibration (SPEC §5).

Estimates: :class:`ElastomerPad` (shape factor and bulk compressibility, shear with bending),
:class:`BoltedJoint` (bolt by the equivalent length or VDI 2230, members by pressure cones, joint
stiffness and load factor), :class:`LevellingWedge`, :class:`ScrewFoot`, :class:`DampingPad`,
:class:`SpringIsolator`, and :func:`isolation` figures. Materials: :func:`default_materials`
(shipped with sources, extendable). Reference: :func:`pad_compression`, :func:`anchor_members`
(axisymmetric FE, scikit-fem). Calibration: :func:`fit_cone_angle`, :func:`fit_pad_factor`,
:func:`fit_frf`. A ``type = "mount"`` model file holds one mount (``mechdyn mount``).
"""

from mechdyn.mounts.bolted import BoltedJoint, Layer, frustum_stiffness, vdi2230_cone_angle
from mechdyn.mounts.calibration import (
    Calibration,
    SdofFit,
    apply,
    fit_cone_angle,
    fit_frf,
    fit_pad_factor,
    load_calibration,
    read_frf_csv,
)
from mechdyn.mounts.fe import AnchorFE, FEResult, anchor_members, pad_compression
from mechdyn.mounts.materials import Material, MaterialDatabase, default_materials, save_materials
from mechdyn.mounts.pad import ElastomerPad
from mechdyn.mounts.types import DampingPad, LevellingWedge, ScrewFoot, SpringIsolator, isolation

__all__ = [
    "AnchorFE",
    "BoltedJoint",
    "Calibration",
    "DampingPad",
    "ElastomerPad",
    "FEResult",
    "Layer",
    "LevellingWedge",
    "Material",
    "MaterialDatabase",
    "ScrewFoot",
    "SdofFit",
    "SpringIsolator",
    "anchor_members",
    "apply",
    "default_materials",
    "fit_cone_angle",
    "fit_frf",
    "fit_pad_factor",
    "frustum_stiffness",
    "isolation",
    "load_calibration",
    "pad_compression",
    "read_frf_csv",
    "save_materials",
    "vdi2230_cone_angle",
]
