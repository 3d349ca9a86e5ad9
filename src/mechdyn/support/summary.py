"""The machine on its mounts as assembled: the rigid body (mass, centre of mass, inertia) and each
mount (where it holds the machine, its stiffness and damping along its axes, and where they came from:
given, estimated from the mount's drawing, or calibrated), as tables for the CLI and reports; the same
rows as a frame, ``to_frame()``, are the model's own (:func:`mechdyn.support.model.model_frame`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from mechdyn.results import Table
from mechdyn.support.model import MountedMachine, _source, model_frame
from mechdyn.units import convert, readable_unit

__all__ = ["model_frame", "model_tables"]


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
