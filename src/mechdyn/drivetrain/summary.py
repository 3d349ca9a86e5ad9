"""The drivetrain as assembled: every disk's inertia, every element's stiffness and a shaft's own
inertia (with its mass model and division), and where each came from (given in the file, computed
from geometry, from gear data), as a table for the CLI, reports and ``to_frame()``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from mechdyn.drivetrain.elements import GroundDamper, GroundSpring, Shaft
from mechdyn.drivetrain.gear_mesh import GearMesh
from mechdyn.drivetrain.structure import DrivetrainLike
from mechdyn.results import Table
from mechdyn.units import convert

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["model_frame", "model_table"]

_COLUMNS = ["name", "value", "unit", "kind", "disks", "ratio", "base radii [mm]", "from"]


def _shown(rows: list[list[Any]]) -> list[list[Any]]:
    """The rows with each value in the unit a designer reads it in (kN·m/rad, kN/mm)."""
    from mechdyn.units import readable

    out = []
    for name, value, unit, *rest in rows:
        if value is not None:
            value, unit = readable(float(value), _SHOWN.get(unit, unit))
        out.append([name, value, unit, *rest])
    return out


_SHOWN = {"kg*m^2": "kg·m²", "N*m/rad": "N·m/rad", "N*m*s/rad": "N·m·s/rad", "N*s/m": "N·s/m"}


def _rows(drivetrain: DrivetrainLike) -> list[list[Any]]:
    said = drivetrain.provenance
    rows: list[list[Any]] = []
    for d in drivetrain.disks:
        rows.append([d.name, d.inertia, "kg*m^2", "disk", "", None, "", said.get(d.name, "given")])
    for e in drivetrain.elements:
        given = said.get(e.name, "given")
        if isinstance(e, Shaft):
            rows.append([e.name, e.stiffness, "N*m/rad", "shaft", " – ".join(e.disks), None, "", given])
            if e.inertia:
                kind = f"shaft inertia, {e.mass_model}" + (
                    f", {e.elements} elements" if e.elements > 1 else ""
                )
                source = said.get(f"{e.name} (inertia)", "given")
                rows.append(
                    [f"{e.name} (inertia)", e.inertia, "kg*m^2", kind, " – ".join(e.disks), None, "", source]
                )
        elif isinstance(e, GearMesh):
            ratio = 1 / abs(e.transmission())
            radii = " / ".join(f"{convert(r, 'm', 'mm'):.5g}" for r in e.base_radii) if e.base_radii else ""
            if e.stiffness is None:
                rows.append(
                    [e.name, None, "", f"{e.kind} mesh, rigid", " – ".join(e.disks), ratio, radii, ""]
                )
            else:
                rows.append(
                    [e.name, e.stiffness, "N/m", f"{e.kind} mesh", " – ".join(e.disks), ratio, radii, given]
                )
        elif isinstance(e, GroundSpring):
            rows.append([e.name, e.stiffness, "N*m/rad", "grounded spring", e.disk, None, "", given])
        elif isinstance(e, GroundDamper):
            rows.append([e.name, e.damping, "N*m*s/rad", "grounded damper", e.disk, None, "", given])
        if isinstance(e, Shaft | GearMesh) and e.damping:
            unit = "N*m*s/rad" if isinstance(e, Shaft) else "N*s/m"
            rows.append(
                [f"{e.name} (damping)", e.damping, unit, "damper", " – ".join(e.disks), None, "", "given"]
            )
    return rows


def model_table(drivetrain: DrivetrainLike) -> Table:
    """The model as assembled: inertias (kg·m²), stiffnesses (N·m/rad; meshes N/m), dampings, and
    where each came from.

    Parameters
    ----------
    drivetrain : Drivetrain
        The model (its :attr:`~mechdyn.drivetrain.Drivetrain.provenance` names the values not given
        as numbers).

    Returns
    -------
    Table
        One row per disk and element, the value in SI with its unit (shown in readable units); a shaft
        with its own inertia has a second row, ``"<name> (inertia)"`` in kg·m², whose kind names its
        mass model and division and whose source says where it came from (ρ J_p l from geometry, or
        given).
    """
    return Table(
        f"{drivetrain.name}: the model as assembled",
        _COLUMNS,
        _shown(_rows(drivetrain)),
        note="A mesh's stiffness acts along its line of action (torsionally k r² at each base radius r); a "
        "rigid mesh is a constraint.",
    )


def model_frame(drivetrain: DrivetrainLike) -> pd.DataFrame:
    """:func:`model_table` as a DataFrame: one row per disk and element, values in SI.

    Parameters
    ----------
    drivetrain : Drivetrain
        The model.
    """
    import pandas as pd

    return pd.DataFrame(_rows(drivetrain), columns=_COLUMNS)
