"""The time-simulation tables of a drivetrain file, read by :mod:`mechdyn.gear_dynamics`.

``mechdyn simulate`` reads each mesh's ``backlash``, ``transmission_error``, ``stiffness_variation``
and ``phase`` (:class:`MeshDynamicsRow`), a ``[motor]`` on a disk (:class:`MotorTable`, or another
file's through :func:`motor_file`), ``[[loads]]`` (:class:`LoadTable`) and ``[simulation]``
(:class:`SimulationTable`); ``mechdyn speed-sweep`` reads ``[speed_sweep]`` (:class:`SpeedSweepTable`).
The drivetrain file type holds these tables beside its elements (:mod:`mechdyn.gear_dynamics.file`
extends :mod:`mechdyn.drivetrain.schema` with them); :func:`dynamics_settings` turns them into the
:class:`DynamicsSettings` that
:meth:`GearSystem.from_drivetrain <mechdyn.gear_dynamics.GearSystem.from_drivetrain>` and the torque
inputs of :mod:`mechdyn.gear_dynamics.loads` take. Every dimensional value carries its unit.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from dataclasses import field as dataclass_field
from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import BeforeValidator, ConfigDict, Field, TypeAdapter, model_validator

from mechdyn.drive.schema import MotorTable as DriveMotorTable
from mechdyn.errors import ModelFileError, ModelWarning
from mechdyn.io.fields import (
    Angle,
    AngularSpeed,
    Dimensionless,
    FileModel,
    Frequency,
    Inertia,
    Length,
    Time,
    Torque,
)
from mechdyn.io.modelfile import ModelSource, read_toml, validate

if TYPE_CHECKING:
    from mechdyn.drivetrain.model import Drivetrain

__all__ = [
    "DynamicsSettings",
    "LoadTable",
    "MeshDynamics",
    "MeshDynamicsRow",
    "MotorTable",
    "SimulationTable",
    "SpeedSweepTable",
    "StiffnessVariation",
    "StiffnessVariationTable",
    "dynamics_settings",
    "motor_file",
]


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


class MeshDynamicsRow(FileModel):
    """A ``[[meshes]]`` row as the time simulation reads it: its name, gear pair and dynamics fields
    (the drivetrain's schema checked the whole row before; the rest is ignored here)."""

    model_config = ConfigDict(extra="ignore", frozen=True)

    name: str
    gear_pair: str | None = None
    backlash: Length | None = None
    transmission_error: Length = 0.0
    stiffness_variation: StiffnessVariation = "constant"
    phase: Dimensionless = 0.0


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


def _where(table: str, i: int, name: str) -> str:
    return f"[[{table}]] #{i + 1} (name = {name!r})"


def dynamics_settings(
    source: ModelSource,
    f: Any,
    drivetrain: Drivetrain,
    check: Callable[[str, str | None], None],
    pairs: Mapping[str, Any],
) -> DynamicsSettings | None:
    """The time-simulation tables of a drivetrain file, their names checked against the drivetrain.

    Parameters
    ----------
    source : ModelSource
        The parsed file, for the errors' location.
    f : pydantic model
        The file's tables as validated: ``meshes`` (rows of :class:`MeshDynamicsRow`), ``motor``,
        ``loads`` and ``simulation``.
    drivetrain : Drivetrain
        The model built from the same file, whose meshes the rows name.
    check : callable
        ``check(where, disk)`` raises a :class:`~mechdyn.errors.ModelFileError` at ``where`` when
        ``disk`` (a name, or None for none) is not a disk of the drivetrain.
    pairs : mapping of str to GearPair
        The gear pair of each mesh given by one, by mesh name (``stiffness_variation = "gears"``
        takes its mesh cycle).

    Returns
    -------
    DynamicsSettings or None
        None when the file has no mesh dynamics, ``[motor]``, ``[[loads]]`` or ``[simulation]``.

    Raises
    ------
    ModelFileError
        A field in error, named with its fix: dynamics on a rigid mesh, a transmission error or a
        varying stiffness without the teeth, a clocking phase with neither, a ``stop`` without a
        ``[motor]`` or more than one, a disk that is not the drivetrain's.
    """
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
