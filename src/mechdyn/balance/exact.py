"""The force part of a counterweight problem, solved to its optimum within every bound and budget.

The shaking force, and the floor force through a support, are linear in each link's mass moment
(m u, m v), for a link without a pivot on the frame its mass m, and for a link that turns at a
varying speed (a rocker rocking the machine on its mounts) its rotary inertia I = J + m (u² + v²)
(:mod:`~mechdyn.balance.influence`). What bounds a point-mass counterweight is convex in the same
numbers: a mass moment ρ = m r within m·r_max, a mass within (m_min, m_max), the total mass within a
budget, and I ≥ ρ²/m (equality for a point mass at ρ/m) with I ≤ m r_max², Σ I within the inertia
budget (a rotated second-order cone, Boyd & Vandenberghe, *Convex Optimization*, 2004, §4.4.2). So

- the RMS is linear least squares (:func:`numpy.linalg.lstsq`) where its solution is unique and
  keeps every bound, else a cone programme started from SLSQP's solution of it;
- the peak (the largest Euclidean magnitude over the cycle, a minimax) and the range are cone
  programmes: minimise t subject to ‖F(θ_i) − F̄‖ ≤ t at every crank angle θ_i (the epigraph form of
  the peak) or the linear range constraints, with the bounds' cones,

solved by cutting planes on HiGHS linear programmes (:mod:`~mechdyn.balance.conic`) to within
:data:`GAP` of a certified lower bound. Then, lexicographically, the lightest counterweights whose
objective is within ``slack`` (and :data:`TIE`) of that optimum: mass that buys nothing is not
added. The design is exact when its point masses give the programme's value: not where the
programme wanted more inertia on a rocking link than a point mass has (I > ρ²/m), nor where the
radius's lower bound (r ≥ r_min > 0, not convex) cuts it; those are handed on to the polish
(:mod:`~mechdyn.balance.solve`) with ``kept`` false.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.balance.conic import Cones, CuttingPlanes, directions
from mechdyn.balance.influence import PER_LINK
from mechdyn.errors import MechdynError

__all__ = ["GAP", "TIE", "Budget", "ForceSolution", "force_optimum", "pivoted", "within_bounds"]

GAP = 1e-6
"""Stated accuracy of an exact force solution: its value is within this fraction above the cone
programme's certified lower bound (besides the ``slack`` traded for less mass)."""

TIE = 1e-9
"""Two objective values within this fraction of each other are equal: the lightest of equal designs
is taken (with ``slack`` 0, mass that buys nothing is not added)."""

_NOISE = 1e-12
"""A scaled mass or mass moment below this (of its bound) is round-off: no counterweight."""

_KEEP = 1e-7
"""A bound or budget broken by less than this fraction (the cuts' tolerance) is met by a rescale."""


@dataclass(frozen=True)
class Budget:
    """What all the counterweights together may cost.

    Parameters
    ----------
    mass : float
        Largest total added mass, kg (inf: none).
    inertia : float
        Largest total added rotary inertia Σ m r² about each link's reference point, kg·m² (inf:
        none).
    slack : float
        Dimensionless: among designs whose objective is within this fraction of the optimum (and
        :data:`TIE`), the lightest is taken; 0: among equal ones.
    """

    mass: float = math.inf
    inertia: float = math.inf
    slack: float = 0.0


@dataclass(frozen=True)
class ForceSolution:
    """The exact force solution as a design.

    Attributes
    ----------
    design : ndarray
        (L, 3) mass (kg), radius (m), angle (rad) per link.
    kept : bool
        Whether the design's point masses give the programme's optimum (False where r ≥ r_min cut
        it, or a rocking link wanted more inertia than a point mass has).
    bound : float
        Certified lower bound of the force metric, N (the optimum itself for least squares).
    method : str
        How it was solved.
    """

    design: np.ndarray
    kept: bool
    bound: float
    method: str


def pivoted(infl: Any) -> list[bool]:
    """Whether each link of ``infl`` is measured from a pin joint with the frame (its mass then adds
    no fluctuating force).

    Parameters
    ----------
    infl : Influence
        The linear maps.
    """
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


def _force(ev: Any, quantity: str) -> tuple[np.ndarray, np.ndarray]:
    """(N, c, 4 L) the force per coefficient and (N, c) the force as it is."""
    if quantity == "floor_force":
        return ev.floor.columns, ev.floor.base
    return ev.infl.columns[:, :2], ev.infl.base[:, :2]


@dataclass(frozen=True)
class _Layout:
    """Scaled variables per link (m u, m v over m_max r_max; m over m_max; I over m_max r_max²)."""

    slots: tuple[Any, ...]
    pivoted: list[bool]
    inertia: bool

    @property
    def per(self) -> int:
        return 4 if self.inertia else 3

    @property
    def n(self) -> int:
        return self.per * len(self.slots)

    def index(self, k: int, what: str) -> int:
        return self.per * k + {"mu": 0, "mv": 1, "m": 2, "I": 3}[what]

    def coefficients(self) -> np.ndarray:
        """(4 L, n) the coefficients x of :mod:`~mechdyn.balance.influence` per scaled variable."""
        T = np.zeros((PER_LINK * len(self.slots), self.n))
        for k, s in enumerate(self.slots):
            m_hi, r_hi = s.mass[1], s.radius[1]
            T[PER_LINK * k + 1, self.index(k, "mu")] = m_hi * r_hi
            T[PER_LINK * k + 2, self.index(k, "mv")] = m_hi * r_hi
            if not self.pivoted[k]:
                T[PER_LINK * k, self.index(k, "m")] = m_hi
            if self.inertia:
                T[PER_LINK * k + 3, self.index(k, "I")] = m_hi * r_hi**2
        return T

    def bounds(self) -> list[tuple[float, float]]:
        out: list[tuple[float, float]] = []
        for s in self.slots:
            m_lo, m_hi = s.mass
            on = 1.0 if m_hi > 0 else 0.0
            out += [(-on, on), (-on, on), (m_lo / m_hi if m_hi > 0 else 0.0, on)]
            if self.inertia:
                out.append((0.0, on))
        return out

    def design(self, y: np.ndarray) -> np.ndarray:
        """(L, 3) mass, radius, angle of scaled variables y; on a pivot, the lightest mass that carries
        the moment within the radius (the mass there moves no force)."""
        out = np.zeros((len(self.slots), 3))
        for k, s in enumerate(self.slots):
            (m_lo, m_hi), (_, r_hi) = s.mass, s.radius
            mu, mv, m = (float(y[self.index(k, w)]) for w in ("mu", "mv", "m"))
            if math.hypot(mu, mv) < _NOISE:  # round-off of a counterweight that is not wanted
                mu = mv = 0.0
                m = m if m >= _NOISE else 0.0
            rho = m_hi * r_hi * math.hypot(mu, mv)
            m *= m_hi
            if self.pivoted[k]:
                m = max(m, rho / r_hi, m_lo)
            r = rho / m if m > 0 else r_hi
            out[k] = (m, r, math.atan2(mv, mu) if rho > 0 else 0.0)
        return out


def within_bounds(design: np.ndarray, slots: tuple[Any, ...], budget: Budget) -> tuple[np.ndarray, bool]:
    """The design with every bound and budget kept (a rescale of the masses where a solver's tolerance
    overshot a budget), and whether it needed no larger change than 1e-7.

    Parameters
    ----------
    design : ndarray
        (L, 3) mass (kg), radius (m), angle (rad) per link.
    slots : tuple of CounterweightSlot
        The links' bounds.
    budget : Budget
        The totals allowed.
    """
    d = design.copy()
    kept = True
    for k, s in enumerate(slots):
        (m_lo, m_hi), (r_lo, r_hi) = s.mass, s.radius
        m, r = d[k, :2]
        if m > m_hi * (1 + _KEEP) or r > r_hi * (1 + _KEEP) or (m > 0 and r < r_lo * (1 - _KEEP)):
            kept = False
        d[k, 0] = min(max(m, m_lo), m_hi)
        d[k, 1] = min(max(r, r_lo), r_hi)
    total, inertia = float(d[:, 0].sum()), float(np.sum(d[:, 0] * d[:, 1] ** 2))
    over = max(_over(total, budget.mass), _over(inertia, budget.inertia))
    if over > 1:
        kept = kept and over < 1 + _KEEP
        d[:, 0] /= over
    return d, kept


def _over(used: float, allowed: float) -> float:
    """used / allowed, with nothing used of nothing allowed 0 (and something of nothing inf)."""
    if used <= 0:
        return 0.0
    return used / allowed if allowed > 0 else math.inf


def _metric(A: np.ndarray, b: np.ndarray, y: np.ndarray, statistic: str) -> float:
    f = A @ y + b  # (N, c)
    if statistic == "rms":
        return float(np.sqrt(np.mean(np.sum((f - f.mean(axis=0)) ** 2, axis=1))))
    if statistic == "peak":
        return float(np.sqrt(np.max(np.sum((f - f.mean(axis=0)) ** 2, axis=1))))
    return float(np.max(f.max(axis=0) - f.min(axis=0)))


def _least_squares(
    A: np.ndarray, b: np.ndarray, lay: _Layout, budget: Budget
) -> tuple[np.ndarray | None, float]:
    """The least-squares optimum as a design, if it is unique and keeps every bound and budget."""
    N, c, n = A.shape
    Am = (A - A.mean(axis=0)).reshape(N * c, n)
    bm = (b - b.mean(axis=0)).reshape(N * c)
    y, *_ = np.linalg.lstsq(Am, -bm, rcond=None)
    used = np.flatnonzero(np.any(Am != 0, axis=0))
    if used.size and np.linalg.matrix_rank(Am[:, used]) < used.size:
        return None, math.nan  # ties: the cone programme takes the lightest of them
    design, kept = within_bounds(lay.design(y), lay.slots, budget)
    return (design, _metric(A, b, y, "rms")) if kept else (None, math.nan)


def force_optimum(
    ev: Any, slots: tuple[Any, ...], quantity: str, statistic: str, budget: Budget
) -> ForceSolution:
    """The counterweights minimising a force metric within every bound and budget, the lightest among
    those within ``budget.slack`` of the optimum.

    Parameters
    ----------
    ev : Evaluator
        The linear maps.
    slots : tuple of CounterweightSlot
        The links and their bounds (kg, m).
    quantity : {"shaking_force", "floor_force"}
        The force.
    statistic : {"rms", "peak", "range"}
        How its fluctuation is measured (:mod:`~mechdyn.balance.objectives`).
    budget : Budget
        Total mass (kg) and rotary inertia (kg·m²) allowed, and the slack traded for less mass.

    Returns
    -------
    ForceSolution

    Notes
    -----
    Least squares, or a cone programme by Kelley's cutting planes (:mod:`~mechdyn.balance.conic`);
    module docstring.
    """
    piv = pivoted(ev.infl)
    cols, base = _force(ev, quantity)
    rocks = bool(
        np.any(np.abs(cols[:, :, PER_LINK - 1 :: PER_LINK]) > 1e-12 * max(float(np.abs(base).max()), 1.0))
    )
    lay = _Layout(tuple(slots), piv, math.isfinite(budget.inertia) or rocks)
    A = cols @ lay.coefficients()  # (N, c, n)
    scale = float(np.sqrt(np.max(np.sum((base - base.mean(axis=0)) ** 2, axis=1)))) or 1.0
    A, b = A / scale, base / scale
    name = f"{quantity}_{statistic}"

    def value(design: np.ndarray) -> float:  # of the point masses themselves, scaled
        return float(ev.metrics(ev.coefficients(design), [name])[name]) / scale

    if statistic == "rms":
        design, optimum = _least_squares(A, b, lay, budget)
        if design is not None and value(design) <= optimum * (1 + GAP) + TIE:  # scaled: TIE absolute too
            return ForceSolution(design, True, optimum * scale, "least squares (numpy.linalg.lstsq)")
    y, bound = _cones(A, b, lay, statistic, budget)
    d, kept = within_bounds(lay.design(y), lay.slots, budget)
    # a rocking link's inertia is a variable I ≥ ρ²/m of the programme; point masses give I = ρ²/m,
    # so the design is the optimum only where the programme took that (it did not want more inertia)
    kept = kept and value(d) <= bound * (1 + budget.slack + TIE) * (1 + GAP) + TIE
    return ForceSolution(
        d,
        kept,
        bound * scale,
        f"cone programme by cutting planes (scipy linprog, HiGHS), to {GAP:.0e} of its lower bound",
    )


def _cones(
    A: np.ndarray, b: np.ndarray, lay: _Layout, statistic: str, budget: Budget
) -> tuple[np.ndarray, float]:
    """Scaled variables of the lightest design within the slack of the optimum, and the certified
    lower bound of the metric (both scaled)."""
    N, c, n = A.shape
    bounds: list[tuple[float | None, float | None]] = list(lay.bounds())
    L = len(lay.slots)
    extra = 1 if statistic != "range" else 2 * c + 1
    nz = n + extra
    t = nz - 1
    bounds += [(None, None)] * (extra - 1) + [(0.0, None)]

    def pad(G: np.ndarray) -> np.ndarray:
        return np.concatenate([G, np.zeros((*G.shape[:-1], extra))], axis=-1)

    groups, start = [], []
    # each counterweight's mass moment within its mass times its largest radius: ‖(mu, mv)‖ ≤ m
    G = np.zeros((L, 2, nz))
    a = np.zeros((L, nz))
    for k in range(L):
        G[k, 0, lay.index(k, "mu")] = G[k, 1, lay.index(k, "mv")] = 1.0
        a[k, lay.index(k, "m")] = 1.0
    groups.append(Cones(G, np.zeros((L, 2)), a, np.zeros(L)))
    start.append(directions(2))
    rows, rhs = [], []
    mass_row = np.zeros(nz)
    for k, s in enumerate(lay.slots):
        mass_row[lay.index(k, "m")] = s.mass[1]
    heaviest = max(float(mass_row.sum()), 1e-300)
    if math.isfinite(budget.mass):  # rows scaled by the largest possible total, not the budget (≥ 0)
        rows.append(mass_row / heaviest)
        rhs.append(budget.mass / heaviest)
    if lay.inertia:  # I ≥ ρ²/m: ‖(2 mu, 2 mv, I − m)‖ ≤ I + m; I ≤ m (r ≤ r_max); Σ I within budget
        G = np.zeros((L, 3, nz))
        a = np.zeros((L, nz))
        row = np.zeros(nz)
        for k, s in enumerate(lay.slots):
            i, m = lay.index(k, "I"), lay.index(k, "m")
            G[k, 0, lay.index(k, "mu")] = G[k, 1, lay.index(k, "mv")] = 2.0
            G[k, 2, i], G[k, 2, m] = 1.0, -1.0
            a[k, i] = a[k, m] = 1.0
            le = np.zeros(nz)
            le[i], le[m] = 1.0, -1.0
            rows.append(le)
            rhs.append(0.0)
            row[i] = s.mass[1] * s.radius[1] ** 2
        groups.append(Cones(G, np.zeros((L, 3)), a, np.zeros(L)))
        start.append(directions(3))
        if math.isfinite(budget.inertia):
            most = max(float(row.sum()), 1e-300)
            rows.append(row / most)
            rhs.append(budget.inertia / most)
    mean = A.mean(axis=0)
    Am, bm = A - mean, b - b.mean(axis=0)
    c0 = 0.0
    if statistic == "peak":  # ‖F(θ_i) − F̄‖ ≤ t at every crank angle
        e_t = np.zeros(nz)
        e_t[t] = 1.0
        groups.append(Cones(pad(Am), bm, np.tile(e_t, (N, 1)), np.zeros(N)))
        start.append(directions(c, 4))
    elif statistic == "rms":  # ‖A y + b‖² = ‖R y + w‖² + c0, R from the eigenvectors of AᵀA
        S = Am.reshape(N * c, n)
        lam, V = np.linalg.eigh(S.T @ S)
        keep = lam > 1e-12 * max(float(lam.max()), 1e-300)
        R = np.sqrt(lam[keep])[:, None] * V[:, keep].T
        w = (V[:, keep].T @ (S.T @ bm.reshape(N * c))) / np.sqrt(lam[keep])
        if not keep.any():  # no counterweight moves the force: t ≥ 0 alone
            R, w, keep = np.zeros((1, n)), np.zeros(1), np.ones(1, dtype=bool)
        c0 = max(float(bm.ravel() @ bm.ravel() - w @ w), 0.0)
        e_t = np.zeros(nz)
        e_t[t] = 1.0
        groups.append(Cones(pad(R)[None], w[None], e_t[None], np.zeros(1)))
        start.append(directions(int(keep.sum())))
    else:  # range: hi_j ≥ F_ij ≥ lo_j, t ≥ hi_j − lo_j
        for j in range(c):
            up = np.zeros((N, nz))
            up[:, :n], up[:, n + j] = A[:, j, :], -1.0
            lo = np.zeros((N, nz))
            lo[:, :n], lo[:, n + c + j] = -A[:, j, :], 1.0
            span = np.zeros((1, nz))
            span[0, n + j], span[0, n + c + j], span[0, t] = 1.0, -1.0, -1.0
            rows += [*up, *lo, *span]
            rhs += [*(-b[:, j]), *b[:, j], 0.0]
    cp = CuttingPlanes(
        bounds,
        groups,
        start,
        np.array(rows).reshape(-1, nz) if rows else None,
        np.array(rhs) if rhs else None,
    )
    cost = np.zeros(nz)
    cost[t] = 1.0
    rms = statistic == "rms"

    def smooth(cost: np.ndarray | None = None, cap: float | None = None, y0: Any = None) -> np.ndarray:
        """An RMS programme's solution by SLSQP, its cones touched there: Kelley is slow on a smooth
        objective, and from there its first bound is tight."""
        lin = np.array(rows)[:, :n] if rows else np.zeros((0, n))
        y = _smooth_rms(R, w, lay, bounds[:n], lin, np.array(rhs), cost, cap, y0)
        z = np.r_[y, np.zeros(extra - 1), np.linalg.norm(R @ y + w)]
        cp.touch(z)
        return z

    first = cp.minimise(cost, smooth() if rms else None)

    def value(y: np.ndarray) -> float:
        return _metric(A, b, y[:n], statistic)

    def as_metric(s: float) -> float:
        return math.sqrt((s * s + c0) / N) if statistic == "rms" else s

    bound = as_metric(first.bound)
    # the lightest within the slack: t capped at the first design's value (the problem is scaled to
    # its value without counterweights, so TIE is also an absolute tolerance)
    reached = value(first.z)
    target = reached * (1 + budget.slack + TIE) + TIE
    if rms:  # rms² N = s² + c0: the cap on s without the cancellation of c0
        s1 = float(np.linalg.norm(R @ first.z[:n] + w))
        top = math.sqrt(s1 * s1 + N * (target - reached) * (target + reached))
    else:
        top = target
    cap = np.zeros(nz)
    cap[t] = 1.0
    cp.add(cap, np.array([top]))
    lightest = mass_row / heaviest
    try:
        second = cp.minimise(lightest, smooth(lightest[:n], top, first.z[:n]) if rms else None)
    except MechdynError:  # the cap leaves too thin a set for HiGHS's tolerances: keep the optimum
        return first.z[:n], bound
    return second.z[:n], bound


def _smooth_rms(
    R: np.ndarray,
    w: np.ndarray,
    lay: _Layout,
    bounds: list[Any],
    rows: np.ndarray,
    rhs: np.ndarray,
    cost: np.ndarray | None = None,
    cap: float | None = None,
    start: np.ndarray | None = None,
) -> np.ndarray:
    """min ‖R y + w‖² (or, given ``cost`` and ``cap``, min cost·y with ‖R y + w‖ ≤ cap) over the
    cones written smooth (m² ≥ mu² + mv², I m ≥ mu² + mv², with m, I ≥ 0 by their bounds) and the
    linear rows, by SLSQP: a start for the cuts, which certify it."""
    from scipy.optimize import minimize

    L = len(lay.slots)
    iu = np.array([lay.index(k, "mu") for k in range(L)])
    iv = np.array([lay.index(k, "mv") for k in range(L)])
    im = np.array([lay.index(k, "m") for k in range(L)])
    ii = np.array([lay.index(k, "I") for k in range(L)]) if lay.inertia else im

    def cone(y: np.ndarray) -> np.ndarray:
        rho2 = y[iu] ** 2 + y[iv] ** 2
        out = [y[im] ** 2 - rho2]
        if lay.inertia:
            out.append(y[ii] * y[im] - rho2)
        return np.concatenate(out)

    def cone_jac(y: np.ndarray) -> np.ndarray:
        J = np.zeros((L * (2 if lay.inertia else 1), y.size))
        k = np.arange(L)
        J[k, iu], J[k, iv], J[k, im] = -2 * y[iu], -2 * y[iv], 2 * y[im]
        if lay.inertia:
            J[L + k, iu], J[L + k, iv] = -2 * y[iu], -2 * y[iv]
            J[L + k, im], J[L + k, ii] = y[ii], y[im]
        return J

    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    if start is None:
        start, *_ = np.linalg.lstsq(R, -w, rcond=None)
        start = np.clip(start, lo, hi)
        start[im] = np.clip(np.maximum(start[im], np.hypot(start[iu], start[iv])), lo[im], hi[im])
        if lay.inertia:
            start[ii] = np.clip(start[im], lo[ii], hi[ii])
    unit = max(float(np.sum((R @ start + w) ** 2)), 1e-300)  # the objective O(1) for SLSQP's ftol
    constraints: list[dict[str, Any]] = [{"type": "ineq", "fun": cone, "jac": cone_jac}]
    if rows.size:
        constraints.append({"type": "ineq", "fun": lambda y: rhs - rows @ y, "jac": lambda y: -rows})
    if cost is None:
        res = minimize(
            lambda y: float(np.sum((R @ y + w) ** 2)) / unit,
            start,
            jac=lambda y: 2 * R.T @ (R @ y + w) / unit,
            method="SLSQP",
            bounds=list(zip(lo, hi, strict=True)),
            constraints=constraints,
            options={"maxiter": 200, "ftol": 1e-14},
        )
    else:
        top = float(cap if cap is not None else np.inf)
        constraints.append(
            {
                "type": "ineq",
                "fun": lambda y: np.atleast_1d(top * top - np.sum((R @ y + w) ** 2)),
                "jac": lambda y: np.atleast_2d(-2 * R.T @ (R @ y + w)),
            }
        )
        res = minimize(
            lambda y: float(cost @ y),
            start,
            jac=lambda y: cost,
            method="SLSQP",
            bounds=list(zip(lo, hi, strict=True)),
            constraints=constraints,
            options={"maxiter": 200, "ftol": 1e-14},
        )
    return np.clip(np.asarray(res.x), lo, hi)
