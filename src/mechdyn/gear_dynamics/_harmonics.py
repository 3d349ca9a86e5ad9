"""How many harmonics harmonic balance keeps, and how far the dynamic factor is from converged.

A mesh stiffness with corners or jumps (gear data, a rectangular wave) has harmonics that fall
slowly, and each harmonic p ω₀ of the response near a natural frequency resonates: the truncation
must reach past the train's highest natural frequency at the lowest speed. The rule kept here takes
the highest mesh frequency's harmonics up to twice the highest natural frequency (at the stiffest
mesh phases) at the lowest speed swept; the answer is then checked by doubling the count at the
speeds where truncation matters most (the lowest speed, where most harmonics fall below the top mode,
and the speed of the largest K_v) and, with the convergence of a profile with corners about H⁻³
(a Fourier series of a function with jumps in its first derivative; the response sums the
resonant terms), the error of K_v at H is estimated as 8/7 of the change from H to 2H (Richardson's
extrapolation, e.g. Press et al., *Numerical Recipes*, 3rd ed., 2007, §4.3).

Turret C over its shipped range (1200–4500 rpm, f_top 14.0 kHz, the mesh at 380 Hz at 1200 rpm): the
rule asks for 74 harmonics; measured against 480, 16 harmonics are 21 % off, 48 1.4 %, 74 0.6 %, 120
0.17 %, 240 6e-5.
"""

from __future__ import annotations

import math

import numpy as np

from mechdyn.gear_dynamics.periodic import LinearPeriodic, PeriodPlan, _highest_frequency

__all__ = [
    "AUTO_FACTOR",
    "HARMONICS_RTOL",
    "MAX_AUTO",
    "estimated_error",
    "harmonics_for",
    "needed_harmonics",
    "truncation_warning",
]

#: The harmonics reach this multiple of the highest natural frequency at the lowest speed.
AUTO_FACTOR = 2.0
#: The most harmonics per mesh frequency the rule asks for (a cost estimate refuses beyond).
MAX_AUTO = 1000
#: The estimated relative error of K_v above which the result warns.
HARMONICS_RTOL = 0.01
#: Fewest harmonics the rule gives.
MIN_AUTO = 8


def needed_harmonics(lin: LinearPeriodic, plan: PeriodPlan, lowest_speed: float) -> int:
    """Harmonics of the highest mesh frequency that reach :data:`AUTO_FACTOR` times the highest
    natural frequency at ``lowest_speed`` (rad/s), a count (at least :data:`MIN_AUTO`, not capped).

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    lowest_speed : float
        The lowest reference speed, rad/s.
    """
    top_mesh = plan.fundamental * max(int(plan.orders.max()) if plan.orders.size else 1, 1) * lowest_speed
    f_top = _highest_frequency(lin.at_speed(lowest_speed)) / (2 * math.pi)
    need = math.ceil(AUTO_FACTOR * f_top / top_mesh) if top_mesh > 0 else MIN_AUTO
    return int(max(need, MIN_AUTO))


def harmonics_for(lin: LinearPeriodic, plan: PeriodPlan, lowest_speed: float) -> int:
    """Harmonics of the highest mesh frequency that reach :data:`AUTO_FACTOR` times the highest
    natural frequency at ``lowest_speed`` (rad/s), a count from :data:`MIN_AUTO` to :data:`MAX_AUTO`.

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    lowest_speed : float
        The lowest reference speed, rad/s.
    """
    return min(needed_harmonics(lin, plan, lowest_speed), MAX_AUTO)


def estimated_error(kv_h: np.ndarray, kv_2h: np.ndarray) -> float:
    """The estimated largest relative error of K_v computed with H harmonics, from the same with 2H:
    8/7 of their largest relative difference (H⁻³ convergence), dimensionless; NaN without load.

    Parameters
    ----------
    kv_h, kv_2h : ndarray
        Dynamic factors with H and 2H harmonics, dimensionless (any shape, NaN where unloaded).
    """
    a, b = np.asarray(kv_h, float), np.asarray(kv_2h, float)
    ok = np.isfinite(a) & np.isfinite(b) & (b != 0)
    if not ok.any():
        return float("nan")
    return float(8.0 / 7.0 * np.max(np.abs(a[ok] - b[ok]) / np.abs(b[ok])))


def truncation_warning(H: int, error: float) -> tuple[str, ...]:
    """The warning of a result whose K_v may be off by more than :data:`HARMONICS_RTOL` from the
    truncation, in words; none within it.

    Parameters
    ----------
    H : int
        Harmonics per mesh frequency, a count.
    error : float
        The estimated largest relative error of K_v (:func:`estimated_error`), dimensionless; NaN
        where not estimated.

    Returns
    -------
    tuple of str
        One warning, or none.
    """
    if not error > HARMONICS_RTOL:
        return ()
    return (
        f"K_v may be off by {100 * error:.2g} % with {H} harmonics per mesh (the change when they are "
        f"doubled): give more (harmonics = {min(4 * H, 2000)}) or leave the count to be chosen",
    )
