"""The analysis tables of a drivetrain file, ``[campbell]`` and ``[response]``, and the settings read
from a file's analysis tables (:class:`DrivetrainSettings`, :attr:`mechdyn.io.LoadedModel.settings`).

The tables are part of the drivetrain file's schema (:class:`mechdyn.drivetrain.schema.DrivetrainFile`),
which :func:`mechdyn.drivetrain.schema.settings` reads into these settings; the time-simulation tables
(``[motor]``, ``[[loads]]``, ``[simulation]``, ``[speed_sweep]``) are added to the file type by the
gear-dynamics wing (:mod:`mechdyn.gear_dynamics.file`). Every dimensional value carries its unit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from typing import Annotated, Any

from pydantic import Field, model_validator

from mechdyn.drivetrain.damping import ModalDamping, RayleighDamping
from mechdyn.io.fields import Angle, AngularSpeed, FileModel, Frequency, PerSecond, Time, Torque

__all__ = [
    "CampbellSettings",
    "CampbellTable",
    "DrivetrainSettings",
    "ExcitationTable",
    "RayleighTable",
    "ResponseSettings",
    "ResponseTable",
    "campbell_settings",
    "response_settings",
]


# an excitation order: cycles per revolution, a positive finite number
Order = Annotated[float, Field(gt=0, allow_inf_nan=False)]


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
class DrivetrainSettings:
    """The analysis tables of a drivetrain file (a loaded file's settings are
    :class:`mechdyn.gear_dynamics.file.DrivetrainTimeSettings`, which adds the time tables).

    Attributes
    ----------
    campbell : CampbellSettings or None
        ``[campbell]``.
    response : ResponseSettings or None
        ``[response]``.
    gear_pairs : dict of str to GearPair
        The gear data of each mesh given by a ``gear_pair``, by mesh name (for ISO 6336-1's K_v); read
        from the model's gear data, not an analysis table, so not compared (a saved file gives its
        meshes by teeth and stiffness).
    """

    campbell: CampbellSettings | None = None
    response: ResponseSettings | None = None
    gear_pairs: dict[str, Any] = dataclass_field(default_factory=dict, compare=False)


def campbell_settings(table: CampbellTable, check: Callable[[str, str | None], None]) -> CampbellSettings:
    """The settings of a ``[campbell]`` table, its reference disk checked.

    Parameters
    ----------
    table : CampbellTable
        The table as validated (speeds in rad/s).
    check : callable
        ``check(where, disk)`` raises a :class:`~mechdyn.errors.ModelFileError` at ``where`` when
        ``disk`` (a name, or None for none) is not a disk of the drivetrain.

    Returns
    -------
    CampbellSettings
    """
    check("[campbell] → reference_disk", table.reference_disk)
    return CampbellSettings(
        table.speed_range, table.reference_disk, tuple(table.shaft_orders), tuple(table.mesh_orders)
    )


def response_settings(table: ResponseTable, check: Callable[[str, str | None], None]) -> ResponseSettings:
    """The settings of a ``[response]`` table: the harmonic torques on one disk summed as phasors
    (N·m), the damping modal (ζ = 0.02 unless given) or Rayleigh, the disks checked.

    Parameters
    ----------
    table : ResponseTable
        The table as validated (torques in N·m, phases in rad, frequencies in Hz).
    check : callable
        ``check(where, disk)`` raises a :class:`~mechdyn.errors.ModelFileError` at ``where`` when
        ``disk`` is not a disk of the drivetrain.

    Returns
    -------
    ResponseSettings
    """
    import cmath

    exc: dict[str, complex] = {}
    for i, e in enumerate(table.excitation):
        check(f"[response] → excitation #{i + 1} → disk", e.disk)
        exc[e.disk] = exc.get(e.disk, 0) + cmath.rect(e.amplitude, e.phase)
    for o in table.outputs:
        check("[response] → outputs", o)
    if table.rayleigh is not None:
        damping: ModalDamping | RayleighDamping = RayleighDamping(table.rayleigh.alpha, table.rayleigh.beta)
    else:
        damping = ModalDamping(0.02 if table.modal_damping is None else table.modal_damping)
    return ResponseSettings(exc, table.frequency_range, table.points, tuple(table.outputs), damping)
