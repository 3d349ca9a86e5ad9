"""Torsional vibration of geared drivetrains (SPEC §3).

Build a :class:`Drivetrain` from :class:`Disk`, :class:`Shaft`, :class:`GearMesh`,
:class:`GroundSpring` and :class:`GroundDamper` (or load a model file with :func:`mechdyn.load`), then
run :func:`modal`, :func:`campbell`, :func:`frf` or :func:`compare_rigid`. :func:`assemble` gives the
checked matrices; :func:`check_matrices` checks a hand-made pair; :func:`model_table` shows the model as
assembled and where each value came from.
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "Assembly": "assembly",
        "CampbellResult": "campbell",
        "Disk": "elements",
        "Drivetrain": "model",
        "FRFResult": "response",
        "GearMesh": "gear_mesh",
        "GroundDamper": "elements",
        "GroundSpring": "elements",
        "ModalDamping": "damping",
        "ModalResult": "modal",
        "ModeComparison": "compare",
        "RayleighDamping": "damping",
        "Shaft": "elements",
        "assemble": "assembly",
        "campbell": "campbell",
        "check_matrices": "mechdyn.vibration.checks",
        "compare_rigid": "compare",
        "frf": "response",
        "mac": "compare",
        "modal": "modal",
        "model_frame": "summary",
        "model_table": "summary",
    },
)
