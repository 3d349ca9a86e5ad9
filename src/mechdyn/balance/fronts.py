"""What counterweights trade: the trade-off front between force, shaking moment and driving torque,
and the mass front — the objective against the total added mass allowed, what each tonne buys.

Both rerun :func:`mechdyn.balance.solve.optimise` (each design the lightest within the slack of its
optimum, so no row carries mass its objective does not use). The mass front's optimal value is a
non-increasing function of the mass allowed, convex where the problem is (a force objective: the
value of a convex programme as a function of a constraint's bound, Boyd & Vandenberghe, *Convex
Optimization*, 2004, §5.6), so read linearly between its rows it overstates the mass a given
reduction needs.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from mechdyn.balance.exact import Budget
from mechdyn.balance.objectives import split

__all__ = ["FRONT_WEIGHTS", "MASS_FRACTIONS", "gain_mass", "link_key", "mass_front", "weight_front"]

FRONT_WEIGHTS = (
    (1.0, 0.0, 0.0),
    (0.75, 0.25, 0.0),
    (0.5, 0.5, 0.0),
    (0.25, 0.75, 0.0),
    (0.0, 1.0, 0.0),
    (0.75, 0.0, 0.25),
    (0.5, 0.0, 0.5),
    (0.25, 0.0, 0.75),
    (0.0, 0.0, 1.0),
    (1 / 3, 1 / 3, 1 / 3),
)
"""(force, shaking moment, driving torque) weights of the trade-off front."""

MASS_FRACTIONS = (0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0)
"""The mass front's total mass allowed, as fractions of the mass of the design found."""


def _unit(name: str) -> str:
    return "N" if split(name)[0] in ("shaking_force", "floor_force") else "Nm"


def link_key(link: str) -> str:
    """``"connecting rod"`` → ``"mass_on_connecting_rod_kg"``: a front's column of one link's mass.

    Parameters
    ----------
    link : str
        The link's name.
    """
    return "mass_on_" + "_".join(link.split()) + "_kg"


def _row(ev: Any, slots: tuple[Any, ...], design: np.ndarray, shown: list[str]) -> dict[str, float]:
    vals = ev.metrics(ev.coefficients(design), shown)
    row = {"counterweight_mass_kg": float(design[:, 0].sum())}
    row.update({link_key(s.link): float(m) for s, m in zip(slots, design[:, 0], strict=True)})
    row["counterweight_inertia_kg_m2"] = float(np.sum(design[:, 0] * design[:, 1] ** 2))
    for n in shown:
        row[f"{n}_{_unit(n)}"] = float(vals[n])
    return row


def weight_front(ev: Any, slots: tuple[Any, ...], budget: Budget) -> list[dict[str, float]]:
    """One row per weighting of :data:`FRONT_WEIGHTS`: the weights, the design's masses (kg) and
    inertia (kg·m²), the force, shaking-force RMS, shaking-moment RMS and driving-torque range.

    Parameters
    ----------
    ev : Evaluator
        The linear maps.
    slots : tuple of CounterweightSlot
        The links and their bounds.
    budget : Budget
        Total mass and inertia allowed, and the slack.
    """
    from mechdyn.balance.exact import force_optimum
    from mechdyn.balance.solve import optimise

    force = "floor_force_rms" if ev.floor is not None else "shaking_force_rms"
    names = [force, "shaking_moment_rms", "driving_torque_rms"]
    shown = list(dict.fromkeys([force, "shaking_force_rms", "shaking_moment_rms", "driving_torque_range"]))
    start = force_optimum(ev, slots, *split(force), budget)  # every weighting starts from it
    rows = []
    for w in FRONT_WEIGHTS:
        weights = {n: v for n, v in zip(names, w, strict=True) if v > 0}
        found = optimise(ev, slots, weights, budget, start)
        row = {f"weight_{n}_ratio": float(v) for n, v in zip(names, w, strict=True)}
        row.update(_row(ev, slots, found.design, shown))
        rows.append(row)
    return rows


def mass_front(
    ev: Any, slots: tuple[Any, ...], weights: dict[str, float], budget: Budget, design: np.ndarray
) -> list[dict[str, float]]:
    """The objective's optimum for a total added mass of :data:`MASS_FRACTIONS` of ``design``'s.

    Parameters
    ----------
    ev : Evaluator
        The linear maps.
    slots : tuple of CounterweightSlot
        The links and their bounds.
    weights : dict
        The objective (metric → weight).
    budget : Budget
        The bounds of the design found (its mass budget is replaced row by row).
    design : ndarray
        (L, 3) the design found (kg, m, rad): the last row.

    Returns
    -------
    list of dict
        Per row: ``max_added_mass_kg``, the masses and inertia used, ``objective_ratio`` (with over
        without), ``gain_share_ratio`` (the share of the design's reduction it buys), and each
        objective metric with the force's RMS, peak and range.
    """
    from mechdyn.balance.solve import optimise

    total = float(design[:, 0].sum())
    if total <= 1e-9 * sum(s.mass[1] for s in slots):  # no counterweight (or round-off of one)
        return []
    names = list(weights)
    force = [n for n in names if split(n)[0] in ("shaking_force", "floor_force")]
    quantity = split(force[0])[0] if force else ("floor_force" if ev.floor is not None else "shaking_force")
    shown = list(dict.fromkeys([*names, *(f"{quantity}_{s}" for s in ("rms", "peak", "range"))]))
    zero = np.zeros((len(slots), 3))
    before = ev.metrics(ev.coefficients(zero), names)

    def ratio(d: np.ndarray) -> float:
        vals = ev.metrics(ev.coefficients(d), names)
        num = sum(w * float(vals[n]) / max(float(before[n]), 1e-300) for n, w in weights.items())
        return float(num / sum(weights.values()))

    designs, best = [], zero
    for f in MASS_FRACTIONS:
        if f == 0:
            d = zero
        elif f == 1:
            d = design
        else:
            d = optimise(ev, slots, weights, replace(budget, mass=f * total)).design
            if ratio(best) < ratio(d):  # the lighter row's design is allowed here too
                d = best
        designs.append(d)
        best = d
    full = 1.0 - ratio(design)
    rows = []
    for f, d in zip(MASS_FRACTIONS, designs, strict=True):
        r = ratio(d)
        row = {"max_added_mass_kg": f * total, **_row(ev, slots, d, shown), "objective_ratio": r}
        row["gain_share_ratio"] = (1.0 - r) / full if full > 0 else math.nan
        rows.append(row)
    return rows


def gain_mass(rows: list[dict[str, float]] | tuple[dict[str, float], ...], share: float = 0.9) -> float:
    """The total mass allowed that buys ``share`` of the design's reduction, linear between the mass
    front's rows (kg; NaN without a front).

    Parameters
    ----------
    rows : sequence of dict
        The mass front (:func:`mass_front`).
    share : float
        Dimensionless share of the reduction, 0 < share ≤ 1.
    """
    if not rows:
        return math.nan
    m = [r["max_added_mass_kg"] for r in rows]
    g = [r["gain_share_ratio"] for r in rows]
    for k in range(1, len(rows)):
        if g[k] >= share:
            if g[k] == g[k - 1]:
                return float(m[k])
            return float(m[k - 1] + (share - g[k - 1]) * (m[k] - m[k - 1]) / (g[k] - g[k - 1]))
    return float(m[-1])
