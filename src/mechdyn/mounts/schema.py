"""The mount model file: ``[model] type = "mount"``.

One mount per file, described by one of ``[pad]`` (bonded elastomer pad), ``[bolted]`` (a bolt or an
anchor clamping ``[[bolted.layers]]``), ``[wedge]`` (levelling wedge mount), ``[screw_foot]``,
``[damping_pad]`` or ``[spring]``. Materials are named from the shipped database
(:func:`~mechdyn.mounts.materials.default_materials`) or from ``[materials] files``. Optional:
``[fe]`` (the finite-element reference: mesh refinements, preloads and a pressure threshold for an
anchor), ``[load]`` (the isolation figures on a given load), ``[calibration]`` (fit the free
parameter to the FE result, to a measured stiffness, or fit stiffness and damping to a measured
FRF; ``use_stored`` applies the latest stored calibration). See ``examples/pad_shore60.toml`` and
``examples/anchor_concrete.toml``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, model_validator

from mechdyn.io.fields import Angle, FileModel, Frequency, Length, LinearStiffness, ModelTableBase, quantity
from mechdyn.io.modelfile import ModelSource, field_context, validate
from mechdyn.mounts.bolted import BoltedJoint, Layer
from mechdyn.mounts.materials import Material, MaterialDatabase, default_materials
from mechdyn.mounts.pad import ElastomerPad
from mechdyn.mounts.types import DampingPad, LevellingWedge, ScrewFoot, SpringIsolator

__all__ = ["MountFile", "MountSpec", "build"]

Area = quantity("m^2")
Force = quantity("N")
Pressure = quantity("Pa")


class ModelTable(ModelTableBase):
    type: Literal["mount"]
    name: str = "mount"


class MaterialsTable(FileModel):
    files: list[str] = Field(default_factory=list)


class PadTable(FileModel):
    material: str | None = None
    shore_a: float | None = None
    thickness: Length
    length: Length | None = None
    width: Length | None = None
    diameter: Length | None = None
    compression_coefficient: float | None = None

    @model_validator(mode="after")
    def _material(self) -> PadTable:
        if (self.material is None) == (self.shore_a is None):
            raise ValueError("give the rubber by material (a name) or by shore_a, one of the two")
        return self


class LayerTable(FileModel):
    thickness: Length
    material: str


class BoltedTable(FileModel):
    diameter: Length
    layers: list[LayerTable] = Field(min_length=1)
    bolt_material: str = "bolt steel"
    head_diameter: Length
    lower_bearing_diameter: Length | None = None
    hole_diameter: Length | None = None
    stress_area: Area | None = None
    nut: Literal["nut", "tapped", "anchor"] = "nut"
    cone_angle: Angle | Literal["vdi2230"] = 0.5235987755982988
    outer_diameter: Length | None = Field(
        default=None, description="D_A of the clamped parts (a cone that reaches it goes on as a sleeve)"
    )
    pitch: Length | None = Field(default=None, description="thread pitch; by default the ISO 261 coarse one")


class WedgeTable(FileModel):
    bearing_area: Area
    height: Length
    material: str = "steel"
    catalogue_stiffness: LinearStiffness | None = None


class ScrewFootTable(FileModel):
    diameter: Length
    free_length: Length
    material: str = "steel"
    base_stiffness: LinearStiffness | None = None
    pitch: Length | None = Field(default=None, description="spindle thread pitch; by default ISO 261 coarse")


class DampingPadTable(PadTable):
    loss_factor: float = Field(default=0.1, ge=0, lt=2)


class SpringTable(FileModel):
    wire_diameter: Length
    coil_diameter: Length
    active_coils: float = Field(gt=0)
    springs: int = Field(default=1, ge=1)
    material: str = "steel"


class FETable(FileModel):
    refinements: list[int] = Field(
        default=[4, 8, 16],
        min_length=1,
        description="the first meshes (elements through the thickness); refined by 2 from the last until "
        "converged",
    )
    tolerance: float = Field(
        default=0.005, gt=0, lt=1, description="largest relative discretisation error of the reference"
    )
    max_refinement: int = Field(default=64, ge=1, le=1024, description="finest mesh it may refine to")
    preloads: list[Force] = Field(default_factory=list)
    pressure_threshold: Pressure | None = None
    plate_radius: Length | None = None
    concrete_radius: Length | None = None


def _weight(value: Any) -> float:
    """A weight in newtons, or a mass taken under standard gravity."""
    from mechdyn.io.fields import within_limits
    from mechdyn.units import STANDARD_GRAVITY, UnitError, to_si

    try:
        newtons = to_si(value, "N")
    except UnitError:
        newtons = to_si(value, "kg") * STANDARD_GRAVITY
    return within_limits(value, newtons, "N")


class LoadTable(FileModel):
    weight: Annotated[float, BeforeValidator(_weight)]
    disturbing_frequency: Frequency
    loss_factor: float | None = None


class CalibrationTable(FileModel):
    reference: Literal["fe", "measured", "frf"] | None = None
    measured_stiffness: LinearStiffness | None = None
    frf_csv: str | None = None
    provenance: str = ""
    use_stored: bool = False

    @model_validator(mode="after")
    def _consistent(self) -> CalibrationTable:
        if self.reference == "measured" and self.measured_stiffness is None:
            raise ValueError('reference = "measured" needs measured_stiffness')
        if self.reference == "frf" and self.frf_csv is None:
            raise ValueError('reference = "frf" needs frf_csv (a CSV file of the measured FRF)')
        return self


class MountFile(FileModel):
    """Schema of a mount model file."""

    model: ModelTable
    materials: MaterialsTable = MaterialsTable()
    pad: PadTable | None = None
    bolted: BoltedTable | None = None
    wedge: WedgeTable | None = None
    screw_foot: ScrewFootTable | None = None
    damping_pad: DampingPadTable | None = None
    spring: SpringTable | None = None
    fe: FETable | None = None
    load: LoadTable | None = None
    calibration: CalibrationTable = CalibrationTable()

    @model_validator(mode="after")
    def _one_mount(self) -> MountFile:
        kinds = [k for k in MOUNT_TABLES if getattr(self, k) is not None]
        if len(kinds) != 1:
            raise ValueError(
                f"describe exactly one mount, with one of {', '.join(f'[{k}]' for k in MOUNT_TABLES)}; "
                f"got {kinds or 'none'}"
            )
        return self


MOUNT_TABLES = ("pad", "bolted", "wedge", "screw_foot", "damping_pad", "spring")


@dataclass(frozen=True)
class MountSpec:
    """A mount as read from a file: the estimate object and what else the file asks for."""

    name: str
    kind: str
    mount: Any
    materials: MaterialDatabase
    fe: FETable | None
    load: LoadTable | None
    calibration: CalibrationTable
    directory: str


def _material(db: MaterialDatabase, name: str) -> Material:
    return db[name]


def _pad(name: str, t: PadTable, db: MaterialDatabase) -> ElastomerPad:
    mat = db.rubber(t.shore_a) if t.shore_a is not None else _material(db, t.material or "")
    return ElastomerPad(name, mat, t.thickness, t.length, t.width, t.diameter, t.compression_coefficient)


def build(source: ModelSource) -> MountSpec:
    """Builder for ``[model] type = "mount"``."""
    f = validate(MountFile, source)
    here = Path(source.path).parent
    db = default_materials()
    with field_context(source, "[materials] → files"):
        for name in f.materials.files:
            p = here / name
            if not p.is_file():
                raise ValueError(f"{name!r}: no such file next to this model ({p})")
            db = db.with_file(p)
    name = f.model.name
    kind = next(k for k in MOUNT_TABLES if getattr(f, k) is not None)
    with field_context(source, f"[{kind}]"):
        if kind == "pad":
            mount: Any = _pad(name, f.pad, db)  # type: ignore[arg-type]
        elif kind == "bolted":
            b = f.bolted
            assert b is not None
            layers = []
            for i, layer in enumerate(b.layers):
                with field_context(source, f"[[bolted.layers]] #{i + 1}"):
                    layers.append(Layer(layer.thickness, _material(db, layer.material)))
            mount = BoltedJoint(
                name,
                b.diameter,
                layers,
                _material(db, b.bolt_material),
                b.head_diameter,
                b.lower_bearing_diameter,
                b.hole_diameter,
                b.stress_area,
                b.nut,
                b.cone_angle,
                b.outer_diameter,
                b.pitch,
            )
        elif kind == "wedge":
            w = f.wedge
            assert w is not None
            mount = LevellingWedge(
                name, w.bearing_area, w.height, _material(db, w.material), w.catalogue_stiffness
            )
        elif kind == "screw_foot":
            s = f.screw_foot
            assert s is not None
            mount = ScrewFoot(
                name, s.diameter, s.free_length, _material(db, s.material), s.base_stiffness, pitch=s.pitch
            )
        elif kind == "damping_pad":
            dp = f.damping_pad
            assert dp is not None
            mount = DampingPad(name, _pad(name, dp, db), dp.loss_factor)
        else:
            sp = f.spring
            assert sp is not None
            mount = SpringIsolator(
                name,
                sp.wire_diameter,
                sp.coil_diameter,
                sp.active_coils,
                _material(db, sp.material),
                sp.springs,
            )
    if f.fe is not None and kind not in ("pad", "bolted", "damping_pad"):
        raise_at = "[fe]"
        from mechdyn.errors import ModelFileError

        raise ModelFileError(
            source.path, raise_at, f"the FE reference models pads and bolted joints, not a {kind}"
        )
    if f.calibration.reference in ("fe", "measured") and kind not in ("pad", "bolted"):
        from mechdyn.errors import ModelFileError

        raise ModelFileError(
            source.path,
            "[calibration] → reference",
            f'a {kind} has no free parameter to calibrate; use reference = "frf" for stiffness and damping',
        )
    return MountSpec(name, kind, mount, db, f.fe, f.load, f.calibration, str(here))
