"""The mechanism as assembled: each body's mass, inertia about its centre of mass, centre of mass and
link length in the drawing, and each joint, as tables for the CLI, reports and ``to_frame()``."""

from __future__ import annotations

from typing import TYPE_CHECKING

from mechdyn.mechanism.model import Mechanism, _body_rows
from mechdyn.results import Table
from mechdyn.units import convert

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["model_frame", "model_tables"]


def model_tables(mechanism: Mechanism) -> list[Table]:
    """The bodies and joints as assembled.

    Parameters
    ----------
    mechanism : Mechanism
        The model (in its drawing position).

    Returns
    -------
    list of Table
        The bodies (mass in kg, inertia about the centre of mass in kg·m², centre of mass and the
        length between a two-point link's points in mm, as drawn) and the joints (kind, bodies, point
        in mm).
    """
    bodies = Table(
        f"{mechanism.name}: the bodies as assembled",
        ["body", "mass [kg]", "inertia [kg·m²]", "com x [mm]", "com y [mm]", "length [mm]", "points"],
        [
            [
                r["body"] + (" (driven)" if r["driven"] else ""),
                r["mass_kg"],
                r["inertia_kg_m2"],
                float(convert(r["center_of_mass_x_m"], "m", "mm")),
                float(convert(r["center_of_mass_y_m"], "m", "mm")),
                None if r["length_m"] is None else float(convert(r["length_m"], "m", "mm")),
                r["points"],
            ]
            for r in _body_rows(mechanism)
        ],
        note="Inertias about each body's centre of mass, normal to the plane; positions as drawn.",
    )
    joints = []
    for j in mechanism.joints:
        point = getattr(j, "point", None) or ", ".join(getattr(j, "points", ()))
        xy = mechanism.points.get(point) if isinstance(point, str) else None
        kind = "slider" if j.slides else "revolute" if j.pins else "gear pair"  # the joint protocol
        joints.append(
            [
                j.name,
                kind,
                " – ".join(j.bodies),
                point,
                None if xy is None else float(convert(xy[0], "m", "mm")),
                None if xy is None else float(convert(xy[1], "m", "mm")),
            ]
        )
    joint_table = Table(
        f"{mechanism.name}: the joints as assembled",
        ["joint", "kind", "bodies", "point", "x [mm]", "y [mm]"],
        joints,
    )
    tables = [bodies, joint_table]
    if mechanism.counterweights:
        tables.append(_counterweight_table(mechanism))
    return tables


def _counterweight_table(mechanism: Mechanism) -> Table:
    """The counterweights: link, mass (kg), own inertia (kg·m²) and drawing position (mm)."""
    rows = []
    for w in mechanism.counterweights:
        p = w.position
        xy = mechanism.points[p] if isinstance(p, str) else p
        rows.append(
            [
                w.name,
                w.body,
                float(w.mass),
                float(w.inertia),
                float(convert(xy[0], "m", "mm")),
                float(convert(xy[1], "m", "mm")),
                p if isinstance(p, str) else "",
            ]
        )
    return Table(
        f"{mechanism.name}: the counterweights",
        ["counterweight", "link", "mass [kg]", "inertia [kg·m²]", "x [mm]", "y [mm]", "at point"],
        rows,
        note="Folded into their links: the bodies above carry them (mass, centre of mass, inertia).",
    )


def model_frame(mechanism: Mechanism) -> pd.DataFrame:
    """The bodies as assembled, one row per body, SI: mass (kg), inertia about the centre of mass
    (kg·m²), centre of mass (m), length between a two-point link's points (m), as drawn.

    Parameters
    ----------
    mechanism : Mechanism
        The model.
    """
    import pandas as pd

    return pd.DataFrame(_body_rows(mechanism))
