"""Contact changes of the time integration, located on the integrator's own steps.

Each mesh with backlash is in one of three contact modes (:mod:`._contact`: drive flanks, gap, back
flanks), a discrete state the force reads. Each mode has at most two exits, each a margin
sign · x + offset of the relative displacement x = δ − e that is positive inside the mode
(:func:`exits`): drive → gap where x falls through 0, back → gap where x rises through −b, gap → drive
where x rises through 0, gap → back where x falls through −b (:data:`EXIT_TO`), each checked on its
own, with its direction, so that a step that carries the teeth across the whole backlash is seen and
the side hit decides the new mode. Where a step ends past an exit, :func:`exit_time` locates the
crossing by Brent's method on the step's dense output, so that the integration restarts there in the
new mode and no step straddles the kink of the force or the jump of the contact damping (e.g. Hairer,
Nørsett & Wanner, *Solving Ordinary Differential Equations I*, §II.6, dense output and
discontinuities). :func:`mechdyn.gear_dynamics.simulate` drives them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mechdyn.gear_dynamics._contact import BACK, DRIVE, GAP

__all__ = ["EXIT_TO", "PROBE", "exit_time", "exits"]


def exits(gap: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The exits of each contact mode as margins sign · x + offset, positive inside the mode.

    Parameters
    ----------
    gap : ndarray
        (m,) backlash of each mesh, m (negative: none, the mesh never leaves the drive side).

    Returns
    -------
    sign : ndarray
        (3, 2) per mode (drive, gap, back) and exit: the sign of x (0: no such exit).
    offset : ndarray
        (m, 3, 2) per mesh, mode and exit: the offset, m (inf: no such exit).
    """
    sign = np.array([[1.0, 0.0], [-1.0, 1.0], [-1.0, 0.0]])
    m = gap.size
    offset = np.full((m, 3, 2), np.inf)
    has = gap >= 0
    offset[has, DRIVE, 0] = 0.0  # drive side → gap where x falls through 0
    offset[has, GAP, 0] = 0.0  # gap → drive side where x rises through 0
    offset[has, GAP, 1] = gap[has]  # gap → back side where x falls through −b
    offset[has, BACK, 0] = -gap[has]  # back side → gap where x rises through −b
    return sign, offset


EXIT_TO = np.array([[GAP, GAP], [DRIVE, BACK], [GAP, GAP]])
"""The mode each mode's exit leads to: drive and back side to the gap; the gap to the side it hits."""

PROBE = np.concatenate([2.0 ** -np.arange(40.0, 4.0, -1.0), np.arange(1, 17) / 16.0])
"""Fractions of a step (ascending) at which a margin that starts on its boundary is probed."""


def exit_time(
    kern: Any,
    dense: Any,
    t0: float,
    t1: float,
    sign: float,
    offset: float,
    j: int,
    args: tuple[Any, ...],
    armed: bool,
) -> float:
    """Where mesh ``j`` crosses an exit of its contact mode within the step [t0, t1], on the step's
    dense output: the first fall of the margin g = sign · x + offset through 0, g(t1) < 0.

    A margin positive at t0 (``armed``) is bracketed by the step. One that starts on its boundary (a
    rounding error either side of 0: the mode entered there, at a restart) leaves only after it has
    been positive: the step is probed from t0 on for the first positive margin, and the root sought
    after it. A margin never positive in the step (the relative velocity at the boundary zero, or
    pointing out of the mode: a grazing touch) leaves at t0. The direction of the crossing thus
    decides, not the side of the boundary that rounding puts the restart on.

    Returns
    -------
    float
        The time of the exit, s.
    """
    from scipy.optimize import brentq

    def g(tt: float) -> float:
        return sign * float(kern.event_value(np.asarray(dense(tt), dtype=float), *args, j)) + offset

    g1 = g(t1)
    if g1 >= 0:  # the dense output at t1 a rounding error off the state: the exit at the step's end
        return t1
    lo = t0
    if not armed or g(t0) <= 0:
        ts = t0 + (t1 - t0) * PROBE
        vals = np.array([g(float(tt)) for tt in ts[:-1]] + [g1])
        inside = np.flatnonzero(vals > 0)
        if not inside.size:
            return t0
        first_out = inside[0] + int(np.argmax(vals[inside[0] :] <= 0))
        lo, t1 = float(ts[first_out - 1]), float(ts[first_out])
    return float(brentq(g, lo, t1, xtol=1e-15 * max(1.0, abs(t1)), rtol=4 * np.finfo(float).eps))
