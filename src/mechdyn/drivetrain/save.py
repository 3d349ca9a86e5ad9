"""A :class:`~mechdyn.drivetrain.Drivetrain` as a drivetrain model file (:func:`mechdyn.save`)."""

from __future__ import annotations

import cmath
from pathlib import Path
from typing import Any

from mechdyn.drivetrain.elements import GroundDamper, GroundSpring, Shaft
from mechdyn.drivetrain.gear_mesh import GearMesh
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
    """The drivetrain model file of ``model``: its disks and elements, and the ``[campbell]``,
    ``[response]``, ``[motor]``, ``[[loads]]``, ``[simulation]`` and ``[speed_sweep]`` tables and the
    meshes' backlash, transmission error and stiffness variation of ``settings``.

    Parameters
    ----------
    model : Drivetrain
        The drivetrain; inertias in kg·m² (disks, and shafts that carry their own, with their
        ``mass_model`` and ``elements``), stiffnesses in N·m/rad (shafts) and N/m (meshes), dampings
        in N·m·s/rad and N·s/m, base radii in m, written exactly.
    settings : DrivetrainSettings, optional
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
        For an element of a kind the file format has no table for, or a mesh whose stiffness varies as
        its gear pair's (the written file gives the mesh by its teeth and stiffness, without the gears).
    """
    campbell = getattr(settings, "campbell", None)
    response = getattr(settings, "response", None)
    dynamics = getattr(settings, "dynamics", None)
    mesh_rows = dynamics.meshes if dynamics is not None else {}
    for name, m in mesh_rows.items():
        if m.stiffness_variation == "gears":
            raise MechdynError(
                f"mechdyn.save: mesh {name!r} takes its stiffness over the mesh cycle from its gear pair, "
                "and a saved drivetrain gives its meshes by teeth and stiffness, without the gears; save "
                'the file as it is, or give the mesh stiffness_variation = "constant" or a '
                "{ fluctuation, contact_ratio } table first"
            )
    doc = TomlDocument()
    doc.comment(written_by("A drivetrain"))
    doc.table("model", model_header("drivetrain", model.name, source))
    for d in model.disks:
        note = model.provenance.get(d.name, "")
        doc.table("disks", {"name": d.name, "inertia": _q(d.inertia, "kg*m^2")}, array=True, note=note)
    for table, kind in _TABLES:
        for e in model.elements:
            if isinstance(e, kind):
                row = {**_row(e), **_mesh_dynamics(mesh_rows.get(e.name))}
                doc.table(table, row, array=True, note=model.provenance.get(e.name, ""))
    odd = [e for e in model.elements if not isinstance(e, tuple(k for _, k in _TABLES))]
    if odd:
        e = odd[0]
        raise MechdynError(
            f"mechdyn.save: element {e.name!r} is a {type(e).__name__}; a drivetrain file holds shafts, "
            "gear meshes, grounded springs and grounded dampers"
        )
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
    if dynamics is not None:
        _simulation_tables(doc, dynamics)
    sweep = getattr(settings, "speed_sweep", None)
    if sweep is not None:
        doc.table("speed_sweep", _fields(sweep))
    return doc.text()


def _mesh_dynamics(m: Any) -> dict[str, Any]:
    if m is None:
        return {}
    variation = m.stiffness_variation
    return {
        "backlash": _q(m.backlash, "m") if m.backlash is not None else None,
        "transmission_error": _q(m.transmission_error, "m") if m.transmission_error else None,
        "stiffness_variation": (
            {"fluctuation": float(variation[0]), "contact_ratio": float(variation[1])}
            if isinstance(variation, tuple)
            else None
        ),
        "phase": float(m.phase) if m.phase else None,
    }


# the unit of each field of [motor], [[loads]] and [simulation] as written (fields not named: as read)
_UNITS = {
    "power": "W",
    "synchronous_speed": "rad/s",
    "rated_speed": "rad/s",
    "rotor_inertia": "kg*m^2",
    "torque": "N*m",
    "initial_torque": "N*m",
    "time": "s",
    "start": "s",
    "end": "s",
    "amplitude": "N*m",
    "frequency": "Hz",
    "phase": "rad",
    "brake": "N*m",
    "hold_speed": "rad/s",
    "duration": "s",
    "initial_speed": "rad/s",
    "output_step": "s",
    "speed_range": "rad/s",
}


def _fields(table: Any) -> dict[str, Any]:
    """A table's fields that differ from their defaults, quantities with their units (a load's start is
    a time; the simulation's start is a word)."""
    out: dict[str, Any] = {}
    for name, info in type(table).model_fields.items():
        value = getattr(table, name)
        if value is None or value == info.default:
            continue
        if isinstance(value, float) and name in _UNITS:
            out[name] = _q(value, _UNITS[name])
        elif name == "speed_range":
            out[name] = [_q(v, _UNITS[name]) for v in value]
        elif isinstance(value, tuple | list):
            out[name] = [list(v) if isinstance(v, tuple) else v for v in value]
        else:
            out[name] = value
    return out


def _simulation_tables(doc: TomlDocument, d: Any) -> None:
    if d.motor is not None:
        motor = _fields(d.motor)
        doc.table("motor", {"disk": motor.pop("disk"), "type": d.motor.type, **motor})
    for load in d.loads:
        row = _fields(load)
        doc.table("loads", {"kind": row.pop("kind"), **row}, array=True)
    if d.simulation is not None:
        doc.table("simulation", _fields(d.simulation))


def _response(doc: TomlDocument, r: Any) -> None:
    from mechdyn.drivetrain.damping import ModalDamping, RayleighDamping

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
