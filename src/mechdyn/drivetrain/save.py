"""A :class:`~mechdyn.drivetrain.Drivetrain` as a drivetrain model file (:func:`mechdyn.save`)."""

from __future__ import annotations

import cmath
from pathlib import Path
from typing import Any

from mechdyn.drivetrain.elements import GearMesh, GroundDamper, GroundSpring, Shaft
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import MechdynError
from mechdyn.io.save import model_header, written_by
from mechdyn.io.writing import TomlDocument, quantity_text

__all__ = ["to_toml"]

# the tables of a drivetrain file, in the order its builder reads them
_TABLES = (
    ("shafts", Shaft),
    ("meshes", GearMesh),
    ("ground_springs", GroundSpring),
    ("ground_dampers", GroundDamper),
)


def _q(value: float, unit: str) -> Any:
    return quantity_text(value, unit)


def _row(e: Any) -> dict[str, Any]:
    if isinstance(e, Shaft):
        return {
            "name": e.name,
            "disks": list(e.disks),
            "stiffness": _q(e.stiffness, "N*m/rad"),
            "damping": _q(e.damping, "N*m*s/rad") if e.damping else None,
            # a shaft's own inertia as assembled (ρ J_p l where it came from its density)
            "inertia": _q(e.inertia, "kg*m^2") if e.inertia else None,
            "mass_model": e.mass_model if e.inertia else None,
            "elements": e.elements if e.elements > 1 else None,
        }
    if isinstance(e, GearMesh):
        return {
            "name": e.name,
            "disks": list(e.disks),
            "kind": e.kind,
            "teeth": list(e.teeth) if e.teeth is not None else None,
            "ratio": float(e.ratio) if e.ratio is not None else None,
            "base_radii": [_q(r, "m") for r in e.base_radii] if e.base_radii is not None else None,
            "stiffness": _q(e.stiffness, "N/m") if e.stiffness is not None else None,
            "damping": _q(e.damping, "N*s/m") if e.damping else None,
        }
    if isinstance(e, GroundSpring):
        return {"name": e.name, "disk": e.disk, "stiffness": _q(e.stiffness, "N*m/rad")}
    return {"name": e.name, "disk": e.disk, "damping": _q(e.damping, "N*m*s/rad")}


def to_toml(model: Drivetrain, settings: Any = None, *, path: Path, source: Any = None) -> str:
    """The drivetrain model file of ``model``: its disks and elements, and the ``[campbell]`` and
    ``[response]`` tables of ``settings``.

    Parameters
    ----------
    model : Drivetrain
        The drivetrain; inertias in kg·m² (disks, and shafts that carry their own, with their
        ``mass_model`` and ``elements``), stiffnesses in N·m/rad (shafts) and N/m (meshes), dampings
        in N·m·s/rad and N·s/m, base radii in m, written exactly.
    settings : tuple of (CampbellSettings or None, ResponseSettings or None), optional
        The analysis tables of a loaded file (:attr:`mechdyn.io.LoadedModel.settings`).
    path : Path
        The file to be written.
    source : ModelSource, optional
        The file the model was loaded from (its description and source are kept).

    Returns
    -------
    str
        The TOML text.

    Raises
    ------
    MechdynError
        For an element of a kind the file format has no table for.
    """
    doc = TomlDocument()
    doc.comment(written_by("A drivetrain"))
    doc.table("model", model_header("drivetrain", model.name, source))
    for d in model.disks:
        note = model.provenance.get(d.name, "")
        doc.table("disks", {"name": d.name, "inertia": _q(d.inertia, "kg*m^2")}, array=True, note=note)
    for table, kind in _TABLES:
        for e in model.elements:
            if isinstance(e, kind):
                doc.table(table, _row(e), array=True, note=model.provenance.get(e.name, ""))
    odd = [e for e in model.elements if not isinstance(e, tuple(k for _, k in _TABLES))]
    if odd:
        e = odd[0]
        raise MechdynError(
            f"mechdyn.save: element {e.name!r} is a {type(e).__name__}; a drivetrain file holds shafts, "
            "gear meshes, grounded springs and grounded dampers"
        )
    campbell, response = settings if isinstance(settings, tuple) else (None, None)
    if campbell is not None:
        doc.table(
            "campbell",
            {
                "speed_range": [_q(w, "rad/s") for w in campbell.speed_range],
                "reference_disk": campbell.reference_disk,
                "shaft_orders": [float(o) for o in campbell.shaft_orders],
                "mesh_orders": [float(o) for o in campbell.mesh_orders],
            },
        )
    if response is not None:
        _response(doc, response)
    return doc.text()


def _response(doc: TomlDocument, r: Any) -> None:
    from mechdyn.drivetrain.response import ModalDamping, RayleighDamping

    modal = None
    if isinstance(r.damping, ModalDamping):
        if not isinstance(r.damping.ratio, float | int):
            raise MechdynError(
                "mechdyn.save: a drivetrain file gives one modal damping ratio for every mode "
                f"(modal_damping); this response has one per mode, {r.damping.ratio!r}"
            )
        modal = float(r.damping.ratio)
    doc.table(
        "response",
        {
            "frequency_range": [_q(f, "Hz") for f in r.frequency_range],
            "points": int(r.points),
            "outputs": list(r.outputs),
            "modal_damping": modal,
        },
    )
    for disk, torque in r.excitation.items():
        amplitude, phase = cmath.polar(complex(torque))
        row = {"disk": disk, "amplitude": _q(amplitude, "N*m"), "phase": _q(phase, "rad") if phase else None}
        doc.table("response.excitation", row, array=True)
    if isinstance(r.damping, RayleighDamping):
        doc.table("response.rayleigh", {"alpha": _q(r.damping.alpha, "1/s"), "beta": _q(r.damping.beta, "s")})
