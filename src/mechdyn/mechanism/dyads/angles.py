"""The crank angle from the datum at every step of each variant's cycle (:func:`crank_angles`), as
both motion solvers report it; with ``angle_datum = "bdc"``, bottom dead centre is located between
the samples by the compiled quartic (:func:`._reduce.between`).
"""

from __future__ import annotations

import math

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.mechanism.model import Mechanism

__all__ = ["crank_angles"]


def crank_angles(
    mechanism: Mechanism, theta_draw: np.ndarray, step: float, s: np.ndarray | None, n: int
) -> np.ndarray:
    """Crank angle from the datum at every step of each variant's cycle, rad, in [0, 2π) (with
    ``"bdc"``, in [−h/2, 2π − h/2): BDC is located between the samples, and the sample nearest it
    comes first).

    Parameters
    ----------
    mechanism : Mechanism
        Its ``angle_datum``: a fixed crank angle, or ``"bdc"`` (the lowest output position, located
        between the samples).
    theta_draw : ndarray
        (V,) each variant's drawing crank angle, rad.
    step : float
        Signed crank step, rad.
    s : ndarray or None
        (V, n) output positions in cycle order (for ``"bdc"``).
    n : int
        Steps per revolution.
    """
    k = np.arange(n)[None, :]
    if mechanism.angle_datum == "bdc":
        if s is None:
            raise ModelError("angle_datum = 'bdc' needs a prismatic output", element="angle_datum")
        filled = np.where(np.isfinite(s), s, np.inf)
        lowest = np.argmin(filled, axis=1)
        # BDC itself, between the samples: the least of the quartic through the five samples about
        # the lowest one (to h⁴), so that an angle from BDC means the same crank position on any grid
        offset = -step * (lowest + _between(filled, lowest))[:, None]
        half = 0.5 * abs(step)  # the sample nearest BDC keeps the first place, at about 0
        return np.mod(step * k + offset + half, 2 * math.pi) - half
    offset = (np.asarray(theta_draw, dtype=float) - float(mechanism.angle_datum))[:, None]
    return np.mod(step * k + offset + 1e-12, 2 * math.pi) - 1e-12


def _between(s: np.ndarray, lowest: np.ndarray) -> np.ndarray:
    """Where, in steps from the lowest sample of each row of ``s`` (V, n), a cycle's least value lies:
    the minimum of the quartic through the five samples about it, within half a step (0 where the
    samples do not allow it: fewer than five, or not finite). Compiled, over all rows at once
    (:func:`mechdyn.mechanism.dyads._reduce.between`): no Python work per variant."""
    from mechdyn.mechanism.dyads._reduce import between

    out = np.empty(s.shape[0])
    between(np.ascontiguousarray(s, dtype=float), np.ascontiguousarray(lowest, dtype=np.int64), out)
    return out
