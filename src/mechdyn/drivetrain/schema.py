"""The drivetrain model file: TOML tables → :class:`Drivetrain` and analysis settings.

A file has ``[model] type = "drivetrain"``, an optional ``[material]`` with defaults for elements
given by geometry, arrays of tables ``[[disks]]``, ``[[shafts]]``, ``[[meshes]]``, ``[[gear_pairs]]``,
``[[ground_springs]]``, ``[[ground_dampers]]``, and optional ``[campbell]`` and ``[response]``
tables for those analyses (:mod:`mechdyn.drivetrain.analysis_tables`). The gear-dynamics wing adds
each mesh's ``backlash``, ``transmission_error``, ``stiffness_variation`` and ``phase`` and the
``[motor]``, ``[[loads]]``, ``[simulation]`` and ``[speed_sweep]`` tables of ``mechdyn simulate`` and
``mechdyn speed-sweep`` (:mod:`mechdyn.gear_dynamics.file`, registered with
:func:`mechdyn.registry.extend_model_type`): :func:`build` validates the whole file with the schema
as extended. Every dimensional value carries its unit. See ``examples/``.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Annotated, Any, Literal

from pydantic import ConfigDict, Field, model_validator

from mechdyn.drivetrain.analysis_tables import (
    CampbellSettings,
    CampbellTable,
    DrivetrainSettings,
    ResponseSettings,
    ResponseTable,
    campbell_settings,
    response_settings,
)
from mechdyn.drivetrain.elements import (
    MAX_SHAFT_ELEMENTS,
    Disk,
    Element,
    GroundDamper,
    GroundSpring,
    Shaft,
)
from mechdyn.drivetrain.gear_mesh import GearMesh
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import ModelFileError, ModelWarning
from mechdyn.gears.schema import GearTable, pair_from_tables
from mechdyn.gears.schema import MaterialTable as GearMaterialTable
from mechdyn.io.fields import (
    Check,
    Density,
    Dimensionless,
    FileModel,
    Inertia,
    Length,
    LinearDamping,
    LinearStiffness,
    ModelTableBase,
    Pressure,
    TorsionalDamping,
    TorsionalStiffness,
)
from mechdyn.io.modelfile import ModelSource, field_context, schema_of, validate
from mechdyn.units import show

__all__ = [
    "CampbellSettings",
    "DrivetrainFile",
    "DrivetrainSettings",
    "MeshTable",
    "ResponseSettings",
    "build",
    "disk_check",
    "settings",
]


# a base-circle radius, positive as the mesh requires (checked with the file's other problems)
BaseRadius = Annotated[Length, Check("m", positive=True, what="base radius")]


class ModelTable(ModelTableBase):
    type: Literal["drivetrain"]
    """The file type, ``"drivetrain"``: it selects the schema and the analyses that read the file."""
    name: str = "drivetrain"
    """The model's name, shown in tables, plots, reports and the results database."""


class MaterialTable(FileModel):
    density: Annotated[Density, Check("kg/m^3", positive=True)] | None = None
    """Density of the disks given by their geometry (a disk's own ``density`` overrides it)."""
    shear_modulus: Annotated[Pressure, Check("Pa", positive=True)] | None = None
    """Shear modulus G of the shafts given by their geometry (a shaft's own overrides it)."""


class DiskTable(FileModel):
    name: str
    """The disk's name, unique in the file; shafts, meshes and outputs refer to it."""
    inertia: Annotated[Inertia, Check("kg*m^2", positive=True)] | None = None
    """Polar moment of inertia J about the shaft axis. Give it, or ``thickness`` and ``outer_diameter``."""
    thickness: Annotated[Length, Check("m", positive=True)] | None = None
    """Axial thickness h of a disk given by its geometry: J = ρ h π (D_o⁴ − D_i⁴)/32."""
    outer_diameter: Annotated[Length, Check("m", positive=True)] | None = None
    """Outer diameter D_o of a disk given by its geometry."""
    inner_diameter: Annotated[Length, Check("m", nonnegative=True)] = 0.0
    """Bore diameter D_i of a disk given by its geometry."""
    density: Annotated[Density, Check("kg/m^3", positive=True)] | None = None
    """Density ρ of this disk (default: ``[material] density``)."""

    @model_validator(mode="after")
    def _one_way(self) -> DiskTable:
        geometry = self.thickness is not None or self.outer_diameter is not None
        if self.inertia is not None and geometry:
            raise ValueError("give either inertia or geometry (thickness, outer_diameter), not both")
        if self.inertia is None and (self.thickness is None or self.outer_diameter is None):
            raise ValueError(
                "give inertia, or thickness and outer_diameter (with density here or in [material])"
            )
        return self


class ShaftTable(FileModel):
    name: str
    """The shaft's name, unique among the elements; used in tables, plots and messages."""
    disks: tuple[str, str]
    """The two disks the shaft connects, by name."""
    stiffness: Annotated[TorsionalStiffness, Check("N*m/rad", positive=True)] | None = None
    """Torsional stiffness k. Give it, or ``length`` and ``diameter`` (k = G π (d⁴ − d_i⁴)/(32 l))."""
    length: Annotated[Length, Check("m", positive=True)] | None = None
    """Length l of a shaft given by its geometry."""
    diameter: Annotated[Length, Check("m", positive=True)] | None = None
    """Outer diameter d of a shaft given by its geometry."""
    inner_diameter: Annotated[Length, Check("m", nonnegative=True)] = 0.0
    """Bore d_i of a hollow shaft given by its geometry."""
    shear_modulus: Annotated[Pressure, Check("Pa", positive=True)] | None = None
    """Shear modulus G of this shaft (default: ``[material] shear_modulus``)."""
    damping: Annotated[TorsionalDamping, Check("N*m*s/rad", nonnegative=True)] = 0.0
    """Viscous torsional damping between the two disks."""
    density: Annotated[Density, Check("kg/m^3", positive=True)] | None = None
    """Density ρ of a shaft given by its geometry: the shaft then carries its own inertia ρ J_p l (only this
    field does; ``[material] density`` is for the disks). Leave both out for a massless shaft."""
    inertia: Annotated[Inertia, Check("kg*m^2", nonnegative=True)] | None = None
    """The whole shaft's own polar mass moment of inertia ρ J_p l, given directly (instead of ``density``)."""
    mass_model: Literal["consistent", "lumped"] = "consistent"
    """How the shaft's inertia enters the mass matrix: ``consistent`` (J/6 [[2, 1], [1, 2]]) or ``lumped``
    (half on each end)."""
    elements: int = Field(default=1, ge=1, le=MAX_SHAFT_ELEMENTS)
    """Number of equal sub-elements the shaft is divided into (nodes ``name[1]``, … inside it); more
    converge to the continuous shaft. Needs ``density`` or ``inertia`` above 1."""

    @model_validator(mode="after")
    def _one_way(self) -> ShaftTable:
        geometry = self.length is not None or self.diameter is not None
        if self.stiffness is not None and geometry:
            raise ValueError("give either stiffness or geometry (length, diameter), not both")
        if self.stiffness is None and (self.length is None or self.diameter is None):
            raise ValueError(
                "give stiffness, or length and diameter (with shear_modulus here or in [material])"
            )
        if self.density is not None and self.inertia is not None:
            raise ValueError("give the shaft's density (with its geometry) or its inertia, not both")
        if self.density is not None and not geometry:
            raise ValueError(
                "density needs the shaft's geometry (length, diameter); give inertia for a shaft given by "
                "its stiffness"
            )
        if self.elements > 1 and self.density is None and self.inertia is None:
            raise ValueError(
                f"elements = {self.elements} divides the shaft, but it has no inertia; give density (with "
                "its geometry) or inertia, or elements = 1"
            )
        return self


class MeshTable(FileModel):
    name: str
    """The mesh's name, unique among the elements."""
    disks: tuple[str, str]
    """The two disks that carry the gears, by name; with ``gear_pair`` the first carries the pinion."""
    kind: Literal["external", "internal"] = "external"
    """``external`` (the gears turn in opposite senses) or ``internal`` (a ring gear: the same sense)."""
    teeth: tuple[int, int] | None = None
    """Tooth numbers [z_a, z_b]: they set the rigid ratio z_b/z_a and the Campbell diagram's mesh orders."""
    ratio: Dimensionless | None = None
    """Speed ratio n = |θ_a/θ_b| when the teeth are not known (instead of ``teeth``)."""
    base_radii: tuple[BaseRadius, BaseRadius] | None = None
    """Base-circle radii [r_a, r_b]; the flexible mesh acts along the line of action at these radii. A warning
    says when they disagree with the teeth or ratio by more than 0.5 %."""
    stiffness: Annotated[LinearStiffness, Check("N/m", positive=True)] | None = None
    """Mesh stiffness k_c along the line of action; leave it out for a rigid mesh (a constraint)."""
    damping: Annotated[LinearDamping, Check("N*s/m", nonnegative=True)] = 0.0
    """Viscous mesh damping along the line of action."""
    gear_pair: str | None = None
    """The name of a ``[[gear_pairs]]`` row: the mesh then takes its teeth, base radii and mean mesh stiffness
    (over a mesh cycle) from that gear data."""

    @model_validator(mode="after")
    def _one_source(self) -> MeshTable:
        given = [k for k in ("teeth", "ratio", "base_radii", "stiffness") if getattr(self, k) is not None]
        if self.gear_pair is not None and self.kind == "internal":
            raise ValueError(
                "a mesh with a gear_pair takes its kind from that pair; remove kind = 'internal' here "
                "and set kind = 'internal' in the [[gear_pairs]] row"
            )
        if self.gear_pair is not None and given:
            raise ValueError(
                f"gear_pair {self.gear_pair!r} sets teeth, base radii and stiffness; "
                f"remove {', '.join(given)}"
            )
        return self


class GearPairTable(FileModel):
    """A spur or helical pair, external or internal, whose mean mesh stiffness, teeth and base radii a
    mesh takes (``gear_pair = name``)."""

    name: str
    """The pair's name, which a mesh's ``gear_pair`` refers to."""
    pinion: GearTable
    """The pinion, by gear data (``teeth``, ``module``, ``face_width``, …; see the gear-pair file)."""
    gear: GearTable
    """The gear, by gear data."""
    center_distance: Length | None = None
    """Operating centre distance (default: the standard one for the profile shifts)."""
    tooth_model: Literal["truncated", "involute"] = "involute"
    """The tooth model of the mesh stiffness, as in a gear-pair file's ``[mesh]``."""
    kind: Literal["external", "internal"] = "external"
    """``internal``: the gear is a ring gear (internal teeth) meshing with the pinion inside it; the mesh
    then turns both the same way."""


class GroundSpringTable(FileModel):
    name: str
    """The spring's name, unique among the elements."""
    disk: str
    """The disk it ties to the frame (a motor, a brake, a clamp)."""
    stiffness: Annotated[TorsionalStiffness, Check("N*m/rad", positive=True)]
    """Torsional stiffness between the disk and the frame."""


class GroundDamperTable(FileModel):
    name: str
    """The damper's name, unique among the elements."""
    disk: str
    """The disk it ties to the frame."""
    damping: Annotated[TorsionalDamping, Check("N*m*s/rad", positive=True)]
    """Viscous torsional damping between the disk and the frame."""


class DrivetrainFile(FileModel):
    """Schema of a drivetrain model file."""

    model: ModelTable
    material: MaterialTable = MaterialTable()
    disks: list[DiskTable] = Field(min_length=1)
    shafts: list[ShaftTable] = Field(default_factory=list)
    meshes: list[MeshTable] = Field(default_factory=list)
    gear_pairs: list[GearPairTable] = Field(default_factory=list)
    gear_material: GearMaterialTable = GearMaterialTable()
    ground_springs: list[GroundSpringTable] = Field(default_factory=list)
    ground_dampers: list[GroundDamperTable] = Field(default_factory=list)
    campbell: CampbellTable | None = None
    response: ResponseTable | None = None


class _MeshPairRow(FileModel):
    """A ``[[meshes]]`` row's name and gear pair (the whole row was validated by :func:`build`)."""

    model_config = ConfigDict(extra="ignore", frozen=True)

    name: str
    gear_pair: str | None = None


class _AnalysisTables(FileModel):
    """The analysis tables of a drivetrain file alone (the rest was validated by :func:`build`)."""

    model_config = ConfigDict(extra="ignore", frozen=True)

    campbell: CampbellTable | None = None
    response: ResponseTable | None = None
    meshes: list[_MeshPairRow] = Field(default_factory=list)
    gear_pairs: list[GearPairTable] = Field(default_factory=list)
    gear_material: GearMaterialTable = GearMaterialTable()


def _where(table: str, i: int, name: str) -> str:
    return f"[[{table}]] #{i + 1} (name = {name!r})"


def _need(source: ModelSource, where: str, field: str, value: float | None, table: str) -> float:
    if value is None:
        raise ModelFileError(source.path, f"{where} → {field}", f"missing; give it here or in [{table}]")
    return value


def _check_names(source: ModelSource, f: DrivetrainFile) -> None:
    """Every name used once; every disk that an element refers to defined."""
    seen: dict[str, str] = {}
    for table in ("disks", "shafts", "meshes", "ground_springs", "ground_dampers", "gear_pairs"):
        for i, row in enumerate(getattr(f, table)):
            where = _where(table, i, row.name)
            if row.name in seen:
                raise ModelFileError(
                    source.path,
                    f"{where} → name",
                    f"{row.name!r} is used twice (also {seen[row.name]}); "
                    "give every disk and element its own name",
                    row.name,
                )
            seen[row.name] = where
    known = {d.name: None for d in f.disks}  # ordered, for the message; a dict for O(1) look-ups
    tables: tuple[tuple[str, Sequence[Any], str], ...] = (
        ("shafts", f.shafts, "disks"),
        ("meshes", f.meshes, "disks"),
        ("ground_springs", f.ground_springs, "disk"),
        ("ground_dampers", f.ground_dampers, "disk"),
    )
    for table, rows, field in tables:
        for i, row in enumerate(rows):
            value = getattr(row, field)
            for disk in (value,) if isinstance(value, str) else value:
                if disk not in known:
                    raise ModelFileError(
                        source.path,
                        f"{_where(table, i, row.name)} → {field}",
                        f"refers to disk {disk!r}, which is not defined; defined disks: {', '.join(known)}",
                        disk,
                    )


def build(source: ModelSource) -> Drivetrain:
    """Build the :class:`Drivetrain` described by a parsed model file, the whole file validated with
    the drivetrain type's schema as registered (with the tables other wings add)."""
    schema = schema_of("drivetrain")
    if not issubclass(schema, DrivetrainFile):  # an extension subclasses the drivetrain's schema
        raise TypeError(f"the drivetrain file type's schema {schema.__name__} is not a DrivetrainFile")
    f = validate(schema, source)
    _check_names(source, f)
    mat = f.material
    disks: list[Disk] = []
    said: dict[str, str] = {}  # where a value not given as a number came from
    # one context per table, not per row (it costs a warnings filter each): errors name their row
    rows = {d.name: _where("disks", i, d.name) for i, d in enumerate(f.disks)}
    with field_context(source, "[[disks]]", rows):
        for d in f.disks:
            where = rows[d.name]
            if d.inertia is not None:
                disks.append(Disk(d.name, d.inertia))
            else:
                rho = _need(
                    source, where, "density", d.density if d.density is not None else mat.density, "material"
                )
                disks.append(
                    Disk.from_geometry(
                        d.name,
                        thickness=d.thickness,
                        outer_diameter=d.outer_diameter,
                        inner_diameter=d.inner_diameter,
                        density=rho,
                    )
                )
                said[d.name] = (
                    f"from geometry: h = {_mm(d.thickness)}, D = {_mm(d.outer_diameter)}"
                    + (f", d = {_mm(d.inner_diameter)}" if d.inner_diameter else "")
                    + f", ρ = {rho:.5g} kg/m³"
                )
    elements: list[Element] = []
    rows = {s.name: _where("shafts", i, s.name) for i, s in enumerate(f.shafts)}
    with field_context(source, "[[shafts]]", rows):
        for s in f.shafts:
            where = rows[s.name]
            if s.stiffness is not None:
                elements.append(
                    Shaft(s.name, s.disks, s.stiffness, s.damping, s.inertia or 0.0, s.mass_model, s.elements)
                )
            else:
                shear = s.shear_modulus if s.shear_modulus is not None else mat.shear_modulus
                shear_modulus = _need(source, where, "shear_modulus", shear, "material")
                shaft = Shaft.from_geometry(
                    s.name,
                    s.disks,
                    length=s.length,
                    diameter=s.diameter,
                    inner_diameter=s.inner_diameter,
                    shear_modulus=shear_modulus,
                    damping=s.damping,
                    density=s.density,
                    mass_model=s.mass_model,
                    elements=s.elements if s.inertia is None else 1,
                )
                if s.inertia is not None:  # the schema allows density or inertia, not both
                    shaft = replace(shaft, inertia=s.inertia, elements=s.elements)
                elements.append(shaft)
                said[s.name] = (
                    f"from geometry: l = {_mm(s.length)}, d = {_mm(s.diameter)}"
                    + (f", dᵢ = {_mm(s.inner_diameter)}" if s.inner_diameter else "")
                    + f", G = {show(float(shear_modulus), 'Pa', 'GPa', '.4g')}"
                )
            if s.density is not None:
                said[f"{s.name} (inertia)"] = f"from geometry: ρ J_p l, ρ = {s.density:.5g} kg/m³"
    pairs = {}
    for i, gp in enumerate(f.gear_pairs):
        where = _where("gear_pairs", i, gp.name)
        pair = pair_from_tables(
            source, where, gp.pinion, gp.gear, f.gear_material, gp.center_distance, gp.tooth_model, gp.kind
        )
        pairs[gp.name] = pair
        with field_context(source, where):  # a mesh stiffness from guessed inputs says so
            for note in (*pair.pinion.guesses, *pair.gear.guesses):
                warnings.warn(note, ModelWarning, stacklevel=2)
    for i, m in enumerate(f.meshes):
        where = _where("meshes", i, m.name)
        if m.gear_pair is not None and m.gear_pair not in pairs:
            known = ", ".join(pairs) or "none"
            raise ModelFileError(
                source.path,
                f"{where} → gear_pair",
                f"{m.gear_pair!r} is not a [[gear_pairs]] name; defined: {known}",
                m.gear_pair,
            )
        with field_context(source, where):
            if m.gear_pair is not None:
                elements.append(
                    GearMesh.from_gear_pair(m.name, m.disks, pairs[m.gear_pair], damping=m.damping)
                )
                model = next(gp.tooth_model for gp in f.gear_pairs if gp.name == m.gear_pair)
                said[m.name] = f"gear pair {m.gear_pair!r}: mean over a mesh cycle, {model} teeth"
                continue
            elements.append(
                GearMesh(
                    m.name,
                    m.disks,
                    kind=m.kind,
                    teeth=m.teeth,
                    ratio=m.ratio,
                    base_radii=m.base_radii,
                    stiffness=m.stiffness,
                    damping=m.damping,
                )
            )
    for i, spring in enumerate(f.ground_springs):
        with field_context(source, _where("ground_springs", i, spring.name)):
            elements.append(GroundSpring(spring.name, spring.disk, spring.stiffness))
    for i, damper in enumerate(f.ground_dampers):
        with field_context(source, _where("ground_dampers", i, damper.name)):
            elements.append(GroundDamper(damper.name, damper.disk, damper.damping))
    tables = {
        row.name: _where(table, i, row.name)
        for table in ("disks", "shafts", "meshes", "ground_springs", "ground_dampers")
        for i, row in enumerate(getattr(f, table))
    }
    with field_context(source, "[model]", tables):
        return Drivetrain(tuple(disks), tuple(elements), name=f.model.name, provenance=said)


def _mm(length_m: Any) -> str:
    return show(float(length_m), "m", "mm", ".5g")


def disk_check(source: ModelSource, drivetrain: Drivetrain) -> Callable[[str, str | None], None]:
    """``check(where, disk)``: raises a :class:`~mechdyn.errors.ModelFileError` at ``where`` in the
    file when ``disk`` (a name, or None for none) is not a disk of ``drivetrain``."""
    known = drivetrain.disk_names

    def check(where: str, disk: str | None) -> None:
        if disk is not None and disk not in known:
            raise ModelFileError(
                source.path, where, f"{disk!r} is not a disk; defined disks: {', '.join(known)}", disk
            )

    return check


def settings(source: ModelSource, drivetrain: Drivetrain) -> DrivetrainSettings:
    """Read the ``[campbell]`` and ``[response]`` tables of a drivetrain file and each mesh's gear pair,
    checking disk and mesh names."""
    f = validate(_AnalysisTables, source)
    check = disk_check(source, drivetrain)
    camp = campbell_settings(f.campbell, check) if f.campbell is not None else None
    resp = response_settings(f.response, check) if f.response is not None else None
    return DrivetrainSettings(camp, resp, _mesh_gear_pairs(source, f))


def _mesh_gear_pairs(source: ModelSource, f: _AnalysisTables) -> dict[str, Any]:
    """The GearPair of each mesh given by a ``gear_pair``, by mesh name (each pair built once)."""
    built: dict[str, Any] = {}
    out: dict[str, Any] = {}
    for m in f.meshes:
        if m.gear_pair is None:
            continue
        if m.gear_pair not in built:
            j, gp = next((j, g) for j, g in enumerate(f.gear_pairs) if g.name == m.gear_pair)
            built[m.gear_pair] = pair_from_tables(
                source,
                _where("gear_pairs", j, gp.name),
                gp.pinion,
                gp.gear,
                f.gear_material,
                gp.center_distance,
                gp.tooth_model,
                gp.kind,
            )
        out[m.name] = built[m.gear_pair]
    return out
