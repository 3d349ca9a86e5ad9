"""A :class:`~mechdyn.gears.GearPair` as a gear-pair model file (:func:`mechdyn.save`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from mechdyn.gears.geometry import SpurGear
from mechdyn.gears.mesh import GearPair
from mechdyn.io.save import model_header, written_by
from mechdyn.io.writing import TomlDocument, quantity_text

__all__ = ["to_toml"]


def _gear(g: SpurGear) -> dict[str, Any]:
    def length(value: float | None) -> Any:
        return None if value is None else quantity_text(value, "m")

    helix = {"helix_angle": quantity_text(g.helix_angle, "rad")} if g.helix_angle else {}
    return helix | {
        "teeth": int(g.teeth),
        "module": length(g.module),
        "face_width": length(g.face_width),
        "pressure_angle": quantity_text(g.pressure_angle, "rad"),
        "profile_shift": float(g.profile_shift),
        "addendum": float(g.addendum),
        "dedendum": float(g.dedendum),
        "fillet_radius": float(g.fillet_radius),
        "bore_diameter": length(g.bore_diameter),
        "rim_thickness": length(g.rim_thickness),
        "web_width": length(g.web_width),
        "rim_supports": g.rim_supports,
        "youngs_modulus": quantity_text(g.youngs_modulus, "Pa"),
        "poisson_ratio": float(g.poisson_ratio),
    }


def to_toml(model: GearPair, settings: Any = None, *, path: Path, source: Any = None) -> str:
    """The gear-pair model file of ``model``: both gears by their data (the helix angle when not 0),
    the centre distance, the tooth model, ``kind = "internal"`` for an internal pair, and the
    ``[mesh]`` settings of a loaded file.

    The gears of a gear-pair file are named ``pinion`` and ``gear``: a pair whose gears have these
    names comes back equal.

    Parameters
    ----------
    model : GearPair
        The pair; lengths in m, the pressure angle in rad, Young's modulus in Pa, written exactly.
    settings : GearPairSpec, optional
        The loaded file's record: its name, the mesh-cycle points and the specific load (N/mm).
    path : Path
        The file to be written.
    source : ModelSource, optional
        The file the model was loaded from (its description and source are kept).

    Returns
    -------
    str
        The TOML text.
    """
    doc = TomlDocument()
    doc.comment(written_by("A gear pair"))
    name = getattr(settings, "name", None) or "gear pair"
    doc.table("model", model_header("gear_pair", name, source))
    doc.table("pinion", _gear(model.pinion))
    doc.table("gear", _gear(model.gear))
    mesh: dict[str, Any] = {
        "center_distance": quantity_text(model.center_distance, "m") if model.center_distance else None,
        "tooth_model": model.tooth_model,
    }
    if model.internal:
        mesh["kind"] = "internal"
    if settings is not None:
        mesh["points"] = int(settings.points)
        mesh["specific_load"] = quantity_text(settings.specific_load, "N/mm")
    doc.table("mesh", mesh)
    return doc.text()
