"""Where a geared train resonates over speed, and what ISO 6336-1's dynamic factor describes beside it.

The periodic steady state of the whole train peaks where an order of a mesh frequency meets one of
the train's natural frequencies (a Campbell diagram's crossings: k · f_mesh(Ω) = f_n, k = 1, 2, …;
the stiffness's harmonics excite the higher orders). ISO 6336-1's K_v by method B describes another
system: the pair alone, its two gears on the mesh spring (the reduced mass of ISO 6336-1:2006,
eq. (30), and c_γα), whose one resonance is at the pinion speed n_E1 (eq. (6)); the train's other
inertias and shafts are not in it. So the two curves answer different questions: the computed one
holds the train's modes, ISO's the pair's own mesh mode. They are shown side by side and stated as
such, never as a check of each other.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ORDERS", "crossings", "iso_note"]

#: The mesh-frequency orders whose crossings with the train's modes are listed.
ORDERS = (1, 2)


def crossings(
    natural_hz: np.ndarray, mesh_cycles: float, low: float, high: float, orders: tuple[int, ...] = ORDERS
) -> list[tuple[int, int, float, float]]:
    """The reference speeds in [low, high] (rad/s) at which an order of one mesh's frequency meets a
    natural frequency of the train: (mode number from 1, order, frequency in Hz, speed in rad/s),
    ascending in speed.

    Parameters
    ----------
    natural_hz : ndarray
        The train's natural frequencies (meshes at mean stiffness, the sweep's boundary), Hz.
    mesh_cycles : float
        Mesh cycles per radian of the reference disk (f_mesh = cycles · Ω), dimensionless.
    low, high : float
        The speed range, rad/s.
    orders : tuple of int
        The mesh-frequency orders k.
    """
    out: list[tuple[int, int, float, float]] = []
    cycles = abs(float(mesh_cycles))
    if cycles == 0.0:
        return out
    for i, f in enumerate(np.asarray(natural_hz, float)):
        if f <= 0.0:
            continue
        for k in orders:
            speed = f / (k * cycles)
            if low <= speed <= high:
                out.append((i + 1, int(k), float(f), float(speed)))
    return sorted(out, key=lambda c: c[3])


def iso_note(meshes_with_iso: list[str]) -> str:
    """What the two dynamic factors describe, in words, for a table's note.

    Parameters
    ----------
    meshes_with_iso : list of str
        The meshes that have ISO 6336-1's K_v.
    """
    if not meshes_with_iso:
        return ""
    return (
        "ISO 6336-1's K_v (method B) is the pair alone on its own mesh mode, resonant at the speed in the "
        "last column; the computed K_v is the whole train's steady state, which peaks where a mesh order "
        "meets a train mode (the rows). They describe different systems and are not expected to agree."
    )
