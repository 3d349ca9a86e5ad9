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

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "AnchorFE": "fe",
        "BoltedJoint": "bolted",
        "Calibration": "calibration",
        "DampingPad": "types",
        "ElastomerPad": "pad",
        "FEResult": "fe",
        "Layer": "bolted",
        "LevellingWedge": "types",
        "MountEstimate": "types",
        "Material": "materials",
        "MaterialDatabase": "materials",
        "ScrewFoot": "types",
        "SdofFit": "calibration",
        "SpringIsolator": "types",
        "anchor_members": "fe",
        "apply": "calibration",
        "default_materials": "materials",
        "fit_cone_angle": "calibration",
        "fit_frf": "calibration",
        "fit_pad_factor": "calibration",
        "frustum_stiffness": "bolted",
        "isolation": "types",
        "load_calibration": "calibration",
        "pad_compression": "fe",
        "read_frf_csv": "calibration",
        "save_materials": "materials",
        "vdi2230_cone_angle": "bolted",
    },
)
