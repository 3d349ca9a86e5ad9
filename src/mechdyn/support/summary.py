"""The machine on its mounts as assembled: the rigid body (mass, centre of mass, inertia) and each
mount (where it holds the machine, its stiffness and damping along its axes, and where they came from:
given, estimated from the mount's drawing, or calibrated), as tables for the CLI, reports and
``to_frame()``."""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.units import convert, readable_unit

if TYPE_CHECKING:
    import pandas as pd

    from mechdyn.support.model import MountedMachine

__all__ = ["model_frame", "model_tables"]


def _source(name: str, drawn: Mapping[str, Any]) -> str:
    """Where a mount's stiffness came from, in words."""
    d = drawn.get(name)
    if d is None:
        return "given"
    kind = re.sub(r"(?<!^)(?=[A-Z])", " ", str(d["estimate"])).lower()  # ElastomerPad: elastomer pad
    said = f"{kind} estimate from {d['source']}"
    calibration = d.get("calibration", "as drawn")
    if isinstance(calibration, Mapping):
        said += f", calibrated ({calibration.get('provenance', 'stored')})"
    return said


def model_tables(machine: MountedMachine, drawn: Mapping[str, Any] | None = None) -> list[Table]:
    """The rigid body and the mounts as assembled.

    Parameters
    ----------
    machine : MountedMachine
        The machine as analysed.
    drawn : mapping, optional
        The mounts estimated from their drawings (:func:`mechdyn.support.result.mounts_from_drawing`):
        named as the source of their stiffness.

    Returns
    -------
    list of Table
        The body (mass in kg, centre of mass in mm, inertia in kg·m²) and the mounts (position in mm,
        stiffness in kN/mm or N/mm, damping in N·s/m, along each mount's own axes).
    """
    drawn = drawn or {}
    b = machine.body
    com = np.asarray(b.center_of_mass, dtype=float)
    J = np.asarray(b.inertia, dtype=float)  # the tensor about the centre of mass
    body = Table(
        f"{machine.name}: the machine as assembled",
        ["quantity", "value", "unit"],
        [
            ["mass", float(b.mass), "kg"],
            *[
                [f"centre of mass {c}", float(convert(v, "m", "mm")), "mm"]
                for c, v in zip("xyz", com, strict=True)
            ],
            *[[f"inertia I{c}{c}", float(J[i, i]), "kg·m²"] for i, c in enumerate("xyz")],
            *[
                [f"product of inertia I{a}{c}", float(J[i, j]), "kg·m²"]
                for i, j, a, c in ((0, 1, "x", "y"), (0, 2, "x", "z"), (1, 2, "y", "z"))
                if J[i, j] != 0
            ],
        ],
        note="Inertias about axes through the centre of mass parallel to the machine's x, y, z (z up).",
    )
    stiff = max((float(np.max(m.stiffness)) for m in machine.mounts), default=0.0)
    k_unit, k_shown = readable_unit(stiff, "N/m")
    rows = []
    for m in machine.mounts:
        p = np.asarray(m.position, dtype=float)
        rows.append(
            [
                m.name,
                *[float(convert(v, "m", "mm")) for v in p],
                *[float(convert(float(k), "N/m", k_unit)) for k in m.stiffness],
                *[float(c) for c in m.damping],
                "yes" if m.anchored else "no",
                _source(m.name, drawn),
            ]
        )
    mounts = Table(
        f"{machine.name}: the mounts as assembled",
        [
            "mount",
            "x [mm]",
            "y [mm]",
            "z [mm]",
            *[f"k{a} [{k_shown}]" for a in "123"],
            *[f"c{a} [N·s/m]" for a in "123"],
            "anchored",
            "from",
        ],
        rows,
        note="Stiffness and damping along each mount's own axes (1, 2, 3: the machine's x, y, z unless the "
        "mount is turned).",
    )
    return [body, mounts]


def model_frame(machine: MountedMachine, drawn: Mapping[str, Any] | None = None) -> pd.DataFrame:
    """The mounts as assembled, one row per mount, SI: position (m), stiffness (N/m) and damping
    (N·s/m) along the mount's axes, anchored, and where the values came from.

    Parameters
    ----------
    machine : MountedMachine
        The machine as analysed.
    drawn : mapping, optional
        The mounts estimated from their drawings, as for :func:`model_tables`.
    """
    import pandas as pd

    rows = []
    for m in machine.mounts:
        row: dict[str, Any] = {"mount": m.name}
        row |= {f"{c}_m": float(v) for c, v in zip("xyz", m.position, strict=True)}
        row |= {f"stiffness_{a}_N_per_m": float(k) for a, k in zip("123", m.stiffness, strict=True)}
        row |= {f"damping_{a}_N_s_per_m": float(c) for a, c in zip("123", m.damping, strict=True)}
        row |= {"anchored": bool(m.anchored), "from": _source(m.name, drawn or {})}
        rows.append(row)
    return pd.DataFrame(rows)
