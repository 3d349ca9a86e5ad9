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

from mechdyn.errors import ModelError
from mechdyn.io.fields import (
    Angle,
    Area,
    Check,
    FileModel,
    Force,
    Frequency,
    Length,
    LinearStiffness,
    ModelTableBase,
    Pressure,
)
from mechdyn.io.modelfile import ModelSource, field_context, validate
from mechdyn.mounts.bolted import BoltedJoint, Layer
from mechdyn.mounts.fe import MAX_REFINEMENT
from mechdyn.mounts.materials import Material, MaterialDatabase, default_materials
from mechdyn.mounts.pad import ElastomerPad
from mechdyn.mounts.types import DampingPad, LevellingWedge, ScrewFoot, SpringIsolator

__all__ = ["MountFile", "MountSpec", "build"]


class ModelTable(ModelTableBase):
    type: Literal["mount"]
    """The file type, ``"mount"``: it selects the schema and the analyses that read the file."""
    name: str = "mount"
    """The model's name, shown in tables, plots, reports and the results database."""


class MaterialsTable(FileModel):
    files: list[str] = Field(default_factory=list)
    """Material files (TOML, relative to this file) added to the shipped database; names there override
    shipped ones."""


# the hardnesses of Lindley's table (the shipped rubbers), between which a pad's rubber is interpolated
SHORE_A_TABLE = (30.0, 75.0)
ShoreA = Annotated[
    float,
    Check(
        "",
        low=SHORE_A_TABLE[0],
        high=SHORE_A_TABLE[1],
        what="Shore A hardness",
        fix="the rubber's moduli are interpolated in Lindley's table, which spans no more; for another "
        "rubber give material = its name (a [materials] file adds one)",
    ),
]
PadLength = Annotated[Length, Check("m", positive=True)]


class PadTable(FileModel):
    material: str | None = None
    """The rubber by name from the materials database (instead of ``shore_a``): an elastomer (a material
    of kind ``rubber``)."""
    shore_a: ShoreA | None = None
    """The rubber by Shore A hardness (30–75), its E, G, k and B interpolated from Lindley's table."""
    thickness: PadLength
    """Pad thickness h between its bonded faces."""
    length: PadLength | None = None
    """Length l of a rectangular pad (with ``width``)."""
    width: PadLength | None = None
    """Width b of a rectangular pad (with ``length``)."""
    diameter: PadLength | None = None
    """Diameter D of a round pad (instead of ``length`` and ``width``)."""
    compression_coefficient: Annotated[float, Check("", low=0.0, high=1.0, low_open=True)] | None = None
    """The rubber's factor k in E_c = E (1 + 2 k S²) (default: the table's for the hardness); the parameter a
    calibration fits."""

    @model_validator(mode="after")
    def _material(self) -> PadTable:
        if (self.material is None) == (self.shore_a is None):
            raise ValueError("give the rubber by material (a name) or by shore_a, one of the two")
        return self


class LayerTable(FileModel):
    thickness: Length
    """Thickness of the clamped layer along the bolt."""
    material: str
    """The layer's material by name from the materials database (e.g. ``steel``, ``concrete C25/30``)."""


class BoltedTable(FileModel):
    diameter: Length
    """Nominal bolt diameter d."""
    layers: list[LayerTable] = Field(min_length=1)
    """The clamped layers from the head (or washer) down, each a ``[[bolted.layers]]`` table."""
    bolt_material: str = "bolt steel"
    """The bolt's material by name."""
    head_diameter: Length
    """Bearing diameter under the head or washer (d_W), where the pressure cone starts."""
    lower_bearing_diameter: Length | None = None
    """Bearing diameter at the far end (nut, or an anchor's head); default: ``head_diameter``."""
    hole_diameter: Length | None = None
    """Clearance-hole diameter (default: ISO 273 medium series)."""
    stress_area: Area | None = None
    """Tensile stress area A_s of the thread (default: π/4 (d − 0.9382 P)², ISO 898-1); the bolt's
    stiffness uses it over ``thread_length`` only, the shank's full area π d²/4 elsewhere."""
    nut: Literal["nut", "tapped", "anchor"] = "nut"
    """What holds the far end: ``nut``, ``tapped`` (a threaded hole) or ``anchor`` (a head in concrete)."""
    cone_angle: Angle | Literal["vdi2230"] = 0.5235987755982988
    """Half-angle α of the pressure cones, or ``"vdi2230"`` for VDI 2230's from the geometry."""
    outer_diameter: Length | None = Field(
        default=None, description="D_A of the clamped parts (a cone that reaches it goes on as a sleeve)"
    )
    pitch: Length | None = Field(default=None, description="thread pitch; by default the ISO 261 coarse one")
    thread_length: Length | None = Field(
        default=None,
        description="free thread within the grip, in series with the shank (default: none, the shank "
        "over the whole grip, as the published estimate takes it)",
    )


class WedgeTable(FileModel):
    bearing_area: Area
    """Area of the wedge's bearing faces."""
    height: Length
    """Height of the wedge stack."""
    material: str = "steel"
    """The wedges' material by name."""
    catalogue_stiffness: LinearStiffness | None = None
    """The maker's stiffness; without it the solid stack E A/h is the (upper-bound) estimate."""


class ScrewFootTable(FileModel):
    diameter: Length
    """Spindle diameter of the levelling screw."""
    free_length: Length
    """Length of spindle between the machine's foot and the base plate."""
    material: str = "steel"
    """The spindle's material by name."""
    base_stiffness: LinearStiffness | None = None
    """Stiffness of the foot's base plate or pad, in series with the spindle."""
    pitch: Length | None = Field(default=None, description="spindle thread pitch; by default ISO 261 coarse")


class DampingPadTable(PadTable):
    loss_factor: float = Field(default=0.1, ge=0, lt=2)
    """Loss factor η of the damping material."""


class SpringTable(FileModel):
    wire_diameter: Length
    """Wire diameter d of a helical spring."""
    coil_diameter: Length
    """Mean coil diameter D."""
    active_coils: float = Field(gt=0)
    """Number of active coils n: k = G d⁴/(8 D³ n)."""
    springs: int = Field(default=1, ge=1)
    """Springs in parallel in the isolator."""
    material: str = "steel"
    """The spring's material by name."""


class FETable(FileModel):
    refinements: list[Annotated[int, Field(ge=1, le=MAX_REFINEMENT)]] = Field(
        default=[4, 8, 16],
        min_length=1,
        description="the first meshes (elements through the thickness); refined by 2 from the last until "
        "converged",
    )
    tolerance: float = Field(
        default=0.005, gt=0, lt=1, description="largest relative discretisation error of the reference"
    )
    max_refinement: int = Field(
        default=64, ge=1, le=MAX_REFINEMENT, description="finest mesh it may refine to"
    )
    preloads: list[Force] = Field(default_factory=list)
    """Preloads at which an anchor's contact pressure is computed."""
    pressure_threshold: Pressure | None = None
    """Contact pressure to compare with (the published anchor: 1.7 MPa)."""
    plate_radius: Length | None = Field(default=None, gt=0)
    """Radius of the base plate in the axisymmetric model (default: 2.5 × the head diameter)."""
    concrete_radius: Length | None = Field(default=None, gt=0)
    """Radius of the concrete block in the axisymmetric model (default: 6 × the head diameter)."""


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
    """The load on the mount, as a force or as a mass under standard gravity."""
    disturbing_frequency: Frequency
    """Frequency of the disturbing force, for transmissibility and isolation."""
    loss_factor: float | None = None
    """Loss factor η of the mount (default: the estimate's)."""


class CalibrationTable(FileModel):
    reference: Literal["fe", "measured", "frf"] | None = None
    """What to calibrate against: ``fe`` (the FE reference), ``measured`` (``measured_stiffness``) or ``frf``
    (a measured frequency response)."""
    measured_stiffness: LinearStiffness | None = None
    """A measured stiffness to fit the free parameter to."""
    frf_csv: str | None = None
    """A CSV file of a measured frequency response (frequency, real and imaginary receptance), fitted by a
    single-degree-of-freedom model."""
    provenance: str = ""
    """Where the reference comes from, stored with the calibration."""
    use_stored: bool = False
    """Predict with the latest stored calibration of this mount."""

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
    mat = db.rubber(t.shore_a) if t.shore_a is not None else _elastomer(db, t.material or "")
    return ElastomerPad(name, mat, t.thickness, t.length, t.width, t.diameter, t.compression_coefficient)


def _elastomer(db: MaterialDatabase, name: str) -> Material:
    """A pad's material by name: an elastomer of the database (steel or concrete would give a pad a
    plausible-looking stiffness from a formula made for rubber)."""
    mat = _material(db, name)
    if mat.kind != "rubber":
        rubbers = ", ".join(repr(n) for n in db.names("rubber")) or "none"
        raise ModelError(
            f"{name!r} is {_kind_words(mat.kind)}, not an elastomer: a bonded pad's stiffness is that of "
            f"rubber (its shape factor and bulk compressibility). Give an elastomer of the database: "
            f'{rubbers} (or shore_a = 30 … 75; a material of your own needs kind = "rubber")',
            field="material",
        )
    return mat


def _kind_words(kind: str) -> str:
    """A material's class in words, with its article: ``a steel``, ``a cast iron``, ``concrete``."""
    words = {"concrete": "concrete", "other": 'of no known class (kind = "other")'}
    return words.get(kind, f"a {kind.replace('_', ' ')}")


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
            pad = f.pad
            assert pad is not None  # kind names the table that is given
            mount: Any = _pad(name, pad, db)
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
                thread_length=b.thread_length,
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
