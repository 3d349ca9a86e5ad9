"""The event-located flow of a drivetrain with backlash over its period, and its Jacobian.

About the nominal rotation at a constant speed (:mod:`.periodic`) each mesh j with backlash b_j is in
one of three contact modes, a discrete state as in :func:`mechdyn.gear_dynamics.simulate`:
drive-side contact (force k_j x_r + c_j ẋ_r), the gap (no force) or back-side contact
(k_j (x_r + b_j) + c_j ẋ_r), x_r = g_j · x − e_j(t): the contact law :func:`._contact.mesh_force`,
the one the time integration uses. The mode changes where x_r crosses 0 or −b_j
in the sense that leaves it: drive → gap where x_r falls through 0, gap → drive where it rises
through 0, gap → back where it falls through −b_j, back → gap where it rises through −b_j.

The flow is integrated by :func:`scipy.integrate.solve_ivp` (DOP853) between consecutive corners of
the stiffness and error profiles (where the error's rate jumps) and, inside each piece, up to the
next contact change, located as a terminal, direction-aware event and restarted there in the new
mode. The variational equations Ẏ = A(t) Y ride along; at a contact change the state is continuous
but the vector field jumps (the spring force does not, the mesh's damping force c_j ẋ_r does), so
the sensitivity is mapped by the saltation matrix of the switching surface h(t, y) = g_j · x −
e_j(t) (+ b_j) = 0,

    Y⁺ = S Y⁻,  S = I + (f⁺ − f⁻) nᵀ / (nᵀ f⁻ + ∂h/∂t),  n = ∂h/∂y = [g_j; 0],  ∂h/∂t = −ė_j,

(Aizerman & Gantmacher, *Prikl. Mat. Mekh.* 22 (1958) 447–457; Leine & Nijmeijer, *Dynamics and
Bifurcations of Non-Smooth Mechanical Systems*, Springer 2004, §7.2), so that the Jacobian of the
period map (and the Floquet multipliers of a non-smooth orbit) are exact up to the integration error.
Here nᵀ f⁻ + ∂h/∂t = ẋ_r, and f⁺ − f⁻ = ∓[0; M⁻¹ g_j c_j ẋ_r]: S differs from I by −Δc_j M⁻¹ g_j g_jᵀ
in its velocity-position block (Δc_j = +c_j entering contact, −c_j leaving), finite even at grazing.
Fixed-time discontinuities (the profile corners) need no saltation (∂h/∂y = 0 there).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.gear_dynamics._contact import BACK, DRIVE, GAP, NO_BACKLASH, announce, mesh_forces
from mechdyn.gear_dynamics.periodic import LinearPeriodic, PeriodPlan

#: Most contact changes per period before the flow gives up (a chattering contact, a trial state of
#: Newton's method far off).
MAX_CHANGES_PER_PERIOD = 400


class FlowError(RuntimeError):
    """The nonlinear flow could not be integrated (a trial state of Newton's method far off)."""


@dataclass(frozen=True)
class Crossing:
    """A contact change: time (s), mesh index, old and new mode."""

    t: float
    mesh: int
    old: int
    new: int


def corners(lin: LinearPeriodic, plan: PeriodPlan) -> np.ndarray:
    """Fractions of the period, 0 … 1, at the corners of every varying mesh's profile and error (the
    union over the meshes: inside a piece each mesh's stiffness and error are linear in time)."""
    cuts = [np.array([0.0, 1.0])]
    for p, e, o in zip(lin.profiles, lin.errors, plan.orders, strict=True):
        if int(o) and (np.ptp(p) > 0 or np.ptp(e) > 0):
            n = int(o) * max(p.size, e.size)
            cuts.append(np.arange(n) / n)
    allc = np.sort(np.concatenate(cuts))
    keep = np.append(True, np.diff(allc) > 1e-12)
    return allc[keep]


class NonsmoothFlow:
    """The backlash flow of ``lin`` at reference speed ``speed`` (rad/s).

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    speed : float
        Reference speed Ω, rad/s.
    rtol : float
        Relative tolerance of the integration, dimensionless.
    saltation : bool
        Map the sensitivity by the saltation matrix at contact changes (False only to show what it
        does).
    """

    def __init__(
        self, lin: LinearPeriodic, plan: PeriodPlan, speed: float, rtol: float = 1e-10, saltation: bool = True
    ) -> None:
        self.lin, self.plan, self.speed, self.rtol, self.saltation = lin, plan, speed, rtol, saltation
        m = lin.m
        self.m, self.d = m, 2 * m
        self.T = plan.period(speed)
        f0 = plan.fundamental * speed
        Minv = np.linalg.inv(lin.M)
        self.G = lin.G
        self.MinvG = Minv @ lin.G.T  # (m, J)
        # the linear part without the meshes (their stiffness and damping switch with the contact)
        self.A_v = -Minv @ (lin.C - (lin.G.T * lin.mesh_damping) @ lin.G)
        self.B_x = -Minv @ lin.K
        self.base = Minv @ lin.force(speed)
        self.gap = np.array([np.inf if b is None else float(b) for b in lin.backlash])
        self.has_gap = np.isfinite(self.gap)
        self.law_gap = np.where(self.has_gap, self.gap, NO_BACKLASH)  # the contact law's backlash
        announce()
        self.c = np.ascontiguousarray(lin.mesh_damping, float)
        self.kbar = np.asarray(lin.mean_stiffness, float)
        self.cuts = corners(lin, plan)
        self._rate = [int(o) * int(s) * f0 for o, s in zip(plan.orders, plan.signs, strict=True)]

    # -- the pieces ------------------------------------------------------------------------------
    def piece(self, a: float, b: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Per mesh, k(t) = K0 + K1 t (N/m) and e(t) = E0 + E1 t (m) on the piece [a, b] (s)."""
        lin = self.lin
        J = len(lin.names)
        K0, K1, E0, E1 = self.kbar.copy(), np.zeros(J), np.zeros(J), np.zeros(J)
        mid = 0.5 * (a + b)
        for j in range(J):
            rate = self._rate[j]
            if not rate:
                continue
            p, e = lin.profiles[j], lin.errors[j]
            for samples, is_k in ((p, True), (e, False)):
                P = samples.size
                base = np.floor(rate * mid * P)
                i = int(base) % P
                lo, hi = samples[i], samples[(i + 1) % P]
                slope = (hi - lo) * P * rate  # per second
                v0 = lo - (hi - lo) * base  # value at t = 0 of this piece's line: lo + (u − base)(hi − lo)
                if is_k:
                    K0[j], K1[j] = self.kbar[j] * v0, self.kbar[j] * slope
                else:
                    E0[j], E1[j] = v0, slope
        return K0, K1, E0, E1

    def modes(self, t: float, y: np.ndarray, E0: np.ndarray, E1: np.ndarray) -> np.ndarray:
        """The contact modes of the state y at t: drive where x_r > 0 (and without backlash), back where
        x_r < −b, else the gap (a state on a boundary: the side its relative velocity heads to)."""
        m = self.m
        xr = self.G @ y[:m] - (E0 + E1 * t)
        vr = self.G @ y[m : 2 * m] - E1
        mode = np.full(xr.size, GAP, dtype=int)
        mode[(xr > 0) | ((xr == 0) & (vr > 0)) | ~self.has_gap] = DRIVE
        mode[self.has_gap & ((xr < -self.gap) | ((xr == -self.gap) & (vr < 0)))] = BACK
        return mode

    def field(
        self, t: float, y: np.ndarray, mode: np.ndarray, coeffs: tuple[np.ndarray, ...], variational: bool
    ) -> np.ndarray:
        """dy/dt in the given modes (the state, and with ``variational`` the d × d sensitivity)."""
        K0, K1, E0, E1 = coeffs
        m, d = self.m, self.d
        x, v = y[:m], y[m:d]
        xr = self.G @ x - (E0 + E1 * t)
        kt = K0 + K1 * t
        fm, _, active = mesh_forces(kt, self.c, xr, self.G @ v - E1, self.law_gap, mode)
        a = self.base + self.B_x @ x + self.A_v @ v - self.MinvG @ fm
        if not variational:
            return np.concatenate([v, a])
        k, c = kt * active, self.c * active  # ∂f/∂x_r and ∂f/∂ẋ_r of the law
        Y = y[d:].reshape(d, d)
        lower = np.concatenate(
            [self.B_x - (self.MinvG * k) @ self.G, self.A_v - (self.MinvG * c) @ self.G], 1
        )
        dY = np.concatenate([Y[m:], lower @ Y])
        return np.concatenate([v, a, dY.ravel()])

    def _events(self, mode: np.ndarray, E0: np.ndarray, E1: np.ndarray) -> list[tuple[Any, int, int]]:
        """(event function, mesh, new mode) for every change the present modes allow."""
        out: list[tuple[Any, int, int]] = []
        m = self.m
        for j in np.flatnonzero(self.has_gap):
            g, e0, e1, b = self.G[j], float(E0[j]), float(E1[j]), float(self.gap[j])

            def make(
                offset: float, direction: float, g: np.ndarray = g, e0: float = e0, e1: float = e1
            ) -> Any:
                def ev(t: float, y: np.ndarray) -> float:
                    return float(g @ y[:m]) - (e0 + e1 * t) + offset

                ev.terminal = True  # type: ignore[attr-defined]
                ev.direction = direction  # type: ignore[attr-defined]
                return ev

            if mode[j] == DRIVE:
                out.append((make(0.0, -1.0), int(j), GAP))
            elif mode[j] == BACK:
                out.append((make(b, 1.0), int(j), GAP))
            else:
                out.append((make(0.0, 1.0), int(j), DRIVE))
                out.append((make(b, -1.0), int(j), BACK))
        return out

    def saltation_matrix(
        self,
        t: float,
        y: np.ndarray,
        j: int,
        old: np.ndarray,
        new: np.ndarray,
        coeffs: tuple[np.ndarray, ...],
    ) -> np.ndarray:
        """S = I + (f⁺ − f⁻) nᵀ / (nᵀ f⁻ + ∂h/∂t) at a change of mesh j's mode from ``old`` to ``new``."""
        d, m = self.d, self.m
        f_minus = self.field(t, y[:d], old, coeffs, False)
        f_plus = self.field(t, y[:d], new, coeffs, False)
        n = np.concatenate([self.G[j], np.zeros(m)])
        dhdt = -float(coeffs[3][j])
        den = float(n @ f_minus) + dhdt  # the relative velocity ẋ_r at the crossing
        S = np.eye(d)
        if den != 0.0:
            S += np.outer(f_plus - f_minus, n) / den
        else:  # grazing: the limit, −Δc M⁻¹ g gᵀ (see the module docstring)
            dc = self.c[j] * ((new[j] != GAP) - (old[j] != GAP))
            S[m:, :m] -= dc * np.outer(self.MinvG[:, j], self.G[j])
        return S

    # -- the flow ----------------------------------------------------------------------------------
    def run(
        self,
        y0: np.ndarray,
        t_eval: np.ndarray | None = None,
        periods: int = 1,
        variational: bool = True,
    ) -> tuple[np.ndarray, np.ndarray, list[Crossing]]:
        """Integrate ``periods`` periods from y0 at t = 0.

        Parameters
        ----------
        y0 : ndarray
            (2m,) the state [x, ẋ], rad and rad/s.
        t_eval : ndarray, optional
            Fractions of the last period at which to sample the state, ascending in [0, 1).
        periods : int
            Periods to integrate, a count.
        variational : bool
            Carry the sensitivity ∂y(t)/∂y0.

        Returns
        -------
        samples : ndarray
            (2m, N) states at ``t_eval``.
        end : ndarray
            The state at the end (2m), followed by the d × d sensitivity (row-major) with
            ``variational``.
        crossings : list of Crossing
            The contact changes in order.
        """
        from scipy.integrate import solve_ivp

        d, T = self.d, self.T
        y0 = np.asarray(y0, float)
        if not np.isfinite(y0).all():
            raise FlowError("the state is not finite")
        y = np.concatenate([y0, np.eye(d).ravel()]) if variational else y0.copy()
        scale = max(float(np.abs(y0).max()), 1e-12)
        atol = np.full(y.size, 1e-14 * scale)
        atol[d:] = 1e-12
        wanted = np.zeros(0) if t_eval is None else (periods - 1 + np.asarray(t_eval, float)) * T
        w = 0
        samples: list[np.ndarray] = []
        crossings: list[Crossing] = []
        mode: np.ndarray | None = None
        limit = MAX_CHANGES_PER_PERIOD * periods
        for k in range(periods):
            for a_frac, b_frac in zip(self.cuts[:-1], self.cuts[1:], strict=True):
                a, b = (k + a_frac) * T, (k + b_frac) * T
                coeffs = self.piece(a, b)
                if mode is None:
                    mode = self.modes(a, y, coeffs[2], coeffs[3])
                t = a
                while b - t > 1e-13 * T:
                    w_end = int(np.searchsorted(wanted, b, side="left"))
                    pts = np.clip(wanted[w:w_end], t, b)
                    events = self._events(mode, coeffs[2], coeffs[3])
                    md = mode.copy()

                    def fun(tt: float, yy: np.ndarray, md: np.ndarray = md, cf: Any = coeffs) -> np.ndarray:
                        return self.field(tt, yy, md, cf, variational)

                    with np.errstate(over="ignore", invalid="ignore"):
                        sol = solve_ivp(
                            fun,
                            (t, b),
                            y,
                            method="DOP853",
                            rtol=self.rtol,
                            atol=atol,
                            t_eval=np.append(pts, b),
                            events=[e[0] for e in events] or None,
                        )
                    if sol.status < 0 or not np.isfinite(sol.y).all():
                        raise FlowError(sol.message)
                    got = int(np.count_nonzero(sol.t < b))
                    if got:
                        samples.append(sol.y[:d, :got])
                    w += got
                    if sol.status == 0:
                        y = sol.y[:, -1]
                        break
                    # the earliest terminal event (solve_ivp stops at the first)
                    hit = [i for i, te in enumerate(sol.t_events) if te.size]
                    i_hit = min(hit, key=lambda i: sol.t_events[i][0])
                    t = float(sol.t_events[i_hit][0])
                    y = np.asarray(sol.y_events[i_hit][0], float).copy()
                    _fn, j, new_mode = events[i_hit]
                    new = mode.copy()
                    new[j] = new_mode
                    if variational and self.saltation:
                        S = self.saltation_matrix(t, y, j, mode, new, coeffs)
                        y[d:] = (S @ y[d:].reshape(d, d)).ravel()
                    crossings.append(Crossing(t, j, int(mode[j]), new_mode))
                    mode = new
                    if len(crossings) > limit:
                        raise FlowError("the contact chatters")
        out = np.concatenate(samples, axis=1) if samples else np.zeros((d, 0))
        return out, y, crossings
