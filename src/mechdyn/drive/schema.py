"""The drive model file: ``[model] type = "drive"``.

``[mechanism]`` names a mechanism model file (relative to this one); ``[motor]`` is an induction
motor from its rating (``type = "induction"``: power, synchronous and rated speed, pull-out ratio)
or a torque–speed curve (``type = "curve"``); ``[transmission]`` the gear ratio motor to crank and
its efficiency, or its ``[[transmission.stages]]`` (belts and meshes, each with its ratio,
efficiency and the inertia of the shaft it drives); ``[flywheel]`` its inertia and shaft (and,
optionally, the speed fluctuation to size it for); ``[process]`` a forming force over the last part
of the stroke before bottom dead centre; ``[analysis]`` the crank angles and the start-up. See
``examples/press_driven.toml``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

from pydantic import Field, model_validator

from mechdyn.errors import ModelFileError
from mechdyn.io.fields import (
    AngularSpeed,
    Dimensionless,
    FileModel,
    Force,
    Inertia,
    Length,
    ModelTableBase,
    quantity,
)
from mechdyn.io.modelfile import (
    ModelSource,
    build_source,
    field_context,
    reference_path,
    referenced,
    validate,
)

__all__ = ["DriveFile", "DriveSpec", "build"]

if TYPE_CHECKING:
    Power = float
else:
    Power = quantity("W")


class ModelTable(ModelTableBase):
    type: Literal["drive"]
    """The file type, ``"drive"``: it selects the schema and the analyses that read the file."""
    name: str = "driven mechanism"
    """The model's name, shown in tables, plots, reports and the results database."""


class MechanismTable(FileModel):
    file: str
    """The mechanism model file (relative to this file) that the motor drives; its driver's speed sign
    gives the direction of rotation, its speed is replaced by the one the drive reaches."""


class MotorTable(FileModel):
    type: Literal["induction", "curve"] = "induction"
    """``induction``: a three-phase induction motor by Kloss's formula from its rating; ``curve``: a
    torque–speed curve."""
    power: Power | None = Field(default=None, gt=0.0)
    """Rated shaft power (induction), e.g. "90 kW"."""
    synchronous_speed: AngularSpeed | None = Field(default=None, gt=0.0)
    """Synchronous speed (induction), e.g. "1500 rpm" for four poles at 50 Hz."""
    rated_speed: AngularSpeed | None = Field(default=None, gt=0.0)
    """Rated speed (induction), e.g. "1485 rpm"."""
    pullout_ratio: Dimensionless | None = Field(default=None, gt=1.0)
    """Pull-out (breakdown) torque over rated torque (induction), e.g. 2.8."""
    curve: list[tuple[str, str]] | None = None
    """Rows [speed, torque] of a torque–speed curve (curve), e.g. [["0 rpm", "1.1 kN*m"], ...], speeds
    increasing, the torque falling at the last row."""
    rotor_inertia: Inertia = Field(default=0.0, ge=0.0)
    """The rotor's moment of inertia."""

    @model_validator(mode="after")
    def _complete(self) -> MotorTable:
        rating = ("power", "synchronous_speed", "rated_speed", "pullout_ratio")
        if self.type == "induction":
            missing = [k for k in rating if getattr(self, k) is None]
            if missing:
                raise ValueError(
                    f'an induction motor needs {", ".join(missing)}; e.g. power = "90 kW", '
                    'synchronous_speed = "1500 rpm", rated_speed = "1485 rpm", pullout_ratio = 2.8'
                )
            if self.curve is not None:
                raise ValueError('curve belongs to type = "curve"; remove it')
        else:
            if self.curve is None or len(self.curve) < 2:
                raise ValueError('a curve motor needs curve = [["0 rpm", "1.1 kN*m"], ...], two rows or more')
            given = [k for k in rating if getattr(self, k) is not None]
            if given:
                raise ValueError(f'{", ".join(given)} belong to type = "induction"; remove them')
        return self


class StageTable(FileModel):
    name: str
    """The stage's name (e.g. "belt", "first mesh"); a flywheel on the shaft it drives says
    ``shaft = "belt"``."""
    ratio: Dimensionless = Field(gt=0.0)
    """Its input speed over its output speed (e.g. 4.5 for a belt from the motor)."""
    efficiency: Dimensionless = Field(default=1.0, gt=0.0, le=1.0)
    """Efficiency η of the power crossing it, in (0, 1], in whichever direction it flows."""
    inertia: Inertia = Field(default=0.0, ge=0.0)
    """Moment of inertia on the shaft it drives (its wheel or pulley and the shaft)."""


class TransmissionTable(FileModel):
    ratio: Dimensionless | None = Field(default=None, gt=0.0)
    """Gear ratio n, motor speed over crank speed (e.g. 98): one stage (or give ``stages``)."""
    efficiency: Dimensionless | None = Field(default=None, gt=0.0, le=1.0)
    """Efficiency η of that one stage, in (0, 1] (default 1): it passes the power crossing it, the
    flywheel's included, with η in the direction the power flows."""
    stages: list[StageTable] | None = None
    """The train from the motor to the crank in order, each ``{name, ratio, efficiency, inertia}``
    (``[[transmission.stages]]``), instead of ``ratio`` and ``efficiency``."""

    @model_validator(mode="after")
    def _one_form(self) -> TransmissionTable:
        if self.stages is not None:
            given = [k for k in ("ratio", "efficiency") if getattr(self, k) is not None]
            if given:
                raise ValueError(
                    f"give {' and '.join(given)} of each stage in [[transmission.stages]], or one ratio "
                    "and efficiency without stages, not both"
                )
            if not self.stages:
                raise ValueError("stages is empty; give one [[transmission.stages]] or more")
            names = [s.name for s in self.stages]
            twice = sorted({n for n in names if names.count(n) > 1})
            if twice:
                raise ValueError(f"stage names must differ; {', '.join(map(repr, twice))} given twice")
        elif self.ratio is None:
            raise ValueError("give the gear ratio (e.g. ratio = 99) or the [[transmission.stages]]")
        return self


class FlywheelTable(FileModel):
    inertia: Inertia = Field(default=0.0, ge=0.0)
    """The flywheel's moment of inertia."""
    shaft: str = "motor"
    """Where it sits: ``"motor"`` (it counts n² times at the crank), ``"crank"``, or the name of the
    stage whose driven shaft carries it."""
    target_fluctuation: Dimensionless | None = Field(default=None, gt=0.0, lt=1.0)
    """Also size the flywheel for this coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean,
    reported beside the results of the flywheel given."""


class ProcessTable(FileModel):
    force: Force = Field(gt=0.0)
    """The forming force at full load, resisting the slide on its working stroke."""
    before_bdc: Length = Field(gt=0.0)
    """Slide travel before bottom dead centre over which it acts."""
    rise: Length = Field(default=0.0, ge=0.0)
    """Slide travel over which it rises from zero to full load."""


class AnalysisTable(FileModel):
    n_angles: int = Field(default=720, ge=8, le=50_000)
    """Crank angles per revolution of the steady state."""
    start_up: bool = True
    """Integrate the run-up from rest too."""
    start_up_method: Literal["LSODA", "Radau", "BDF", "DOP853", "RK45"] = "LSODA"
    """Time integrator of the start-up (``scipy.integrate.solve_ivp``)."""


class DriveFile(FileModel):
    """Schema of a drive model file."""

    model: ModelTable
    mechanism: MechanismTable
    motor: MotorTable
    transmission: TransmissionTable
    flywheel: FlywheelTable = FlywheelTable()
    process: ProcessTable | None = None
    analysis: AnalysisTable = AnalysisTable()


@dataclass(frozen=True)
class DriveSpec:
    """A drive as read from a file, with its analysis settings.

    Attributes
    ----------
    drive : Drive
        Motor, gearing, flywheel and the mechanism with its forming force.
    settings : AnalysisTable
        Crank angles and start-up.
    target_fluctuation : float or None
        δ to size the flywheel for, dimensionless.
    mechanism_path : str
        The mechanism model file.
    """

    drive: Any
    settings: AnalysisTable
    target_fluctuation: float | None
    mechanism_path: str

    @property
    def name(self) -> str:
        return str(self.drive.name)


def build(source: ModelSource) -> DriveSpec:
    """Builder for ``[model] type = "drive"``.

    Parameters
    ----------
    source : ModelSource
        The parsed file.
    """
    from mechdyn.drive.model import Drive, FormingForce
    from mechdyn.drive.motor import InductionMotor, TorqueSpeedCurve
    from mechdyn.drive.train import Stage
    from mechdyn.mechanism.schema import MechanismSpec

    f = validate(DriveFile, source)
    ref = f.mechanism.file
    msource = referenced(source, ref)
    if msource is None:
        raise ModelFileError(
            source.path,
            "[mechanism] → file",
            f"{ref!r}: no such file next to this model ({reference_path(source, ref)}); give the mechanism "
            'model file\'s path relative to this file, e.g. file = "press_link_drive.toml"',
            ref,
        )
    spec = build_source(msource)
    if not isinstance(spec, MechanismSpec):
        raise ModelFileError(
            source.path,
            "[mechanism] → file",
            f"{ref!r} is a {msource.model_type!r} model; give a mechanism model file",
            ref,
        )
    mechanism = spec.mechanism
    m = f.motor
    with field_context(source, "[motor]"):
        if m.type == "induction":
            assert m.power and m.synchronous_speed and m.rated_speed and m.pullout_ratio  # the schema's check
            motor: Any = InductionMotor.from_rating(
                m.power, m.synchronous_speed, m.rated_speed, m.pullout_ratio, m.rotor_inertia, "motor"
            )
        else:
            motor = TorqueSpeedCurve.from_table(m.curve or [], m.rotor_inertia, "motor")
    if f.process is not None:
        p = f.process
        with field_context(source, "[process]"):
            mechanism = FormingForce(p.force, p.before_bdc, p.rise).on(mechanism, 2 * f.analysis.n_angles)
    t = f.transmission
    stages = tuple(Stage(s.ratio, s.efficiency, s.inertia, s.name) for s in t.stages or ())
    shafts = ("motor", *(s.name for s in stages[:-1]), "crank")
    if f.flywheel.shaft not in shafts:
        raise ModelFileError(
            source.path,
            "[flywheel] → shaft",
            f"{f.flywheel.shaft!r} names no shaft of the train; give one of "
            + ", ".join(repr(x) for x in shafts)
            + " (a stage's name is the shaft it drives; the last stage drives the crank)",
            f.flywheel.shaft,
        )
    with field_context(source, "[transmission]"):
        drive = Drive(
            mechanism,
            motor,
            t.ratio,
            f.flywheel.inertia,
            f.flywheel.shaft,
            t.efficiency,
            f.model.name,
            stages,
        )
    return DriveSpec(drive, f.analysis, f.flywheel.target_fluctuation, str(msource.path))
