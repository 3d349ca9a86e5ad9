"""Field types for model-file schemas: quantities with units, converted to SI on reading."""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict

from mechdyn.units import to_si

__all__ = [
    "Angle",
    "Density",
    "Dimensionless",
    "FileModel",
    "Frequency",
    "Length",
    "LinearStiffness",
    "ModelTableBase",
    "Pressure",
    "quantity",
]


def quantity(unit: str) -> Any:
    """A pydantic field type that reads a quantity and holds its magnitude in ``unit`` (SI).

    ``quantity("N*m/rad")`` accepts ``"0.95e6 N*m/rad"`` or ``"950 kN*m/rad"`` and stores
    ``950000.0``; a bare number is refused unless ``unit`` is dimensionless or angular.
    """

    def convert(value: Any) -> float:
        return to_si(value, unit)

    return Annotated[float, BeforeValidator(convert)]


class FileModel(BaseModel):
    """Base of every table in a model file: unknown fields are errors, values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True, str_strip_whitespace=True)


# The field types every model file uses; a capability declares its own beside them.
Length = quantity("m")
Angle = quantity("rad")
Pressure = quantity("Pa")
Density = quantity("kg/m^3")
Frequency = quantity("Hz")
LinearStiffness = quantity("N/m")
Dimensionless = quantity("")


class ModelTableBase(FileModel):
    """The ``[model]`` table every model file starts with; each type adds ``type: Literal[...]``."""

    name: str = "model"
    description: str = ""
    source: str = ""
