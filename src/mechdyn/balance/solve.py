"""Counterweights that cut what reaches the floor: the design variables and the optimiser.

Per link, a point mass m at radius r and angle β from the link's reference point
(:func:`~mechdyn.balance.influence.reference_point`, its pivot on the frame when it has one), within
the bounds of a :class:`CounterweightSlot`. The force part of the problem is linear in the mass
moments (m u, m v) and, for a link without a pivot on the frame, the mass m
(:mod:`~mechdyn.balance.influence`), so it is solved exactly: least squares
(:func:`numpy.linalg.lstsq`) for an RMS, a linear programme (:func:`scipy.optimize.linprog`,
HiGHS) for a peak or a range (a peak by the largest projection on 32 directions in the plane, or 26
in space: within 0.5 % (plane) of the Euclidean peak). The mass moment of a link on a pivot is then
carried by the largest allowed radius (the lightest counterweight). The rest — the shaking moment,
the driving torque, a weighted sum, or a force solution the bounds cut — is polished by
:func:`scipy.optimize.minimize` (SLSQP, bounds on m, r) started from the exact force solution.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.balance.influence import PER_LINK, Influence, influence
from mechdyn.balance.objectives import metric, parse_objective, split
from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = ["CounterweightSlot", "Evaluator", "balance"]


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


def _slots(slots: Any) -> tuple[CounterweightSlot, ...]:
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


def _force_rows(ev: Evaluator, quantity: str, free: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(N, c, F) the force columns of the free coefficients and (N, c) the base."""
    if quantity == "floor_force":
        return ev.floor.columns[:, :, free], ev.floor.base
    return ev.infl.columns[:, :2, free], ev.infl.base[:, :2]


def _directions(c: int) -> np.ndarray:
    if c == 2:
        a = 2 * np.pi * np.arange(32) / 32
        return np.column_stack([np.cos(a), np.sin(a)])
    g = np.array(
        [(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1) if (i, j, k) != (0, 0, 0)]
    )
    return g / np.linalg.norm(g, axis=1, keepdims=True)


def _exact_force(
    ev: Evaluator, quantity: str, statistic: str, free: np.ndarray, box: np.ndarray
) -> np.ndarray:
    """The free coefficients minimising a force metric: least squares (RMS) or a linear programme."""
    from scipy.optimize import linprog

    cols, base = _force_rows(ev, quantity, free)
    A = cols - cols.mean(axis=0)
    b = base - base.mean(axis=0)
    N, c, F = A.shape
    if statistic == "rms":
        sol, *_ = np.linalg.lstsq(A.reshape(N * c, F), -b.reshape(N * c), rcond=None)
        return np.asarray(sol)
    bounds = [(-float(v), float(v)) for v in box] + [(None, None)]
    if statistic == "peak":
        D = _directions(c)  # (d, c)
        G = np.einsum("dc,ncf->ndf", D, A).reshape(-1, F)
        h = np.einsum("dc,nc->nd", D, b).reshape(-1)
        A_ub = np.hstack([G, -np.ones((G.shape[0], 1))])
        res = linprog(np.r_[np.zeros(F), 1.0], A_ub=A_ub, b_ub=-h, bounds=bounds, method="highs")
        return np.asarray(res.x[:F]) if res.success else np.zeros(F)
    # range: hi_c ≥ f_nc, lo_c ≤ f_nc, t ≥ hi_c − lo_c
    nv = F + 2 * c + 1
    rows, rhs = [], []
    for j in range(c):
        up = np.zeros((N, nv))
        up[:, :F] = cols[:, j, :]
        up[:, F + j] = -1.0
        rows.append(up)
        rhs.append(-base[:, j])
        lo = np.zeros((N, nv))
        lo[:, :F] = -cols[:, j, :]
        lo[:, F + c + j] = 1.0
        rows.append(lo)
        rhs.append(base[:, j])
        t = np.zeros((1, nv))
        t[0, F + j], t[0, F + c + j], t[0, -1] = 1.0, -1.0, -1.0
        rows.append(t)
        rhs.append(np.zeros(1))
    cost = np.zeros(nv)
    cost[-1] = 1.0
    bounds = bounds[:F] + [(None, None)] * (2 * c + 1)
    res = linprog(cost, A_ub=np.vstack(rows), b_ub=np.concatenate(rhs), bounds=bounds, method="highs")
    return np.asarray(res.x[:F]) if res.success else np.zeros(F)


def _design_from(
    x_free: np.ndarray, free: np.ndarray, slots: tuple[CounterweightSlot, ...], pivoted: list[bool]
) -> tuple[np.ndarray, bool]:
    """(L, 3) mass, radius, angle carrying the solved coefficients, and whether the bounds kept them."""
    L = len(slots)
    x = np.zeros(PER_LINK * L)
    x[free] = x_free
    design = np.zeros((L, 3))
    kept = True
    for k, s in enumerate(slots):
        m, mu, mv = x[PER_LINK * k : PER_LINK * k + 3]
        rho = float(np.hypot(mu, mv))
        beta = float(np.arctan2(mv, mu))
        (m_lo, m_hi), (r_lo, r_hi) = s.mass, s.radius
        if pivoted[k]:  # the mass moment alone counts: carry it at the largest radius
            r = r_hi
            m = rho / r
            if m > m_hi:
                m, kept = m_hi, False
            elif m < m_lo:
                m = m_lo
                r = rho / m if m > 0 else r_hi
                if r < r_lo:
                    r, kept = r_lo, False
        else:
            clipped = float(np.clip(m, m_lo, m_hi))
            kept = kept and clipped == m
            m = clipped
            r = rho / m if m > 0 else r_lo
            kept = kept and (m > 0 or rho == 0)
            if r > r_hi or r < r_lo:
                r, kept = float(np.clip(r, r_lo, r_hi)), False
        design[k] = (m, r, beta)
    return design, kept


@dataclass(frozen=True)
class _Problem:
    ev: Evaluator
    slots: tuple[CounterweightSlot, ...]
    weights: dict[str, float]
    scale: dict[str, float]

    def value(self, design: np.ndarray) -> float:
        vals = self.ev.metrics(self.ev.coefficients(design), list(self.weights))
        return float(sum(w * float(vals[n]) / self.scale[n] for n, w in self.weights.items()))

    def polish(self, start: np.ndarray) -> np.ndarray:
        from scipy.optimize import minimize

        L = len(self.slots)
        bounds = []
        for s in self.slots:
            bounds += [s.mass, s.radius, (-4 * np.pi, 4 * np.pi)]
        span = np.array([max(hi - lo, 1e-12) for lo, hi in bounds])
        lo = np.array([b[0] for b in bounds])

        def f(z: np.ndarray) -> float:
            return self.value((lo + z * span).reshape(L, 3))

        z0 = np.clip((start.ravel() - lo) / span, 0.0, 1.0)
        res = minimize(
            f, z0, method="SLSQP", bounds=[(0.0, 1.0)] * z0.size, options={"maxiter": 300, "ftol": 1e-12}
        )
        best = res.x if res.fun <= f(z0) else z0
        return (lo + best * span).reshape(L, 3)


def balance(
    mechanism: Any,
    slots: Sequence[Any],
    objective: str | Mapping[str, float] = "shaking_force_rms",
    *,
    support: Any = None,
    placement: Any = None,
    n_angles: int = 360,
    front: bool = True,
) -> Any:
    """Counterweights on the given links that minimise the objective (:class:`BalanceResult`).

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism (its own counterweights, if any, are part of it).
    slots : sequence of CounterweightSlot or str
        The links that may carry a counterweight and their bounds (a link name alone: mass 0 to
        1e4 kg, radius 0 to 1 m).
    objective : str or mapping
        A metric (``shaking_force_rms``, ``shaking_force_peak``, ``shaking_force_range``,
        ``shaking_moment_*``, ``driving_torque_*``, ``floor_force_*`` with a support), or a mapping
        of metrics to dimensionless weights: the weighted sum of each relative to its value without
        counterweights (:mod:`mechdyn.balance.objectives`).
    support : MountedMachine, optional
        The machine on its mounts (:mod:`mechdyn.support`), for the floor force.
    placement : Placement, optional
        Where the mechanism sits in the machine (default :meth:`Placement.output_up`).
    n_angles : int
        Crank angles over one revolution.
    front : bool
        Also sweep the weights between the force (floor force with a support, else shaking force),
        shaking moment and driving torque RMS: the trade-off front.

    Returns
    -------
    BalanceResult

    Notes
    -----
    Linearity of shaking force, moment and torque in (m, m u, m v, J + m r²) per link (Berkof &
    Lowen, J. Eng. Ind. 91 (1969) 21–26); exact least squares or linear programme for a force
    objective, SLSQP from that solution otherwise (module docstring).
    """
    from mechdyn.balance.result import BalanceResult

    t0 = time.perf_counter()
    slots_ = _slots(slots)
    infl = influence(mechanism, [s.link for s in slots_], n_angles)
    floor = None
    if support is not None:
        from mechdyn.balance.floor import floor_map

        floor = floor_map(infl, support, placement)
    ev = Evaluator(infl, floor)
    weights = parse_objective(objective, floor is not None)
    t_setup = time.perf_counter() - t0
    t1 = time.perf_counter()
    design, method, exact = _optimise(ev, slots_, weights)
    t_solve = time.perf_counter() - t1
    rows: list[dict[str, float]] = []
    if front:
        rows = _front(ev, slots_)
    return BalanceResult(
        influence=infl,
        floor=floor,
        slots=slots_,
        objective=weights,
        design=design,
        method=method,
        exact=exact,
        front=tuple(rows),
        setup_seconds=t_setup,
        solve_seconds=t_solve,
    )


def _pivoted(infl: Influence) -> list[bool]:
    from mechdyn.mechanism.model import GROUND

    out = []
    for body, point in zip(infl.links, infl.points, strict=True):
        out.append(
            any(
                j.pins and GROUND in j.bodies and body in j.bodies and j.point == point
                for j in infl.mechanism.joints
            )
        )
    return out


def _force_start(
    ev: Evaluator, slots: tuple[CounterweightSlot, ...], quantity: str, statistic: str
) -> tuple[np.ndarray, bool]:
    """The exact solution of a force metric, as a design within the bounds, and whether it is exact."""
    pivoted = _pivoted(ev.infl)
    free = []
    box = []
    for k, s in enumerate(slots):
        reach = s.mass[1] * s.radius[1]
        if not pivoted[k]:
            free.append(PER_LINK * k)
            box.append(s.mass[1])
        free += [PER_LINK * k + 1, PER_LINK * k + 2]
        box += [reach, reach]
    free_ = np.array(free)  # the J + m r² column, where it moves the floor, is left to the polish
    x = _exact_force(ev, quantity, statistic, free_, np.array(box))
    return _design_from(x, free_, slots, pivoted)


def _optimise(
    ev: Evaluator, slots: tuple[CounterweightSlot, ...], weights: dict[str, float]
) -> tuple[np.ndarray, str, bool]:
    names = list(weights)
    zero = np.zeros(PER_LINK * len(slots))
    before = ev.metrics(zero, names)
    scale = {n: max(float(before[n]), 1e-300) for n in names}
    problem = _Problem(ev, slots, weights, scale)
    force = [n for n in names if split(n)[0] in ("shaking_force", "floor_force")]
    lead = force[0] if force else ("floor_force_rms" if ev.floor is not None else "shaking_force_rms")
    q, s = split(lead)
    start, kept = _force_start(ev, slots, q, s)
    method_exact = (
        "least squares (numpy.linalg.lstsq)" if s == "rms" else "linear programme (scipy linprog, HiGHS)"
    )
    only_force = len(names) == 1 and names[0] in force
    floor_rocks = q == "floor_force" and _rocking(ev)
    if only_force and kept and not floor_rocks:
        return start, f"exact: {method_exact}", True
    polished = problem.polish(start)
    if problem.value(polished) > problem.value(start):
        polished = start
    return polished, f"SLSQP (scipy.optimize.minimize) from the exact force solution by {method_exact}", False


def _rocking(ev: Evaluator) -> bool:
    """Whether a link's J + m r² column reaches the floor (it turns at a varying speed)."""
    if ev.floor is None:
        return False
    cols = ev.floor.columns[:, :, PER_LINK - 1 :: PER_LINK]
    return bool(np.any(np.abs(cols) > 1e-12 * max(float(np.abs(ev.floor.base).max()), 1.0)))


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


def _front(ev: Evaluator, slots: tuple[CounterweightSlot, ...]) -> list[dict[str, float]]:
    force = "floor_force_rms" if ev.floor is not None else "shaking_force_rms"
    names = [force, "shaking_moment_rms", "driving_torque_rms"]
    shown = [force, "shaking_force_rms", "shaking_moment_rms", "driving_torque_range"]
    shown = list(dict.fromkeys(shown))
    rows = []
    for w in FRONT_WEIGHTS:
        weights = {n: v for n, v in zip(names, w, strict=True) if v > 0}
        design, _, _ = _optimise(ev, slots, weights)
        vals = ev.metrics(ev.coefficients(design), shown)
        row = {f"weight_{n}_ratio": float(v) for n, v in zip(names, w, strict=True)}
        row["counterweight_mass_kg"] = float(design[:, 0].sum())
        unit = {"shaking_force": "N", "floor_force": "N"}
        for n in shown:
            row[f"{n}_{unit.get(split(n)[0], 'Nm')}"] = float(vals[n])
        rows.append(row)
    return rows
