"""Field types for model-file schemas: quantities with units, converted to SI on reading."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any, TypeAlias

from pydantic import BaseModel, BeforeValidator, ConfigDict

from mechdyn.checks import DEFAULT_LIMIT, MAGNITUDE_LIMITS, magnitude_limit
from mechdyn.units import to_si

__all__ = [
    "DEFAULT_LIMIT",
    "MAGNITUDE_LIMITS",
    "Acceleration",
    "Angle",
    "AngularSpeed",
    "Area",
    "Check",
    "Density",
    "Dimensionless",
    "FileModel",
    "Force",
    "Frequency",
    "Inertia",
    "Length",
    "LineLoad",
    "LinearDamping",
    "LinearStiffness",
    "Mass",
    "ModelTableBase",
    "PerSecond",
    "Pressure",
    "Time",
    "Torque",
    "TorsionalDamping",
    "TorsionalStiffness",
    "Unit",
    "Velocity",
    "quantity",
    "within_limits",
]


def quantity(unit: str) -> Any:
    """A pydantic field type that reads a quantity and holds its magnitude in ``unit`` (SI).

    ``quantity("N*m/rad")`` accepts ``"0.95e6 N*m/rad"`` or ``"950 kN*m/rad"`` and stores
    ``950000.0``; a bare number is refused unless ``unit`` is dimensionless or angular. The named
    types below (:data:`Length`, :data:`Torque`, ...) are the same for the units model files use;
    a type checker sees those as ``float``.

    Parameters
    ----------
    unit : str
        The SI unit the value is held in, as pint spells it.
    """
    return Annotated[float, Unit(unit), _in_si(unit)]


def _in_si(unit: str) -> BeforeValidator:
    """The validator that converts a file's value to ``unit`` and checks its magnitude."""

    def convert(value: Any) -> float:
        return within_limits(value, to_si(value, unit), unit)

    return BeforeValidator(convert)


@dataclass(frozen=True)
class Unit:
    """The SI unit a quantity field holds its value in: metadata of the field's type, read by the
    model-file reference of the documentation and by tools that show a field's unit.

    Attributes
    ----------
    unit : str
        The unit as pint spells it, e.g. ``"N*m/rad"``; ``""`` for a dimensionless number.
    """

    unit: str


def within_limits(value: Any, si: float, unit: str) -> float:
    """``si`` (the SI magnitude of a file's ``value`` in ``unit``) if it is within the magnitude a
    machine can have; a ValueError naming the bound otherwise.

    The bounds are those of the Python API, :data:`mechdyn.checks.MAGNITUDE_LIMITS` (re-exported
    here as :data:`MAGNITUDE_LIMITS`): one table for model files and constructors alike.
    """
    limit = magnitude_limit(unit)
    if abs(si) > limit:
        shown = f"{limit:g} {unit}".strip()
        raise ValueError(
            f"{value!r} is beyond any machine this package models (at most {shown} in magnitude); "
            "check the number and its unit"
        )
    return si


@dataclass(frozen=True)
class Check:
    """A field's value check, made as the file is validated: the Python API's own check
    (:func:`mechdyn.checks.check_number`, the same bounds and the same words), so that a value out of
    range is listed with every other problem of the file (a negative inertia beside a wrong unit)
    instead of being found by the builder once the others are fixed.

    Metadata of a field's type, with the unit the field holds: ``Annotated[Inertia, Check("kg*m^2",
    positive=True)]``. A study reads it to refuse a range that leaves what the file accepts
    (:meth:`problem`), and the model-file reference shows its bounds (:attr:`gt`, :attr:`ge`,
    :attr:`lt`, :attr:`le`).

    Attributes
    ----------
    unit : str
        The SI unit the field holds (``""``: a dimensionless number).
    positive, nonnegative : bool
        The value must be positive (and at least :data:`mechdyn.checks.SMALLEST_POSITIVE` of its
        unit) / must not be negative.
    low, high : float, optional
        Bounds in ``unit``, closed unless ``low_open`` / ``high_open``.
    low_open, high_open : bool
    what : str, optional
        The value in words, for the message (default: the field's name).
    fix : str
        A sentence added to the message: what else to give.
    """

    unit: str = ""
    positive: bool = False
    nonnegative: bool = False
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    what: str | None = None
    fix: str = ""

    @property
    def gt(self) -> float | None:
        """The open lower bound, as the model-file reference shows limits."""
        if self.low is not None:
            return self.low if self.low_open else None
        return 0 if self.positive else None

    @property
    def ge(self) -> float | None:
        """The closed lower bound."""
        if self.low is not None:
            return None if self.low_open else self.low
        return 0 if self.nonnegative and not self.positive else None

    @property
    def lt(self) -> float | None:
        """The open upper bound."""
        return self.high if self.high is not None and self.high_open else None

    @property
    def le(self) -> float | None:
        """The closed upper bound."""
        return self.high if self.high is not None and not self.high_open else None

    def problem(self, value: float, field: str) -> str | None:
        """What is wrong with ``value`` (in :attr:`unit`) for ``field``, with what it accepts; None
        when it passes.

        Parameters
        ----------
        value : float
            The value, SI.
        field : str
            The field's name, for the message.
        """
        from mechdyn.checks import check_number
        from mechdyn.errors import ModelError

        try:
            check_number(
                "",  # an element: the message shows the value alone, the location names the field
                field,
                value,
                self.unit,
                low=self.low,
                high=self.high,
                low_open=self.low_open,
                high_open=self.high_open,
                positive=self.positive,
                nonnegative=self.nonnegative,
                what=self.what,
            )
        except ModelError as exc:
            return exc.detail + (f"; {self.fix}" if self.fix else "")
        return None

    def __get_pydantic_core_schema__(self, source: Any, handler: Any) -> Any:
        from pydantic_core import PydanticCustomError, core_schema

        def check(value: Any, info: Any) -> Any:
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                problem = self.problem(float(value), info.field_name or "value")
                if problem is not None:
                    # the type io.modelfile shows as it is: the message names the value itself
                    raise PydanticCustomError("value_check", "{problem}", {"problem": problem})
            return value

        return core_schema.with_info_after_validator_function(check, handler(source))


class FileModel(BaseModel):
    """Base of every table in a model file: unknown fields are errors, values are frozen."""

    # a field's docstring (the string literal under it) is its description in the model-file reference
    model_config = ConfigDict(
        extra="forbid", frozen=True, str_strip_whitespace=True, use_attribute_docstrings=True
    )


# The field types of model files: a float in SI, read from a quantity with its unit (the Unit marker
# tells the documentation the unit; the validator converts and bounds the value).
Length: TypeAlias = Annotated[float, Unit("m"), _in_si("m")]
Area: TypeAlias = Annotated[float, Unit("m^2"), _in_si("m^2")]
Angle: TypeAlias = Annotated[float, Unit("rad"), _in_si("rad")]
Mass: TypeAlias = Annotated[float, Unit("kg"), _in_si("kg")]
Inertia: TypeAlias = Annotated[float, Unit("kg*m^2"), _in_si("kg*m^2")]
Density: TypeAlias = Annotated[float, Unit("kg/m^3"), _in_si("kg/m^3")]
Pressure: TypeAlias = Annotated[float, Unit("Pa"), _in_si("Pa")]
Force: TypeAlias = Annotated[float, Unit("N"), _in_si("N")]
Torque: TypeAlias = Annotated[float, Unit("N*m"), _in_si("N*m")]
Time: TypeAlias = Annotated[float, Unit("s"), _in_si("s")]
Frequency: TypeAlias = Annotated[float, Unit("Hz"), _in_si("Hz")]
PerSecond: TypeAlias = Annotated[float, Unit("1/s"), _in_si("1/s")]
AngularSpeed: TypeAlias = Annotated[float, Unit("rad/s"), _in_si("rad/s")]
Velocity: TypeAlias = Annotated[float, Unit("m/s"), _in_si("m/s")]
Acceleration: TypeAlias = Annotated[float, Unit("m/s^2"), _in_si("m/s^2")]
LinearStiffness: TypeAlias = Annotated[float, Unit("N/m"), _in_si("N/m")]
TorsionalStiffness: TypeAlias = Annotated[float, Unit("N*m/rad"), _in_si("N*m/rad")]
LinearDamping: TypeAlias = Annotated[float, Unit("N*s/m"), _in_si("N*s/m")]
TorsionalDamping: TypeAlias = Annotated[float, Unit("N*m*s/rad"), _in_si("N*m*s/rad")]
# ISO 6336's line load F_t/b is conventionally in N/mm
LineLoad: TypeAlias = Annotated[float, Unit("N/mm"), _in_si("N/mm")]
Dimensionless: TypeAlias = Annotated[float, Unit(""), _in_si("")]


class ModelTableBase(FileModel):
    """The ``[model]`` table every model file starts with; each type adds ``type: Literal[...]``."""

    name: str = "model"
    """The model's name, shown in tables, plots, reports and the results database."""
    description: str = ""
    """Free text about the model: what it represents, what was assumed."""
    source: str = ""
    """Where the data come from (a drawing, a publication, a measurement)."""
