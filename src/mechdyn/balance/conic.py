"""Second-order cone programmes by cutting planes: Kelley's method on HiGHS linear programmes.

The counterweight problems are small cone programmes: minimise c·z subject to linear constraints and
cones ‖G_k z + h_k‖₂ ≤ a_k·z + e_k (a Euclidean peak over the crank cycle, a counterweight's mass
moment within its mass times its largest radius, its rotary inertia against its mass). SciPy has no
cone solver, but HiGHS solves linear programmes exactly and fast, and a cone is the intersection of
its tangent half-spaces

    u·(G_k z + h_k) ≤ a_k·z + e_k   for every unit vector u.

:class:`CuttingPlanes` starts each cone with a few of them, solves the linear programme
(:func:`scipy.optimize.linprog`, HiGHS), adds for every cone the solution violates the half-space
through the violating point (u = (G_k z + h_k)/‖G_k z + h_k‖), and repeats until no cone is violated
by more than a tolerance (J. E. Kelley, "The cutting-plane method for solving convex programs",
J. SIAM 8 (1960) 703–712). Every half-space holds at every feasible point, so each programme's value
is a lower bound of the cone programme's: the gap to the value at the solution found certifies how
near the optimum it is. Cuts stay for the next objective over the same cones (a lexicographic second
stage starts where the first ended).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mechdyn.errors import MechdynError

__all__ = ["Cones", "CuttingPlanes", "Solution", "directions"]

TOLERANCE = 1e-9
"""Largest violation of a cone accepted, in the units of the problem (made O(1) by the caller)."""

ROUNDS = 200
"""Most linear programmes one :meth:`CuttingPlanes.minimise` solves."""

_HIGHS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}


def directions(d: int, n: int = 8) -> np.ndarray:
    """(P, d) unit vectors to start a cone of dimension ``d`` with: ``n`` at equal angles in the plane,
    ±e_i otherwise (the cuts add the rest where they are needed).

    Parameters
    ----------
    d : int
        The cone's dimension (count).
    n : int
        Directions in the plane (count, at least 3).
    """
    if d == 2:
        a = 2 * np.pi * np.arange(n) / n
        return np.column_stack([np.cos(a), np.sin(a)])
    return np.vstack([np.eye(d), -np.eye(d)])


@dataclass(frozen=True)
class Cones:
    """K cones of one dimension d over n variables: ‖G_k z + h_k‖₂ ≤ a_k·z + e_k.

    Attributes
    ----------
    G : ndarray
        (K, d, n).
    h : ndarray
        (K, d).
    a : ndarray
        (K, n).
    e : ndarray
        (K,).
    """

    G: np.ndarray
    h: np.ndarray
    a: np.ndarray
    e: np.ndarray

    def violation(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(K,) ‖G_k z + h_k‖ − (a_k·z + e_k), and (K, d) the unit vectors of G_k z + h_k."""
        v = np.einsum("kdn,n->kd", self.G, z) + self.h
        norm = np.linalg.norm(v, axis=1)
        u = np.zeros_like(v)
        u[:, 0] = 1.0  # any direction cuts off a point whose cone has a negative height
        big = norm > 0
        u[big] = v[big] / norm[big, None]
        return norm - (self.a @ z + self.e), u

    def cuts(self, which: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Half-spaces (rows, right-hand sides) of cones ``which`` (M,) along unit vectors ``u`` (M, d)."""
        rows = np.einsum("md,mdn->mn", u, self.G[which]) - self.a[which]
        return rows, self.e[which] - np.einsum("md,md->m", u, self.h[which])


@dataclass(frozen=True)
class Solution:
    """What one :meth:`CuttingPlanes.minimise` found.

    Attributes
    ----------
    z : ndarray
        The last linear programme's solution.
    bound : float
        Its value: a lower bound of the cone programme's.
    violation : float
        Largest violation of a cone at ``z`` (≤ the tolerance when converged).
    rounds : int
        Linear programmes solved.
    """

    z: np.ndarray
    bound: float
    violation: float
    rounds: int


class CuttingPlanes:
    """Cone programmes over one set of variables, linear constraints and cones, by Kelley's cuts.

    Parameters
    ----------
    bounds : sequence of (low, high)
        Of each variable (None for no bound); the cones' variables should be bounded.
    cones : sequence of Cones
        The cones.
    start : sequence of ndarray
        (P, d) unit vectors each group of cones starts with (:func:`directions`).
    A_ub, b_ub : ndarray, optional
        Linear constraints A z ≤ b.
    tolerance : float
        Largest violation of a cone accepted.
    """

    def __init__(
        self,
        bounds: Sequence[tuple[float | None, float | None]],
        cones: Sequence[Cones],
        start: Sequence[np.ndarray],
        A_ub: np.ndarray | None = None,
        b_ub: np.ndarray | None = None,
        tolerance: float = TOLERANCE,
    ) -> None:
        self.bounds = list(bounds)
        self.cones = list(cones)
        self.tolerance = tolerance
        n = len(self.bounds)
        self._rows: list[np.ndarray] = [np.zeros((0, n))]
        self._rhs: list[np.ndarray] = [np.zeros(0)]
        if A_ub is not None and b_ub is not None:
            self.add(np.asarray(A_ub, dtype=float), np.asarray(b_ub, dtype=float))
        for group, u in zip(self.cones, start, strict=True):
            K, P = group.h.shape[0], u.shape[0]
            rows, rhs = group.cuts(np.repeat(np.arange(K), P), np.tile(u, (K, 1)))
            self.add(rows, rhs)

    def add(self, rows: np.ndarray, rhs: np.ndarray) -> None:
        """Add linear constraints rows · z ≤ rhs (kept for every later objective)."""
        self._rows.append(np.atleast_2d(rows))
        self._rhs.append(np.atleast_1d(rhs))

    def violation(self, z: np.ndarray) -> float:
        """Largest violation of a cone, a linear constraint or a bound at ``z``."""
        worst = max((float(g.violation(z)[0].max(initial=0.0)) for g in self.cones), default=0.0)
        worst = max(worst, float(np.max(np.vstack(self._rows) @ z - np.concatenate(self._rhs), initial=0.0)))
        for x, (lo, hi) in zip(z, self.bounds, strict=True):
            worst = max(worst, (lo - x) if lo is not None else 0.0, (x - hi) if hi is not None else 0.0)
        return worst

    def touch(self, z: np.ndarray) -> None:
        """Add every cone's tangent half-space at ``z`` (a good point found otherwise: the cuts there
        make the next bound tight)."""
        for group in self.cones:
            _, u = group.violation(z)
            self.add(*group.cuts(np.arange(u.shape[0]), u))

    def minimise(self, c: np.ndarray, incumbent: np.ndarray | None = None) -> Solution:
        """Minimise c·z over the cones and the constraints so far.

        Parameters
        ----------
        c : ndarray
            (n,) the objective's coefficients.
        incumbent : ndarray, optional
            (n,) a point that keeps every cone (to the tolerance), found otherwise: returned as soon
            as a programme's bound comes within the tolerance of its value.

        Returns
        -------
        Solution

        Raises
        ------
        MechdynError
            When a linear programme fails (infeasible constraints), or the cuts do not converge.
        """
        from scipy.optimize import linprog

        if incumbent is not None and self.violation(incumbent) > self.tolerance:
            incumbent = None
        worst = np.inf
        for rounds in range(1, ROUNDS + 1):
            res = linprog(
                c,
                A_ub=np.vstack(self._rows),
                b_ub=np.concatenate(self._rhs),
                bounds=self.bounds,
                method="highs",
                options=_HIGHS,
            )
            if not res.success:
                raise MechdynError(f"the counterweight linear programme failed: {res.message}")
            if incumbent is not None and float(c @ incumbent) - float(res.fun) <= self.tolerance:
                return Solution(incumbent, float(res.fun), self.violation(incumbent), rounds)
            z = np.asarray(res.x)
            worst = 0.0
            for group in self.cones:
                viol, u = group.violation(z)
                worst = max(worst, float(viol.max(initial=0.0)))
                bad = np.flatnonzero(viol > self.tolerance)
                if bad.size:
                    self.add(*group.cuts(bad, u[bad]))
            if worst <= self.tolerance:
                return Solution(z, float(res.fun), worst, rounds)
        raise MechdynError(
            f"the counterweight cone programme did not converge in {ROUNDS} linear programmes "
            f"(largest violation {worst:.2g})"
        )
