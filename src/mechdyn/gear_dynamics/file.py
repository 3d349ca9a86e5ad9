"""The drivetrain file with its time tables: the gear-dynamics wing's part of the drivetrain file type.

:mod:`mechdyn.drivetrain.schema` validates a drivetrain's elements and its ``[campbell]`` and
``[response]``. This module adds what ``mechdyn simulate`` and ``mechdyn speed-sweep`` read: each
mesh's ``backlash``, ``transmission_error``, ``stiffness_variation`` and ``phase`` (:class:`MeshTable`),
and the ``[motor]``, ``[[loads]]``, ``[simulation]`` and ``[speed_sweep]`` tables of
:mod:`mechdyn.gear_dynamics.schema` (:class:`DrivetrainFile`). :mod:`mechdyn.gear_dynamics.analyses`
registers both with :func:`mechdyn.registry.extend_model_type`, so that a drivetrain file is validated
whole, and :func:`settings` gives a loaded file's :class:`DrivetrainTimeSettings`.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import TYPE_CHECKING

from pydantic import ConfigDict, Field, model_validator

from mechdyn.drivetrain import schema as drivetrain_file
from mechdyn.drivetrain.analysis_tables import DrivetrainSettings
from mechdyn.gear_dynamics.schema import (
    DynamicsSettings,
    LoadTable,
    MeshDynamicsRow,
    MotorTable,
    SimulationTable,
    SpeedSweepTable,
    StiffnessVariation,
    dynamics_settings,
)
from mechdyn.io.fields import Dimensionless, FileModel, Length
from mechdyn.io.modelfile import ModelSource, validate

if TYPE_CHECKING:
    from mechdyn.drivetrain.model import Drivetrain

__all__ = ["DrivetrainFile", "DrivetrainTimeSettings", "MeshTable", "settings"]


class MeshTable(drivetrain_file.MeshTable):
    """A ``[[meshes]]`` row with the fields of the time simulation and the speed sweep."""

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
    def _gears_need_a_pair(self) -> MeshTable:
        if self.stiffness_variation == "gears" and self.gear_pair is None:
            raise ValueError(
                'stiffness_variation = "gears" takes the mesh cycle of a gear pair; give gear_pair = the '
                "name of a [[gear_pairs]] row, or stiffness_variation = { fluctuation = 0.3, "
                "contact_ratio = 1.6 }"
            )
        return self


class DrivetrainFile(drivetrain_file.DrivetrainFile):
    """Schema of a drivetrain model file."""

    meshes: list[MeshTable] = Field(default_factory=list)  # type: ignore[assignment]  # the rows, narrowed
    motor: MotorTable | None = None
    """A motor on a disk, for ``mechdyn simulate``."""
    loads: list[LoadTable] = Field(default_factory=list)
    """Torques on disks over time, for ``mechdyn simulate``."""
    simulation: SimulationTable | None = None
    """The time simulation of ``mechdyn simulate``: duration, initial speed, integrator."""
    speed_sweep: SpeedSweepTable | None = None
    """The periodic steady state over speed of ``mechdyn speed-sweep``: speed range, points, reference."""


class _TimeTables(FileModel):
    """The time tables of a drivetrain file alone (the whole file was validated by the builder)."""

    model_config = ConfigDict(extra="ignore", frozen=True)

    meshes: list[MeshDynamicsRow] = Field(default_factory=list)
    motor: MotorTable | None = None
    loads: list[LoadTable] = Field(default_factory=list)
    simulation: SimulationTable | None = None
    speed_sweep: SpeedSweepTable | None = None


@dataclass(frozen=True)
class DrivetrainTimeSettings(DrivetrainSettings):
    """The analysis tables of a drivetrain file with its time tables (a loaded file's
    :attr:`mechdyn.io.LoadedModel.settings`).

    Attributes
    ----------
    campbell, response, gear_pairs
        As :class:`mechdyn.drivetrain.DrivetrainSettings`.
    dynamics : DynamicsSettings or None
        The mesh dynamics, ``[motor]``, ``[[loads]]`` and ``[simulation]`` (None when the file has none).
    speed_sweep : SpeedSweepTable or None
        ``[speed_sweep]`` (SI values).
    """

    dynamics: DynamicsSettings | None = None
    speed_sweep: SpeedSweepTable | None = None


def settings(source: ModelSource, drivetrain: Drivetrain) -> DrivetrainTimeSettings:
    """Read a drivetrain file's analysis tables and its time tables, checking disk and mesh names.

    Parameters
    ----------
    source : ModelSource
        The parsed file.
    drivetrain : Drivetrain
        The model built from it (its disks and meshes are what the tables name).

    Returns
    -------
    DrivetrainTimeSettings

    Raises
    ------
    ModelFileError
        A table that names a disk the drivetrain lacks, or a mesh's dynamics it cannot have (see
        :func:`mechdyn.gear_dynamics.schema.dynamics_settings`).
    """
    base = drivetrain_file.settings(source, drivetrain)
    f = validate(_TimeTables, source)
    check = drivetrain_file.disk_check(source, drivetrain)
    if f.speed_sweep is not None:
        check("[speed_sweep] → reference", f.speed_sweep.reference)
    dynamics = dynamics_settings(source, f, drivetrain, check, base.gear_pairs)
    kept = {fld.name: getattr(base, fld.name) for fld in fields(base)}
    return DrivetrainTimeSettings(**kept, dynamics=dynamics, speed_sweep=f.speed_sweep)
