"""Gear model files: ``type = "gear_pair"`` (ordinary gear data) and ``type = "tooth_pair"``
(raw truncated-triangle tooth data, as published), and the gear tables a drivetrain file reuses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from pydantic import Field

from mechdyn.gears.geometry import SpurGear
from mechdyn.gears.mesh import GearPair
from mechdyn.gears.tooth import TruncatedTooth
from mechdyn.io.fields import (
    Angle,
    FileModel,
    Length,
    LineLoad,
    ModelTableBase,
    Pressure,
)
from mechdyn.io.fields import LinearStiffness as Stiffness
from mechdyn.io.modelfile import ModelSource, field_context, validate

__all__ = [
    "GearPairModel",
    "GearTable",
    "MaterialTable",
    "ToothPairModel",
    "build_gear_pair",
    "build_tooth_pair",
]


class MaterialTable(FileModel):
    youngs_modulus: Pressure = 206e9
    """Young's modulus E of the gears (a gear's own value overrides it)."""
    poisson_ratio: float = Field(default=0.3, gt=-1.0, lt=0.5)
    """Poisson's ratio ν of the gears, for the Hertz term and the shear modulus."""


class GearTable(FileModel):
    """One spur or helical gear from ordinary gear data."""

    teeth: int = Field(ge=5)
    """Number of teeth z."""
    module: Length
    """Module m (the pitch diameter is m z); the normal module m_n of a helical gear (pitch diameter
    m_n z / cos β)."""
    face_width: Length
    """Face width b."""
    pressure_angle: Angle = math.radians(20.0)
    """Standard pressure angle α of the basic rack (the normal pressure angle α_n of a helical gear)."""
    helix_angle: Angle = 0.0
    """Helix angle β at the reference circle (0: spur gear); both gears of a pair take the same β."""
    profile_shift: float = 0.0
    """Profile-shift coefficient x (in modules)."""
    addendum: float = 1.0
    """Addendum coefficient h_a* (in modules): tip radius = m (z/2 + h_a* + x)."""
    dedendum: float = 1.25
    """Dedendum coefficient h_f* (in modules): root radius = m (z/2 − h_f* + x)."""
    fillet_radius: float = 0.38
    """Tip rounding ρ_fP* of the basic rack (in modules; ISO 53 profile A), which cuts the root fillet."""
    bore_diameter: Length | None = None
    """Diameter of the gear's bore, for the foundation of the teeth. Without it the gear is taken as solid to
    half its root diameter, and the result says so."""
    rim_thickness: Length | None = Field(
        default=None,
        description="s_R of a rim-and-web blank (ISO's C_R, with web_width); of an internal gear, the "
        "rim's radial thickness outside the root circle, which with rim_supports makes its rim a curved "
        "beam between them (without it the ring's rim is rigid, and the result says so)",
    )
    web_width: Length | None = Field(default=None, description="b_s of a rim-and-web blank")
    rim_supports: int | None = Field(default=None, ge=1)
    """Number of evenly spaced supports (bolts, pins, spline teeth) holding an internal gear's rim, given
    with its rim_thickness: the rim between two of them is a curved beam clamped at both."""
    youngs_modulus: Pressure | None = None
    """Young's modulus of this gear (default: ``[material]``)."""
    poisson_ratio: float | None = Field(default=None, gt=-1.0, lt=0.5)
    """Poisson's ratio of this gear (default: ``[material]``)."""

    def build(self, name: str, material: MaterialTable, internal: bool = False) -> SpurGear:
        """The gear, named ``name``, with the material's defaults; ``internal`` for a ring gear."""
        return SpurGear(
            teeth=self.teeth,
            module=self.module,
            face_width=self.face_width,
            pressure_angle=self.pressure_angle,
            profile_shift=self.profile_shift,
            addendum=self.addendum,
            dedendum=self.dedendum,
            youngs_modulus=self.youngs_modulus
            if self.youngs_modulus is not None
            else material.youngs_modulus,
            poisson_ratio=self.poisson_ratio if self.poisson_ratio is not None else material.poisson_ratio,
            bore_diameter=self.bore_diameter,
            name=name,
            rim_thickness=self.rim_thickness,
            web_width=self.web_width,
            fillet_radius=self.fillet_radius,
            helix_angle=self.helix_angle,
            internal=internal,
            rim_supports=self.rim_supports,
        )


class MeshSettings(FileModel):
    center_distance: Length | None = None
    """Operating centre distance (default: from the profile shifts)."""
    tooth_model: Literal["truncated", "involute"] = "involute"
    """``involute`` (the tooth as the rack generates it, root fillet and involute, potential energy integrated
    over its thickness) or ``truncated`` (truncated-triangle tooth, closed form)."""
    kind: Literal["external", "internal"] = "external"
    """``external`` (two external gears) or ``internal`` (the pinion inside the ``[gear]``, a ring gear with
    more teeth; its teeth point inward, it has no bore)."""
    points: int = Field(default=400, ge=4, le=100_000)
    """Positions over one mesh cycle at which the mesh stiffness is computed."""
    specific_load: LineLoad = 100.0  # N/mm, for the ISO load correction
    """Line load F_t/b for ISO 6336-1's load correction of c′ and c_γα."""


class PairModelTable(ModelTableBase):
    type: Literal["gear_pair"]
    """The file type, ``"gear_pair"``: it selects the schema and the analyses that read the file."""
    name: str = "gear pair"
    """The model's name, shown in tables, plots, reports and the results database."""


class GearPairModel(FileModel):
    """Schema of a ``gear_pair`` file."""

    model: PairModelTable
    material: MaterialTable = MaterialTable()
    pinion: GearTable
    gear: GearTable
    mesh: MeshSettings = MeshSettings()


@dataclass(frozen=True)
class GearPairSpec:
    """A gear pair as read from a file, with the mesh settings and its title."""

    name: str
    pair: GearPair
    points: int
    specific_load: float


def pair_from_tables(
    source: ModelSource,
    where: str,
    pinion: GearTable,
    gear: GearTable,
    material: MaterialTable,
    center_distance: float | None,
    tooth_model: Literal["truncated", "involute"] = "involute",
    kind: Literal["external", "internal"] = "external",
) -> GearPair:
    """Build a :class:`GearPair` from gear tables, errors located at ``where``; ``kind = "internal"``
    makes the gear a ring gear."""
    with field_context(source, f"{where} → pinion"):
        p = pinion.build("pinion", material)
    with field_context(source, f"{where} → gear"):
        g = gear.build("gear", material, internal=kind == "internal")
    with field_context(source, where):
        return GearPair(p, g, center_distance, tooth_model)


def build_gear_pair(source: ModelSource) -> GearPairSpec:
    """Builder for ``[model] type = "gear_pair"``."""
    f = validate(GearPairModel, source)
    pair = pair_from_tables(
        source,
        "[mesh]",
        f.pinion,
        f.gear,
        f.material,
        f.mesh.center_distance,
        f.mesh.tooth_model,
        f.mesh.kind,
    )
    return GearPairSpec(f.model.name, pair, f.mesh.points, f.mesh.specific_load)


# -- raw tooth data ------------------------------------------------------------------------------


class ToothTable(FileModel):
    tip_height: Length
    """Height h_a of the tooth's tip, from the same datum as the other heights."""
    root_height: Length
    """Height h_b of the root section, where the taper starts."""
    load_height: Length
    """Height h_c at which the normal force acts."""
    tip_thickness: Length
    """Tooth thickness t_a at the tip."""
    root_thickness: Length
    """Tooth thickness t_b at the root section."""
    root_radius: Length | None = None
    """Radius of the root section, for the foundation term of Sainsot et al. (2004) with ``bore_radius``."""
    bore_radius: Length | None = None
    """Radius of the gear's bore, for the foundation term (with ``root_radius``)."""


class LoadTable(FileModel):
    load_angle: Angle
    """Angle φ between the normal force and the perpendicular to the tooth's centre line."""
    face_width: Length
    """Face width f of the teeth."""
    formulas: Literal["published", "refined"] = "published"
    """``published``: the published tooth model term by term (bending and shear of the whole tooth
    from the root, the published foundation term); ``refined``: bending and shear from the root
    section up, axial compression, and the foundation of Sainsot et al. (2004) when root and bore
    radii are given."""


class PublishedTable(FileModel):
    mesh_stiffness: Stiffness | None = None
    """The stiffness the publication prints for this pair, to compare with."""
    note: str = ""
    """Where the printed value comes from."""


class ToothModelTable(ModelTableBase):
    type: Literal["tooth_pair"]
    """The file type, ``"tooth_pair"``: it selects the schema and the analyses that read the file."""
    name: str = "tooth pair"
    """The model's name, shown in tables, plots, reports and the results database."""


class ToothPairModel(FileModel):
    """Schema of a ``tooth_pair`` file: two truncated-triangle teeth loaded at one point."""

    model: ToothModelTable
    material: MaterialTable = MaterialTable()
    load: LoadTable
    pinion: ToothTable
    gear: ToothTable
    published: PublishedTable = PublishedTable()


@dataclass(frozen=True)
class ToothPairSpec:
    """Two teeth with their load points, and the published stiffness to compare with."""

    name: str
    teeth: tuple[TruncatedTooth, TruncatedTooth]
    load_heights: tuple[float, float]
    load_angle: float
    published_stiffness: float | None
    published_note: str
    formulas: str = "published"


def build_tooth_pair(source: ModelSource) -> ToothPairSpec:
    """Builder for ``[model] type = "tooth_pair"``."""
    f = validate(ToothPairModel, source)
    teeth = []
    for label, t in (("pinion", f.pinion), ("gear", f.gear)):
        with field_context(source, f"[{label}]"):
            tooth = TruncatedTooth(
                tip_height=t.tip_height,
                root_height=t.root_height,
                tip_thickness=t.tip_thickness,
                root_thickness=t.root_thickness,
                face_width=f.load.face_width,
                youngs_modulus=f.material.youngs_modulus,
                poisson_ratio=f.material.poisson_ratio,
                root_radius=t.root_radius,
                bore_radius=t.bore_radius,
                name=label,
            )
            tooth.compliances(t.load_height, f.load.load_angle)  # checks the load point now
        teeth.append(tooth)
    return ToothPairSpec(
        f.model.name,
        (teeth[0], teeth[1]),
        (f.pinion.load_height, f.gear.load_height),
        f.load.load_angle,
        f.published.mesh_stiffness,
        f.published.note,
        f.load.formulas,
    )
