"""The drivetrain model file: TOML tables → :class:`Drivetrain` and analysis settings.

A file has ``[model] type = "drivetrain"``, an optional ``[material]`` with defaults for elements
given by geometry, arrays of tables ``[[disks]]``, ``[[shafts]]``, ``[[meshes]]``,
``[[ground_springs]]``, ``[[ground_dampers]]``, and optional ``[campbell]`` and ``[response]``
tables for those analyses. A time simulation (``mechdyn simulate``) reads each mesh's ``backlash``,
``transmission_error`` and ``stiffness_variation``, a ``[motor]`` on a disk, ``[[loads]]`` and
``[simulation]``; a speed sweep (``mechdyn speed-sweep``) reads ``[speed_sweep]``. Every dimensional
value carries its unit. See ``examples/``.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace
from dataclasses import field as dataclass_field
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, ConfigDict, Field, TypeAdapter, model_validator

from mechdyn.drive.schema import MotorTable as DriveMotorTable
from mechdyn.drivetrain.elements import (
    MAX_SHAFT_ELEMENTS,
    Disk,
    Element,
    GearMesh,
    GroundDamper,
    GroundSpring,
    Shaft,
)
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.drivetrain.response import ModalDamping, RayleighDamping
from mechdyn.errors import ModelFileError, ModelWarning
from mechdyn.gears.schema import GearTable, pair_from_tables
from mechdyn.gears.schema import MaterialTable as GearMaterialTable
from mechdyn.io.fields import (
    Angle,
    AngularSpeed,
    Check,
    Density,
    Dimensionless,
    FileModel,
    Frequency,
    Inertia,
    Length,
    LinearDamping,
    LinearStiffness,
    ModelTableBase,
    PerSecond,
    Pressure,
    Time,
    Torque,
    TorsionalDamping,
    TorsionalStiffness,
)
from mechdyn.io.modelfile import ModelSource, field_context, read_toml, validate
from mechdyn.units import show

__all__ = [
    "CampbellSettings",
    "DrivetrainFile",
    "DrivetrainSettings",
    "DynamicsSettings",
    "MeshDynamics",
    "ResponseSettings",
    "SpeedSweepTable",
    "build",
    "settings",
]


# an excitation order: cycles per revolution, a positive finite number
Order = Annotated[float, Field(gt=0, allow_inf_nan=False)]
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


class StiffnessVariationTable(FileModel):
    """A mesh stiffness that alternates between single and double tooth contact (a rectangular wave)."""

    fluctuation: Dimensionless = Field(ge=0.0, lt=2.0)
    """Peak-to-peak mesh stiffness over the mean, k/k̄ (e.g. 0.3)."""
    contact_ratio: Dimensionless = Field(ge=1.0, le=2.0)
    """Transverse contact ratio ε, from 1 to 2: the fraction ε − 1 of the cycle has two pairs in
    contact."""

    @model_validator(mode="after")
    def _positive(self) -> StiffnessVariationTable:
        low = 1.0 - self.fluctuation * (self.contact_ratio - 1.0)
        if low <= 0.0:
            raise ValueError(
                f"fluctuation {self.fluctuation:g} with contact_ratio {self.contact_ratio:g} makes the "
                f"single-contact stiffness {low:g} × the mean, not positive; give a smaller fluctuation"
            )
        return self


def _stiffness_variation(value: Any) -> Any:
    """A word or a table, each refused in words: the union's own errors would name its branches."""
    from pydantic import ValidationError

    hint = '"constant", "gears", or a table { fluctuation = 0.3, contact_ratio = 1.6 }'
    if isinstance(value, str):
        if value not in ("constant", "gears"):
            raise ValueError(f"{value!r} is not a stiffness variation; give {hint}")
        return value
    if isinstance(value, dict):
        try:
            return StiffnessVariationTable.model_validate(value)
        except ValidationError as exc:
            e = exc.errors()[0]
            field = ".".join(str(x) for x in e["loc"])
            message = str(e["msg"]).removeprefix("Value error, ")
            raise ValueError(f"{field + ': ' if field else ''}{message}") from None
    if isinstance(value, StiffnessVariationTable):
        return value
    raise ValueError(f"{value!r} is not a stiffness variation; give {hint}")


# "constant", "gears" or a rectangular wave; checked by _stiffness_variation before the union
StiffnessVariation = Annotated[
    Literal["constant", "gears"] | StiffnessVariationTable, BeforeValidator(_stiffness_variation)
]


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
    backlash: Length | None = Field(default=None, gt=0.0)
    """Total backlash along the line of action, for ``mechdyn simulate``: the teeth separate and may hit
    the back flanks (default: none, the teeth always in contact)."""
    transmission_error: Length = Field(default=0.0, ge=0.0)
    """Amplitude of the static transmission error, a sine at the mesh frequency, for ``mechdyn simulate``
    (needs the teeth)."""
    stiffness_variation: StiffnessVariation = "constant"
    """How the mesh stiffness varies over the mesh cycle in ``mechdyn simulate``: ``"constant"`` (the
    mean), ``"gears"`` (the cycle of the ``gear_pair``'s teeth), or a rectangular wave
    ``{ fluctuation = 0.3, contact_ratio = 1.6 }`` (needs the teeth). Modal analyses use the mean."""
    phase: Dimensionless = Field(default=0.0, ge=-1.0, le=1.0)
    """The mesh's clocking against the others, in mesh cycles: how far its stiffness cycle and
    transmission error stand ahead when the first disk's angle is 0 (0.25: a quarter of a base pitch;
    an angle α of the first gear is z_a · α / 360°). Rounded to the cycle's samples (1/360 cycle for a
    rectangular wave); it matters with a stiffness_variation or a transmission_error."""

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
        if self.stiffness_variation == "gears" and self.gear_pair is None:
            raise ValueError(
                'stiffness_variation = "gears" takes the mesh cycle of a gear pair; give gear_pair = the '
                "name of a [[gear_pairs]] row, or stiffness_variation = { fluctuation = 0.3, "
                "contact_ratio = 1.6 }"
            )
        return self


class MotorTable(DriveMotorTable):
    """A motor driving one disk in ``mechdyn simulate``: the drive file's ``[motor]`` (an induction
    motor from its rating, or a torque–speed curve) with the disk it drives."""

    disk: str
    """The disk the motor drives (its rotor: the rotor's inertia belongs in that disk's ``inertia``)."""
    ratio: Dimensionless = Field(default=1.0, gt=0.0)
    """Motor speed over the disk's speed, for a loss-free gear or belt between them (1: on the disk)."""
    direction: Literal[1, -1] = 1
    """1: the motor drives the disk in the positive sense of rotation; −1: the negative sense."""
    rotor_inertia: Inertia = Field(default=0.0, ge=0.0)
    """Leave it out here: the rotor is the ``disk``, whose ``inertia`` holds it (only 0 is accepted)."""

    @model_validator(mode="after")
    def _rotor_is_the_disk(self) -> MotorTable:
        if self.rotor_inertia:
            raise ValueError(
                f"rotor_inertia: the rotor is disk {self.disk!r}; add its inertia to that disk's inertia "
                "and remove rotor_inertia here"
            )
        return self


class _MotorFile(FileModel):
    """A file read for its ``[motor]`` only (``mechdyn simulate --motor FILE``): a drive file, a
    drivetrain file or a file of its own; its other tables are not read."""

    model_config = ConfigDict(extra="ignore")
    motor: MotorTable


def _nonzero_inertia(value: Any) -> bool:
    try:
        return bool(TypeAdapter(Inertia).validate_python(value))
    except ValueError:
        return True  # shown as written in the warning


def motor_file(path: str, disk: str | None, disks: Sequence[str]) -> MotorTable:
    """The ``[motor]`` table of another file, to drive a drivetrain in ``mechdyn simulate --motor``.

    Parameters
    ----------
    path : str
        A TOML file with a ``[motor]`` table: a drive file's (an induction motor from its rating, or a
        torque–speed curve), a drivetrain file's, or a file holding only that table.
    disk : str or None
        The disk it drives where the table names none (a drive file's motor drives a crank).
    disks : sequence of str
        The drivetrain's disks, one of which it must drive.

    Returns
    -------
    MotorTable
        Checked as a drivetrain's ``[motor]``; a drive file's ``rotor_inertia`` is left out, with a
        warning, as the rotor is the disk (its inertia is the disk's ``inertia``).

    Raises
    ------
    ModelFileError
        No such file, no ``[motor]`` table, no disk, or a field in error (named, with its fix).
    """
    source = read_toml(path, "a .toml file with a [motor] table (a drive or drivetrain file)")
    table = source.data.get("motor")
    if not isinstance(table, dict):
        raise ModelFileError(
            source.path,
            "[motor]",
            'no [motor] table; give a drive or drivetrain file, or a file with [motor] type = "induction", '
            'power = "3 kW", synchronous_speed = "3000 rpm", rated_speed = "2880 rpm", pullout_ratio = 2.8',
        )
    data = dict(table)
    if "disk" not in data:
        if disk is None:
            raise ModelFileError(
                source.path,
                "[motor] → disk",
                'names no disk and the model has no [motor]; add disk = "the motor\'s disk" here, or a '
                "[motor] table to the model, or pass --reference DISK",
            )
        data["disk"] = disk
    rotor = data.pop("rotor_inertia", None)
    if rotor is not None and _nonzero_inertia(rotor):
        warnings.warn(
            f"{source.path}: [motor] → rotor_inertia = {rotor!r} is not added: the rotor is disk "
            f"{data['disk']!r}, whose inertia the model gives",
            ModelWarning,
            stacklevel=2,
        )
    checked = validate(_MotorFile, replace(source, data={**source.data, "motor": data})).motor
    if checked.disk not in disks:
        raise ModelFileError(
            source.path,
            "[motor] → disk",
            f"{checked.disk!r} is not a disk of the drivetrain; give one of {', '.join(disks)}",
            checked.disk,
        )
    return checked


# the fields each kind of [[loads]] row reads (besides kind and disk) and those it needs
_LOAD_FIELDS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "constant": (("torque",), ("torque",)),
    "step": (("torque", "time", "initial_torque"), ("torque", "time")),
    "ramp": (("torque", "start", "end", "initial_torque"), ("torque", "start", "end")),
    "table": (("rows",), ("rows",)),
    "harmonic": (("amplitude", "frequency", "phase", "torque"), ("amplitude", "frequency")),
    "stop": (("time", "brake", "hold_speed"), ("time",)),
}


class LoadTable(FileModel):
    """A torque on a disk in ``mechdyn simulate``; the ``kind`` says which fields it reads."""

    kind: Literal["constant", "step", "ramp", "table", "harmonic", "stop"]
    """``constant`` (torque), ``step`` (initial_torque, then torque from time), ``ramp`` (initial_torque
    to torque from start to end), ``table`` (rows of [time, torque]), ``harmonic`` (torque + amplitude
    cos(2π frequency t + phase)), ``stop`` (the ``[motor]`` switched off at time, a brake holding)."""
    disk: str | None = None
    """The disk it acts on (a ``stop`` acts on the motor's disk: leave it out there)."""
    torque: Torque | None = None
    """The torque (constant), the torque after the step or the ramp, or the mean of a harmonic torque, in
    the drivetrain's positive sense: a load resists a disk turning that way with a negative torque, and
    one turning the other way (beyond an external mesh) with a positive one."""
    initial_torque: Torque = 0.0
    """The torque before the step or the ramp (step, ramp)."""
    time: Time | None = Field(default=None, ge=0.0)
    """The instant of the step or the stop (step, stop)."""
    start: Time | None = Field(default=None, ge=0.0)
    """When the ramp begins (ramp)."""
    end: Time | None = Field(default=None, ge=0.0)
    """When the ramp ends, after its start (ramp)."""
    rows: list[tuple[str, str]] | None = None
    """Rows [time, torque], times increasing, e.g. [["0 s", "0 N*m"], ["0.5 s", "-8 N*m"]] (table); the
    torque is interpolated linearly and the end values hold outside."""
    amplitude: Torque | None = None
    """Amplitude of the harmonic torque (harmonic)."""
    frequency: Frequency | None = Field(default=None, ge=0.0)
    """Frequency of the harmonic torque (harmonic)."""
    phase: Angle = 0.0
    """Phase of the harmonic torque at t = 0 (harmonic)."""
    brake: Torque = Field(default=0.0, ge=0.0)
    """Brake torque opposing the motor's disk after the stop (stop; 0: the motor only switched off)."""
    hold_speed: AngularSpeed = Field(default=0.01, gt=0.0)
    """Speed below which the brake torque falls smoothly to zero, so a stopped train is held (stop)."""

    @model_validator(mode="after")
    def _fields_of_kind(self) -> LoadTable:
        reads, needs = _LOAD_FIELDS[self.kind]
        missing = [k for k in needs if getattr(self, k) is None]
        if missing:
            raise ValueError(f"a {self.kind} load needs {', '.join(missing)}; {_LOAD_EXAMPLES[self.kind]}")
        defaults = LoadTable.model_fields
        extra = [
            k
            for k in self.model_fields_set
            if k not in ("kind", "disk", *reads) and getattr(self, k) != defaults[k].default
        ]
        if extra:
            raise ValueError(
                f"{', '.join(sorted(extra))} {'is' if len(extra) == 1 else 'are'} not read by a {self.kind} "
                f"load; remove {'it' if len(extra) == 1 else 'them'} ({_LOAD_EXAMPLES[self.kind]})"
            )
        if self.kind == "stop":
            if self.disk is not None:
                raise ValueError("a stop acts on the [motor]'s disk; remove disk")
        elif self.disk is None:
            raise ValueError(f"a {self.kind} load needs the disk it acts on; give disk = its name")
        if self.kind == "ramp" and not (self.end or 0.0) > (self.start or 0.0):
            raise ValueError(f"the ramp ends at {self.end:g} s, not after its start at {self.start:g} s")
        if self.kind == "table" and len(self.rows or []) < 2:
            raise ValueError(
                'a table load needs two rows or more, e.g. [["0 s", "0 N*m"], ["1 s", "-5 N*m"]]'
            )
        return self


_LOAD_EXAMPLES = {
    "constant": 'e.g. torque = "-12 N*m"',
    "step": 'e.g. torque = "-12 N*m", time = "0.5 s"',
    "ramp": 'e.g. torque = "-12 N*m", start = "0.5 s", end = "0.8 s"',
    "table": 'e.g. rows = [["0 s", "0 N*m"], ["0.5 s", "-12 N*m"]]',
    "harmonic": 'e.g. amplitude = "2 N*m", frequency = "50 Hz"',
    "stop": 'e.g. time = "1.5 s", brake = "20 N*m"',
}

_METHODS = Literal["LSODA", "Radau", "BDF", "DOP853", "RK45", "RK23"]


class SimulationTable(FileModel):
    """The time simulation of ``mechdyn simulate``."""

    duration: Time = Field(gt=0.0)
    """Simulated time, e.g. "2 s"."""
    initial_speed: AngularSpeed = 0.0
    """Speed of the ``reference`` disk at t = 0 (every disk in the rigid rotation of that speed)."""
    reference: str | None = None
    """The disk of ``initial_speed`` (default: the first disk)."""
    start: Literal["static", "rest"] = "static"
    """``static``: the train starts deflected by the torques at t = 0; ``rest``: not deflected."""
    output_step: Time | None = Field(default=None, gt=0.0)
    """Sample the result every output_step (default: every integration step; give one for long runs)."""
    method: _METHODS = "LSODA"
    """Time integrator (``scipy.integrate.solve_ivp``): LSODA switches between Adams and BDF as needed."""
    rtol: Dimensionless = Field(default=1e-7, ge=1e-13, le=1e-2)
    """Relative tolerance of the integrator."""
    cycle_steps: int = Field(default=8, ge=1, le=100_000)
    """Fewest integration steps per mesh cycle (a varying mesh stiffness is resolved, not stepped over)."""


class SpeedSweepTable(FileModel):
    """The periodic steady state over speed of ``mechdyn speed-sweep``."""

    speed_range: tuple[AngularSpeed, AngularSpeed] | None = None
    """Lowest and highest speed of the ``reference`` disk, both above zero, e.g. ["1000 rpm", "5000 rpm"]."""
    points: int = Field(default=60, ge=3, le=10_000)
    """Speeds evenly spaced over the range (more are added near each resonance peak)."""
    reference: str | None = None
    """The disk whose speed is swept (default: the ``[motor]``'s disk, else the first disk)."""
    drive: Literal["motor", "torque", "speed"] | None = None
    """How the train is driven at each speed: ``motor`` (no disk held; the ``[motor]`` drives, its
    torque following its torque–speed curve moved to each speed, as ``mechdyn simulate`` integrates
    it), ``torque`` (no disk held; a constant torque at the reference disk holds the load) or ``speed``
    (the reference disk held at exactly each speed: a kinematic input, which moves the modes of a train
    whose motor rotor it is). Default: ``motor`` where the file has a ``[motor]``, else ``torque``."""
    harmonics: int | None = Field(default=None, ge=1, le=2000)
    """Harmonics of each mesh frequency kept by harmonic balance (default: enough to reach twice the
    highest natural frequency at the lowest speed, doubled until K_v changes by less than 1 %; the
    result states the estimated error either way)."""
    backlash: bool = True
    """``false``: the teeth stay in contact, the meshes' backlash ignored (harmonic balance, fast; a
    note says where the mesh force would reverse); ``true``: shooting with Newton's method where a
    mesh has backlash, through contact loss and back-side contact (about a second a speed)."""
    direction: Literal["up", "down", "both"] = "up"
    """With backlash, the order in which the speeds are swept, each solution the start of the next:
    ``up``, ``down``, or ``both`` (the two branches of the jump, and the speeds between them)."""

    @model_validator(mode="after")
    def _range(self) -> SpeedSweepTable:
        if self.speed_range is not None and not 0 < self.speed_range[0] < self.speed_range[1]:
            raise ValueError(
                'speed_range: give [low, high] with 0 < low < high, e.g. ["1000 rpm", "5000 rpm"]'
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


class CampbellTable(FileModel):
    speed_range: tuple[AngularSpeed, AngularSpeed]
    """Lowest and highest speed of the reference disk for ``mechdyn campbell``."""
    reference_disk: str | None = None
    """The disk whose speed is the abscissa (default: the first disk)."""
    shaft_orders: list[Order] = Field(default_factory=lambda: [1.0])
    """Excitation orders per revolution of each shaft line, at its own speed."""
    mesh_orders: list[Order] = Field(default_factory=lambda: [1.0])
    """Multiples of each mesh's tooth-passing frequency (teeth × shaft speed); needs ``teeth``."""


class ExcitationTable(FileModel):
    disk: str
    """The disk the harmonic torque acts on."""
    amplitude: Torque
    """Amplitude of the harmonic torque."""
    phase: Angle = 0.0
    """Phase of the harmonic torque."""


class RayleighTable(FileModel):
    alpha: PerSecond = 0.0
    """Mass-proportional coefficient α of Rayleigh damping, C = α M + β K."""
    beta: Time = 0.0
    """Stiffness-proportional coefficient β of Rayleigh damping, C = α M + β K."""


class ResponseTable(FileModel):
    excitation: list[ExcitationTable] = Field(min_length=1)
    frequency_range: tuple[Frequency, Frequency]
    """Lowest and highest frequency of ``mechdyn frf``."""
    points: int = Field(default=1000, ge=2, le=200_000)
    """Frequencies in the range, spaced logarithmically."""
    outputs: list[str] = Field(default_factory=list)
    """Disks, shafts and meshes whose response is reported (default: all disks)."""
    modal_damping: float | None = Field(default=None, ge=0.0, lt=1.0)
    """Damping ratio ζ of every mode (instead of ``[response.rayleigh]``)."""
    rayleigh: RayleighTable | None = None

    @model_validator(mode="after")
    def _check(self) -> ResponseTable:
        lo, hi = self.frequency_range
        if not 0 < lo < hi:
            raise ValueError(f"frequency_range {lo:g}..{hi:g} Hz must satisfy 0 < low < high")
        if self.modal_damping is not None and self.rayleigh is not None:
            raise ValueError("give modal_damping or [response.rayleigh], not both")
        return self


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
    motor: MotorTable | None = None
    """A motor on a disk, for ``mechdyn simulate``."""
    loads: list[LoadTable] = Field(default_factory=list)
    """Torques on disks over time, for ``mechdyn simulate``."""
    simulation: SimulationTable | None = None
    """The time simulation of ``mechdyn simulate``: duration, initial speed, integrator."""
    speed_sweep: SpeedSweepTable | None = None
    """The periodic steady state over speed of ``mechdyn speed-sweep``: speed range, points, reference."""


class _MeshDynamicsRow(FileModel):
    model_config = ConfigDict(extra="ignore", frozen=True)

    name: str
    gear_pair: str | None = None
    backlash: Length | None = None
    transmission_error: Length = 0.0
    stiffness_variation: StiffnessVariation = "constant"
    phase: Dimensionless = 0.0


class _AnalysisTables(FileModel):
    """The analysis tables of a drivetrain file alone (the rest was validated by :func:`build`)."""

    model_config = ConfigDict(extra="ignore", frozen=True)

    campbell: CampbellTable | None = None
    response: ResponseTable | None = None
    meshes: list[_MeshDynamicsRow] = Field(default_factory=list)
    gear_pairs: list[GearPairTable] = Field(default_factory=list)
    gear_material: GearMaterialTable = GearMaterialTable()
    motor: MotorTable | None = None
    loads: list[LoadTable] = Field(default_factory=list)
    simulation: SimulationTable | None = None
    speed_sweep: SpeedSweepTable | None = None


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
    """Build the :class:`Drivetrain` described by a parsed model file."""
    f = validate(DrivetrainFile, source)
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


@dataclass(frozen=True)
class CampbellSettings:
    """The ``[campbell]`` table: reference speed range (rad/s), reference disk, orders."""

    speed_range: tuple[float, float]
    reference_disk: str | None
    shaft_orders: tuple[float, ...]
    mesh_orders: tuple[float, ...]


@dataclass(frozen=True)
class ResponseSettings:
    """The ``[response]`` table: torques (N·m, complex), frequency range (Hz), outputs, damping."""

    excitation: dict[str, complex]
    frequency_range: tuple[float, float]
    points: int
    outputs: tuple[str, ...]
    damping: ModalDamping | RayleighDamping


@dataclass(frozen=True)
class MeshDynamics:
    """A mesh's ``backlash``, ``transmission_error`` and ``stiffness_variation`` (for ``mechdyn simulate``).

    Attributes
    ----------
    backlash : float or None
        Total backlash along the line of action, m (None: always in contact).
    transmission_error : float
        Amplitude of the static transmission error, a sine at the mesh frequency, m.
    stiffness_variation : str or tuple of float
        ``"constant"``, ``"gears"`` (the cycle of ``gear_pair``), or (fluctuation, contact ratio) of a
        rectangular wave, dimensionless.
    gear_pair : GearPair or None
        The gear data whose mesh cycle ``"gears"`` takes.
    phase : float
        The mesh's clocking, mesh cycles.
    """

    backlash: float | None = None
    transmission_error: float = 0.0
    stiffness_variation: str | tuple[float, float] = "constant"
    gear_pair: Any = None
    phase: float = 0.0

    def profile(self) -> Any:
        """The stiffness profile :meth:`GearSystem.from_drivetrain` takes (a MeshCycle, a mapping, or
        None for a constant stiffness)."""
        if self.stiffness_variation == "gears":
            return self.gear_pair.mesh_cycle()
        if isinstance(self.stiffness_variation, tuple):
            fluctuation, contact_ratio = self.stiffness_variation
            return {"fluctuation": fluctuation, "contact_ratio": contact_ratio}
        return None


@dataclass(frozen=True)
class DynamicsSettings:
    """The time-simulation tables of a drivetrain file: mesh dynamics, ``[motor]``, ``[[loads]]`` and
    ``[simulation]`` as read (SI values).

    Attributes
    ----------
    meshes : dict of str to MeshDynamics
        The meshes that set backlash, a transmission error or a varying stiffness, by name.
    motor : MotorTable or None
        The ``[motor]`` table.
    loads : tuple of LoadTable
        The ``[[loads]]`` rows.
    simulation : SimulationTable or None
        The ``[simulation]`` table.
    """

    meshes: dict[str, MeshDynamics] = dataclass_field(default_factory=dict)
    motor: MotorTable | None = None
    loads: tuple[LoadTable, ...] = ()
    simulation: SimulationTable | None = None

    def system_options(self) -> dict[str, dict[str, Any]]:
        """``mesh_profiles``, ``errors``, ``backlash`` and ``phases`` for
        :meth:`GearSystem.from_drivetrain`."""
        profiles = {n: m.profile() for n, m in self.meshes.items() if m.stiffness_variation != "constant"}
        errors = {
            n: {"amplitude": m.transmission_error} for n, m in self.meshes.items() if m.transmission_error
        }
        gaps = {n: m.backlash for n, m in self.meshes.items() if m.backlash is not None}
        phases = {n: m.phase for n, m in self.meshes.items() if m.phase}
        return {"mesh_profiles": profiles, "errors": errors, "backlash": gaps, "phases": phases}

    def inputs(self) -> list[Any]:
        """The torque inputs of :mod:`mechdyn.gear_dynamics.loads`: the motor, then the loads in file order
        (a ``stop`` replaces the motor)."""
        from mechdyn.drive.motor import InductionMotor, TorqueSpeedCurve
        from mechdyn.gear_dynamics import loads as L

        out: list[Any] = []
        motor = None
        if self.motor is not None:
            m = self.motor
            if m.type == "induction":
                assert m.power and m.synchronous_speed and m.rated_speed and m.pullout_ratio  # the schema's
                curve: Any = InductionMotor.from_rating(
                    m.power, m.synchronous_speed, m.rated_speed, m.pullout_ratio, 0.0, "motor"
                )
            else:
                curve = TorqueSpeedCurve.from_table(m.curve or [], 0.0, "motor")
            motor = L.MotorTorque(m.disk, curve, m.ratio, m.direction)
            out.append(motor)
        for row in self.loads:
            r: Any = row  # the fields its kind needs are there (LoadTable checked them)
            if r.kind == "stop":
                assert motor is not None and r.time is not None  # settings() checked
                out[0] = L.BrakeStop(out[0], r.time, r.brake, r.hold_speed)
                continue
            disk = str(r.disk)
            if r.kind == "constant":
                out.append(L.ConstantTorque(disk, r.torque))
            elif r.kind == "step":
                out.append(L.StepTorque(disk, r.torque, r.time, r.initial_torque))
            elif r.kind == "ramp":
                out.append(L.RampTorque(disk, r.torque, r.start, r.end, r.initial_torque))
            elif r.kind == "table":
                out.append(L.TabulatedTorque.from_table(disk, r.rows or []))
            else:
                out.append(L.HarmonicTorque(disk, r.amplitude, r.frequency, r.phase, r.torque or 0.0))
        return out


@dataclass(frozen=True)
class DrivetrainSettings:
    """The analysis tables of a drivetrain file (:attr:`mechdyn.io.LoadedModel.settings`).

    Attributes
    ----------
    campbell : CampbellSettings or None
        ``[campbell]``.
    response : ResponseSettings or None
        ``[response]``.
    dynamics : DynamicsSettings or None
        The mesh dynamics, ``[motor]``, ``[[loads]]`` and ``[simulation]`` (None when the file has none).
    speed_sweep : SpeedSweepTable or None
        ``[speed_sweep]`` (SI values).
    gear_pairs : dict of str to GearPair
        The gear data of each mesh given by a ``gear_pair``, by mesh name (for ISO 6336-1's K_v); read
        from the model's gear data, not an analysis table, so not compared (a saved file gives its
        meshes by teeth and stiffness).
    """

    campbell: CampbellSettings | None = None
    response: ResponseSettings | None = None
    dynamics: DynamicsSettings | None = None
    speed_sweep: SpeedSweepTable | None = None
    gear_pairs: dict[str, Any] = dataclass_field(default_factory=dict, compare=False)


def settings(source: ModelSource, drivetrain: Drivetrain) -> DrivetrainSettings:
    """Read the optional analysis tables of a drivetrain file, checking disk and mesh names."""
    import cmath

    f = validate(_AnalysisTables, source)
    known = drivetrain.disk_names

    def check(where: str, disk: str | None) -> None:
        if disk is not None and disk not in known:
            raise ModelFileError(
                source.path, where, f"{disk!r} is not a disk; defined disks: {', '.join(known)}", disk
            )

    camp = None
    if f.campbell is not None:
        c = f.campbell
        check("[campbell] → reference_disk", c.reference_disk)
        camp = CampbellSettings(c.speed_range, c.reference_disk, tuple(c.shaft_orders), tuple(c.mesh_orders))
    resp = None
    if f.response is not None:
        r = f.response
        exc: dict[str, complex] = {}
        for i, e in enumerate(r.excitation):
            check(f"[response] → excitation #{i + 1} → disk", e.disk)
            exc[e.disk] = exc.get(e.disk, 0) + cmath.rect(e.amplitude, e.phase)
        for o in r.outputs:
            check("[response] → outputs", o)
        if r.rayleigh is not None:
            damping: ModalDamping | RayleighDamping = RayleighDamping(r.rayleigh.alpha, r.rayleigh.beta)
        else:
            damping = ModalDamping(0.02 if r.modal_damping is None else r.modal_damping)
        resp = ResponseSettings(exc, r.frequency_range, r.points, tuple(r.outputs), damping)
    if f.speed_sweep is not None:
        check("[speed_sweep] → reference", f.speed_sweep.reference)
    pairs = _mesh_gear_pairs(source, f)
    dynamics = _dynamics(source, f, drivetrain, check, pairs)
    return DrivetrainSettings(camp, resp, dynamics, f.speed_sweep, pairs)


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


def _dynamics(
    source: ModelSource, f: _AnalysisTables, drivetrain: Drivetrain, check: Any, pairs: dict[str, Any]
) -> DynamicsSettings | None:
    """The time-simulation tables, their names checked against the drivetrain; ``pairs`` the gear pair
    of each mesh given by one (:func:`_mesh_gear_pairs`)."""
    meshes: dict[str, MeshDynamics] = {}
    for i, m in enumerate(f.meshes):
        variation = m.stiffness_variation
        where = _where("meshes", i, m.name)
        if m.backlash is None and not m.transmission_error and variation == "constant":
            if m.phase:
                raise ModelFileError(
                    source.path,
                    f"{where} → phase",
                    "a clocking phase shifts the mesh's stiffness cycle and transmission error, and this "
                    'mesh has neither; give stiffness_variation (e.g. "gears") or a transmission_error, '
                    "or remove phase",
                    m.phase,
                )
            continue
        element = drivetrain.element(m.name)
        if getattr(element, "rigid", False):
            given = (
                "backlash"
                if m.backlash is not None
                else ("transmission_error" if m.transmission_error else "stiffness_variation")
            )
            raise ModelFileError(
                source.path,
                f"{where} → {given}",
                "a rigid mesh (no stiffness) has no backlash, transmission error or stiffness variation; "
                "give the mesh its stiffness (with base_radii) or a gear_pair",
            )
        if getattr(element, "teeth", None) is None and (m.transmission_error or variation != "constant"):
            given = "transmission_error" if m.transmission_error else "stiffness_variation"
            raise ModelFileError(
                source.path,
                f"{where} → {given}",
                "a transmission error or a stiffness varying over the mesh cycle needs the teeth (the mesh "
                "phase counts them); give teeth = [z_a, z_b] instead of ratio",
            )
        pair = pairs[m.name] if variation == "gears" else None  # the schema asks "gears" for a gear_pair
        shape = (
            variation
            if isinstance(variation, str)
            else (float(variation.fluctuation), float(variation.contact_ratio))
        )
        meshes[m.name] = MeshDynamics(m.backlash, m.transmission_error, shape, pair, m.phase)
    if f.motor is not None:
        check("[motor] → disk", f.motor.disk)
    for i, load in enumerate(f.loads):
        if load.kind == "stop" and f.motor is None:
            raise ModelFileError(
                source.path,
                f"[[loads]] #{i + 1} → kind",
                "a stop switches off the [motor]; add a [motor] table, or give the braking torque as a step "
                "load",
                "stop",
            )
        check(f"[[loads]] #{i + 1} → disk", load.disk)
    stops = [i for i, load in enumerate(f.loads) if load.kind == "stop"]
    if len(stops) > 1:
        raise ModelFileError(
            source.path,
            f"[[loads]] #{stops[1] + 1} → kind",
            "the motor stops once; keep one stop row",
            "stop",
        )
    if f.simulation is not None:
        check("[simulation] → reference", f.simulation.reference)
    if not meshes and f.motor is None and not f.loads and f.simulation is None:
        return None
    return DynamicsSettings(meshes, f.motor, tuple(f.loads), f.simulation)
