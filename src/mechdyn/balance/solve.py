"""Counterweights that cut what reaches the floor: the design variables and the optimiser.

Per link, a point mass m at radius r and angle β from the link's reference point
(:func:`~mechdyn.balance.influence.reference_point`, its pivot on the frame when it has one), within
the bounds of a :class:`CounterweightSlot`, and all of them within a total mass and a total rotary
inertia (:class:`~mechdyn.balance.exact.Budget`). The force part of the problem is linear in the
mass moments (m u, m v) and, for a link without a pivot on the frame, the mass m
(:mod:`~mechdyn.balance.influence`), and its bounds are convex, so it is solved to its optimum
(:mod:`~mechdyn.balance.exact`: least squares for an RMS, a cone programme by cutting planes on
HiGHS linear programmes for a peak or a range, within 1e-6 of a certified lower bound), the
lightest design among those within ``slack`` of it. The rest — the shaking moment, the driving
torque, a weighted sum, a floor force that a rocking link's inertia moves, or a force solution the
smallest radius cuts — is polished by :func:`scipy.optimize.minimize` (SLSQP, bounds on m and r, the
budgets as constraints) started from the exact force solution, then lightened the same way: SLSQP
minimises the total mass with the objective held within the slack of the polished value.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.balance.exact import TIE, Budget, ForceSolution, force_optimum, within_bounds
from mechdyn.balance.influence import PER_LINK, Influence
from mechdyn.balance.objectives import metric, split
from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = ["CounterweightSlot", "Evaluator", "Found", "lead", "optimise", "slots_of"]


@dataclass(frozen=True)
class CounterweightSlot:
    """Where a counterweight may go on one link, and how heavy it may be.

    Parameters
    ----------
    link : str
        The link's name.
    mass : (min, max)
        kg or quantities, 0 ≤ min ≤ max ≤ 1e8 kg.
    radius : (min, max)
        Distance from the link's reference point (its pivot on the frame, else its first point), m
        or quantities, 0 ≤ min ≤ max ≤ 1e3 m, max > 0: the annulus the counterweight's centre may
        sit in.
    """

    link: str
    mass: Any = (0.0, 1e4)
    radius: Any = (0.0, 1.0)

    def __post_init__(self) -> None:
        el = f"counterweight slot on {self.link}"
        pairs = {}
        for f, unit in (("mass", "kg"), ("radius", "m")):
            v = getattr(self, f)
            if isinstance(v, str) or len(v) != 2:
                raise ModelError(f"{v!r} must be two values (min, max)", element=el, field=f)
            lo, hi = (si_field(el, f, x, unit, nonnegative=True) for x in v)
            if lo > hi:
                raise ModelError(f"min {lo:g} is above max {hi:g}; give (min, max)", element=el, field=f)
            pairs[f] = (lo, hi)
            object.__setattr__(self, f, (lo, hi))
        if pairs["radius"][1] <= 0:
            raise ModelError("the largest radius must be above 0 m", element=el, field="radius")


def slots_of(slots: Any) -> tuple[CounterweightSlot, ...]:
    out = []
    for s in slots:
        out.append(s if isinstance(s, CounterweightSlot) else CounterweightSlot(s))
    return tuple(out)


class Evaluator:
    """Objective values of counterweight designs, from the linear maps (microseconds a design).

    Parameters
    ----------
    infl : Influence
        Shaking force, moment, driving torque as linear maps.
    floor : FloorMap, optional
        The floor force through a support model.
    """

    def __init__(self, infl: Influence, floor: Any = None) -> None:
        self.infl = infl
        self.floor = floor

    def coefficients(self, design: np.ndarray) -> np.ndarray:
        """(..., 4 L) x = (m, m u, m v, m r²) per link for designs (..., L, 3) of (m kg, r m, β rad).

        Parameters
        ----------
        design : ndarray
            (..., L, 3) mass (kg), radius (m), angle β (rad) from the link's reference point.
        """
        d = np.asarray(design, dtype=float)
        m, r, b = d[..., 0], d[..., 1], d[..., 2]
        x = np.stack([m, m * r * np.cos(b), m * r * np.sin(b), m * r**2], axis=-1)
        return x.reshape(*d.shape[:-2], PER_LINK * d.shape[-2])

    def quantity(self, name: str, x: np.ndarray) -> np.ndarray:
        """(..., N, c) a quantity over the cycle for coefficients ``x`` (..., 4 L).

        Parameters
        ----------
        name : str
            ``shaking_force``, ``shaking_moment``, ``driving_torque`` or ``floor_force``.
        x : ndarray
            (..., 4 L) coefficients per link: m in kg, m u and m v in kg·m, J + m (u² + v²) in kg·m².
        """
        if name == "floor_force":
            if self.floor is None:
                raise ModelError(
                    "the floor force needs a support model", element="balance", field="objective"
                )
            return np.asarray(self.floor.force(x))
        ch = self.infl.channels(x)
        pick = {"shaking_force": slice(0, 2), "shaking_moment": slice(2, 3), "driving_torque": slice(3, 4)}
        return np.asarray(ch[..., pick[name]])

    def metrics(self, x: np.ndarray, names: Sequence[str]) -> dict[str, np.ndarray]:
        """Each named metric (``shaking_force_rms`` …) for coefficients ``x`` (..., 4 L), SI.

        Parameters
        ----------
        x : ndarray
            (..., 4 L) coefficients per link: m in kg, m u and m v in kg·m, J + m (u² + v²) in kg·m².
        names : sequence of str
            Metric names (:func:`mechdyn.balance.objectives.metric_names`).
        """
        cache: dict[str, np.ndarray] = {}
        out = {}
        for n in names:
            q, s = split(n)
            if q not in cache:
                cache[q] = self.quantity(q, x)
            out[n] = metric(cache[q], s)
        return out


@dataclass(frozen=True)
class _Problem:
    ev: Evaluator
    slots: tuple[CounterweightSlot, ...]
    weights: dict[str, float]
    scale: dict[str, float]
    budget: Budget

    def value(self, design: np.ndarray) -> float:
        vals = self.ev.metrics(self.ev.coefficients(design), list(self.weights))
        return float(sum(w * float(vals[n]) / self.scale[n] for n, w in self.weights.items()))

    def _space(self) -> tuple[np.ndarray, np.ndarray]:
        bounds = []
        for s in self.slots:
            bounds += [s.mass, s.radius, (-4 * np.pi, 4 * np.pi)]
        lo = np.array([b[0] for b in bounds])
        return lo, np.array([max(hi - lo, 1e-12) for lo, hi in bounds])

    def _budgets(self, design: Any) -> list[dict[str, Any]]:
        """SLSQP constraints (≥ 0) of the total mass and inertia budgets, on ``design(z)``, each scaled
        by the largest total the slots allow."""
        out = []
        b = self.budget
        if math.isfinite(b.mass):
            most = max(b.mass, sum(s.mass[1] for s in self.slots), 1e-300)
            out.append({"type": "ineq", "fun": lambda z: (b.mass - design(z)[:, 0].sum()) / most})
        if math.isfinite(b.inertia):
            top = max(b.inertia, sum(s.mass[1] * s.radius[1] ** 2 for s in self.slots), 1e-300)

            def spare(z: np.ndarray) -> float:
                d = design(z)
                return float(b.inertia - np.sum(d[:, 0] * d[:, 1] ** 2)) / top

            out.append({"type": "ineq", "fun": spare})
        return out

    def polish(self, start: np.ndarray) -> np.ndarray:
        """SLSQP from ``start`` (within the bounds and budgets), the better of the two."""
        from scipy.optimize import minimize

        L = len(self.slots)
        lo, span = self._space()

        def design(z: np.ndarray) -> np.ndarray:
            return (lo + z * span).reshape(L, 3)

        def f(z: np.ndarray) -> float:
            return self.value(design(z))

        z0 = np.clip((start.ravel() - lo) / span, 0.0, 1.0)
        res = minimize(
            f,
            z0,
            method="SLSQP",
            bounds=[(0.0, 1.0)] * z0.size,
            constraints=self._budgets(design),
            options={"maxiter": 300, "ftol": 1e-12},
        )
        x, kept = within_bounds(design(_snap(res.x)), self.slots, self.budget)
        return x if kept and self.value(x) < self.value(start) else start

    def lighten(self, design0: np.ndarray) -> np.ndarray:
        """The lightest design within the slack of ``design0``'s value (SLSQP, from it): mass that buys
        nothing for the objective is taken off."""
        from scipy.optimize import minimize

        L = len(self.slots)
        lo, span = self._space()
        heaviest = max(sum(s.mass[1] for s in self.slots), 1e-300)
        value0 = self.value(design0)
        target = value0 * (1 + self.budget.slack + TIE)
        inner = value0 * (1 + self.budget.slack + TIE / 2)  # SLSQP may overstep its constraint a little

        def design(z: np.ndarray) -> np.ndarray:
            return (lo + z * span).reshape(L, 3)

        z0 = np.clip((design0.ravel() - lo) / span, 0.0, 1.0)
        res = minimize(
            lambda z: design(z)[:, 0].sum() / heaviest,
            z0,
            method="SLSQP",
            bounds=[(0.0, 1.0)] * z0.size,
            constraints=[
                {"type": "ineq", "fun": lambda z: inner - self.value(design(z))},
                *self._budgets(design),
            ],
            options={"maxiter": 300, "ftol": 1e-12},
        )
        x, kept = within_bounds(design(_snap(res.x)), self.slots, self.budget)
        lighter = x[:, 0].sum() < design0[:, 0].sum()
        return x if lighter and kept and self.value(x) <= target else design0


def _snap(z: np.ndarray) -> np.ndarray:
    """Scaled variables within [0, 1], those within 1e-9 of a bound on it (no 1e-10 kg masses)."""
    z = np.clip(z, 0.0, 1.0)
    return np.where(z < 1e-9, 0.0, np.where(z > 1 - 1e-9, 1.0, z))


@dataclass(frozen=True)
class Found:
    """A design and how it was found.

    Attributes
    ----------
    design : ndarray
        (L, 3) mass (kg), radius (m), angle (rad) per link.
    method : str
        How.
    exact : bool
        Whether it is the force problem's optimum to the stated accuracy.
    bound : float
        Certified lower bound of the objective's metric (SI) when exact, else NaN.
    """

    design: np.ndarray
    method: str
    exact: bool
    bound: float


def lead(ev: Evaluator, weights: Mapping[str, float]) -> str:
    """The force metric the design starts from: the objective's first force metric, else the force's
    RMS (the floor force with a support, else the shaking force).

    Parameters
    ----------
    ev : Evaluator
        The linear maps.
    weights : mapping
        The objective (metric → weight).
    """
    force = [n for n in weights if split(n)[0] in ("shaking_force", "floor_force")]
    return force[0] if force else ("floor_force_rms" if ev.floor is not None else "shaking_force_rms")


def optimise(
    ev: Evaluator,
    slots: tuple[CounterweightSlot, ...],
    weights: dict[str, float],
    budget: Budget,
    start: ForceSolution | None = None,
) -> Found:
    """The counterweights minimising a weighted objective within every bound and budget.

    Parameters
    ----------
    ev : Evaluator
        The linear maps.
    slots : tuple of CounterweightSlot
        The links and their bounds.
    weights : dict
        Metric → dimensionless weight (:func:`mechdyn.balance.objectives.parse_objective`).
    budget : Budget
        Total mass (kg), total inertia (kg·m²) and the slack traded for less mass.
    start : ForceSolution, optional
        The exact solution of the leading force metric (:func:`lead`) for this budget, when already
        solved.

    Returns
    -------
    Found
    """
    names = list(weights)
    zero = np.zeros(PER_LINK * len(slots))
    before = ev.metrics(zero, names)
    scale = {n: max(float(before[n]), 1e-300) for n in names}
    problem = _Problem(ev, slots, weights, scale, budget)
    first = lead(ev, weights)
    if start is None:
        start = force_optimum(ev, slots, *split(first), budget)
    only_force = names == [first]
    if only_force and start.kept:
        return Found(start.design, f"exact: {start.method}", True, start.bound)
    polished = problem.lighten(problem.polish(start.design))
    return Found(
        polished,
        f"SLSQP (scipy.optimize.minimize) from the exact force solution by {start.method}, "
        "then the lightest within the slack",
        False,
        math.nan,
    )
