"""Singular and non-assembly positions of the closed-form path, found between the samples too.

Each dyad of the closed-form path has a singularity measure m(ψ) over the crank angle ψ: the sine
of its transmission angle (RRR) or the cosine between its link and the guide (RRP). The closed form
keeps the branch of the drawing, so m never changes sign; it reaches zero where the dyad's links
fall in line (a change point or toggle, where the physical branch is lost) and is undefined where
the loop cannot close. Sampling can step over both: a change point between two samples, or a jam a
fraction of a degree wide. So every local minimum of |m| below :data:`SCREEN` at the samples is
refined by evaluating the closed form on finer and finer grids (the compiled kernel at any angles)
down to :data:`ANGLE_TOL`; the minimum is a singular position when |m| falls to zero there as a V (it
does at a change point), and the first angle where the loop stops closing is located by bisection.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["ANGLE_TOL", "SCREEN", "Finding", "screen"]

SCREEN = 0.25
"""|m| at a sample below which its neighbourhood is searched (a transmission angle of 14.5°; the
measure next to a change point or a jam between samples is a few hundredths)."""
ANGLE_TOL = 1e-7
"""rad: the width to which a singular position or the edge of a jam is located (6e-6°)."""
_GRID = 17  # points per refinement grid
_V_RATIO = 0.3  # |m| at the minimum below this share of |m| a little to either side: a V through zero
_V_STEP = 1e-5  # rad


@dataclass(frozen=True)
class Finding:
    """A position the closed form cannot pass.

    Attributes
    ----------
    kind : {"singular", "assembly"}
    turned : float
        Crank angle turned from the drawing where it happens, rad (in the direction of rotation).
    dyad : int
        The dyad (in the order of the solution).
    until : float or None
        For ``"assembly"``: where the loop closes again, rad turned (None if not within a turn).
    """

    kind: str
    turned: float
    dyad: int
    until: float | None = None


def screen(measure: Any, meas: np.ndarray, step: float) -> Finding | None:
    """The first position in the turn that the closed form cannot pass, or None.

    Parameters
    ----------
    measure : callable
        ``measure(turned) -> (M, dyads)`` the dyads' measures at crank angles turned from the
        drawing (rad), NaN where a loop does not close.
    meas : ndarray
        (N, dyads) the measures at the samples ψ_k = k · step.
    step : float
        rad between samples.
    """
    found: list[Finding] = []
    bad = np.isnan(meas).any(axis=1)
    if bad.any():
        k = int(np.argmax(bad))  # the first sample that does not close; sample 0 is the drawing
        found.append(_loss(measure, (k - 1) * step, k * step, step))
    a = np.abs(meas)
    prev, nxt = np.roll(a, 1, axis=0), np.roll(a, -1, axis=0)
    cand = (a < SCREEN) & (a <= prev) & (a <= nxt)
    for k, d in zip(*np.nonzero(cand), strict=True):
        f = _minimum(measure, float(k) * step, step, int(d))
        if f is not None:
            found.append(f)
    if not found:
        return None
    return min(found, key=lambda f: f.turned % (2 * math.pi))


def _edge(jammed: Any, lo: float, hi: float, closing: bool) -> float:
    """Bisect to ANGLE_TOL where ``jammed`` changes between lo and hi; the angle on the jammed side
    when the loop stops closing, on the closing side when it closes again."""
    while hi - lo > ANGLE_TOL:
        mid = 0.5 * (lo + hi)
        if jammed(mid) != closing:  # stopping: (lo closes, hi jams); closing again: the reverse
            hi = mid
        else:
            lo = mid
    return hi


def _loss(measure: Any, lo: float, hi: float, step: float) -> Finding:
    """The first angle in (lo, hi] where a loop stops closing, its dyad, and where it closes again."""

    def jammed(t: float) -> bool:
        return bool(np.isnan(measure(np.array([t]))[0]).any())

    start = _edge(jammed, lo, hi, closing=False)
    dyad = int(np.argmax(np.isnan(measure(np.array([start]))[0])))
    # the end of the jam: the first sample after it that closes, then bisection back
    for j in range(1, math.ceil(2 * math.pi / step) + 1):
        t = start + j * step
        if not jammed(t):
            return Finding("assembly", start, dyad, _edge(jammed, t - step, t, closing=True))
    return Finding("assembly", start, dyad, None)


def _minimum(measure: Any, centre: float, step: float, d: int) -> Finding | None:
    """Refine a sampled minimum of |m_d| about ``centre``; a Finding when it is a singular position
    or a jam, else None."""
    lo, hi = centre - step, centre + step
    while hi - lo > ANGLE_TOL:
        grid = np.linspace(lo, hi, _GRID)
        m = measure(grid)
        nan = np.isnan(m).any(axis=1)
        if nan.any():
            j = int(np.argmax(nan))
            if j == 0:  # the jam starts before this window: bisect back from the window's start
                return _loss(measure, lo - step, lo, step)
            return _loss(measure, float(grid[j - 1]), float(grid[j]), step)
        i = int(np.argmin(np.abs(m[:, d])))
        lo, hi = float(grid[max(i - 1, 0)]), float(grid[min(i + 1, _GRID - 1)])
    t = 0.5 * (lo + hi)
    f0, fm, fp = np.abs(measure(np.array([t, t - _V_STEP, t + _V_STEP]))[:, d])
    if not np.isfinite([fm, fp]).all():
        return _loss(measure, t - _V_STEP, t + _V_STEP, step)
    if f0 < 1e-12 or f0 < _V_RATIO * min(fm, fp):
        return Finding("singular", t, d)
    return None
