"""Periodic steady state of a geared drivetrain at constant speed, and its sweep over speed.

The reference disk (a motor) turns at exactly Ω — a kinematic input, the usual boundary condition of
a speed sweep — and the loads draw constant torques. About the nominal rigid rotation q = Ω t r the
teeth-in-contact vibration x obeys the linear time-periodic system of :mod:`.floquet`,

    M ẍ + C ẋ + K(t) x = F₀ + Σ_j g_j (k_j(τ_j) e_j(τ_j) + c_j ė_j),  τ_j = z_j θ_a,nominal / (2π),

excited by the static transmission errors e_j and, through the varying stiffness, by the mean load.
Its periodic response comes from

* **harmonic balance** (the fast path): x = Σ_p X_p exp(i p ω₀ t), p = −H … H; the stiffness
  harmonics couple X_p to X_(p − h m_j), so one sparse linear system in the coefficients gives the
  response exactly up to the truncation (Nayfeh & Mook, *Nonlinear Oscillations*, 1979, §5.4, Hill's
  determinant; Blankenship & Kahraman, *J. Sound Vib.* 185 (1995) 743–765 for gear pairs);
* **shooting**: the one-period propagator [[Φ, y_p], [0, 1]] of the forced system (Magnus product or
  solve_ivp, :mod:`.floquet`) and y₀ = (I − Φ)⁻¹ y_p (e.g. Nayfeh & Balachandran, *Applied Nonlinear
  Dynamics*, 1995, §7.1); with backlash the same shooting wrapped in Newton's method on the nonlinear
  flow, integrated from one contact change to the next (located events), its Jacobian from the
  variational equations mapped by the saltation matrix at every contact change
  (:mod:`._nonsmooth`), continued over speed from each solution to the next, up or down
  (``direction``), so that the jump of the softening backlash nonlinearity shows (Kahraman & Singh,
  *J. Sound Vib.* 142 (1990) 49–75).

Several meshes share the common period of their mesh frequencies (the greatest common divisor of
their rational ratios, :func:`.floquet.period_plan`); where it is longer than 64 mesh periods the
dominant mesh's period is used and the others held at their mean stiffness, with a note.

The dynamic factor K_v = max f_j / f_j,static compares with ISO 6336-1's K_v where the gear data
are given (``gear_pairs``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from mechdyn.checks import check_count
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics._cost import check as check_cost
from mechdyn.gear_dynamics._cost import sweep_cost
from mechdyn.gear_dynamics._harmonics import (
    HARMONICS_RTOL,
    MAX_AUTO,
    estimated_error,
    harmonics_for,
    needed_harmonics,
)
from mechdyn.gear_dynamics._nonsmooth import FlowError, NonsmoothFlow
from mechdyn.gear_dynamics._resonance import crossings, iso_note
from mechdyn.gear_dynamics.floquet import (
    UNSTABLE_MARGIN,
    Boundary,
    LinearPeriodic,
    PeriodPlan,
    _check_speed,
    _monodromy,
    _natural_frequencies,
    _spectral,
    _speeds,
    interpolant_harmonics,
    interpolate,
    interpolated_slope,
    ivp_propagators,
    linear_periodic,
    ordered_product,
    period_plan,
    product_harmonics,
    propagators,
    segments,
)
from mechdyn.results import Result, Table

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["SpeedSweepResult", "SteadyState", "speed_sweep", "steady_state"]

Method = Literal["auto", "harmonic_balance", "shooting"]
_METHODS = ("auto", "harmonic_balance", "shooting")
Direction = Literal["up", "down", "both"]
_DIRECTIONS = ("up", "down", "both")
#: A local maximum of a sweep's force amplitude is a resonance where its prominence (the height
#: above the higher of the two minima that separate it from higher ground, as
#: :func:`scipy.signal.find_peaks`) is at least this fraction of the peak's own height.
PEAK_PROMINENCE = 0.02
#: The up and down sweeps differ (a jump, hysteresis) where their force amplitudes differ by more than
#: this fraction of the larger.
HYSTERESIS_RTOL = 0.01
#: A Floquet multiplier is real where its imaginary part is below this fraction of its modulus.
_REAL_RTOL = 1e-9
#: The relative width in speed to which the end of a branch (a jump) is located by bisection.
EDGE_RTOL = 1e-3
#: Runs of :func:`_settle_periods` periods, each followed by Newton, before a speed is given up.
_SETTLE_ROUNDS = 4


# -- harmonic balance ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Balance:
    """The speed-independent part of the harmonic-balance system."""

    H: int
    K_held: np.ndarray  # structure plus every mesh at its mean stiffness, N·m/rad
    varying: tuple[int, ...]  # the meshes whose stiffness varies in the period
    toeplitz: np.ndarray  # (J_v, 2H+1, 2H+1): k̄_j (c_(p − p') − δ) of each varying mesh, N/m
    forcing_orders: tuple[np.ndarray, ...]  # per mesh: global orders p of its error terms
    ke: tuple[np.ndarray, ...]  # per mesh: coefficients of (k e)(τ) at those orders, N
    e: tuple[np.ndarray, ...]  # per mesh: coefficients of e(τ), m


def _balance(lin: LinearPeriodic, plan: PeriodPlan, harmonics: int) -> _Balance:
    top = max(int(plan.orders.max()) if plan.orders.size else 1, 1)
    H = harmonics * top
    p = np.arange(-H, H + 1)
    diff = p[:, None] - p[None, :]
    K_held = lin.K.copy()
    varying, blocks, orders, kes, es = [], [], [], [], []
    for j in range(len(lin.names)):
        o, sgn = int(plan.orders[j]), int(plan.signs[j])
        if o == 0:  # held at its mean stiffness
            K_held += lin.mean_stiffness[j] * np.outer(lin.G[j], lin.G[j])
            orders.append(np.zeros(0, int))
            kes.append(np.zeros(0, complex))
            es.append(np.zeros(0, complex))
            continue
        h = diff // o * sgn
        c = interpolant_harmonics(lin.profiles[j], h.ravel()).reshape(h.shape)
        # Z carries every mesh at k̄ (so that it is regular at p = 0); T the deviation from it
        K_held += lin.mean_stiffness[j] * np.outer(lin.G[j], lin.G[j])
        varying.append(j)
        blocks.append(
            np.where(diff % o == 0, lin.mean_stiffness[j] * c, 0.0) - lin.mean_stiffness[j] * np.eye(p.size)
        )
        he = np.arange(-(H // o), H // o + 1)
        err = lin.errors[j]
        if np.any(err):
            prof = lin.profiles[j]
            if prof.size != err.size:  # the system samples both alike; resample where not
                P = max(prof.size, err.size)
                prof, err = interpolate(prof, np.arange(P) / P), interpolate(err, np.arange(P) / P)
            kes.append(lin.mean_stiffness[j] * product_harmonics(prof, err, he))
            es.append(interpolant_harmonics(err, he))
        else:
            kes.append(np.zeros(he.size, complex))
            es.append(np.zeros(he.size, complex))
        orders.append(he * sgn * o)
    n_p = 2 * H + 1
    toeplitz = np.array(blocks).reshape(len(blocks), n_p, n_p)
    return _Balance(H, K_held, tuple(varying), toeplitz, tuple(orders), tuple(kes), tuple(es))


def _hb_solve(lin: LinearPeriodic, plan: PeriodPlan, bal: _Balance, speed: float) -> np.ndarray:
    """(2H+1, m) complex coefficients X_p, p = −H … H.

    The meshes couple the harmonics only through their deflections Δ_(j,p) = g_j · X_p, so the
    system is condensed onto them: with Z_p = K − (p ω₀)² M + i p ω₀ C (every mesh at its mean
    stiffness), T_j the Toeplitz matrix of k_j − k̄_j and R_p = G Z_p⁻¹ Gᵀ, (I + R T) Δ = G Z⁻¹ F, a
    dense system of J (2H+1) unknowns instead of
    m (2H+1) (the Woodbury identity, e.g. Golub & Van Loan, *Matrix Computations*, 4th ed., §2.1.4);
    then X_p = Z_p⁻¹ (F_p − Σ_j g_j (T Δ)_(j,p)).
    """
    H, m = bal.H, lin.m
    n_p = 2 * H + 1
    w0 = 2 * np.pi * plan.fundamental * speed
    p = np.arange(-H, H + 1)
    Z = (
        bal.K_held[None, :, :]
        - (p * w0)[:, None, None] ** 2 * lin.M[None, :, :]
        + 1j * (p * w0)[:, None, None] * lin.C[None, :, :]
    )
    if lin.idle is not None:  # the rigid angle's mean: nothing depends on it, fix it at 0
        Z[H, lin.idle, lin.idle] = max(float(np.abs(bal.K_held).max()), 1.0)
    F = np.zeros((n_p, m), complex)
    F[H] += lin.force(speed)
    for j in range(len(lin.names)):
        if bal.forcing_orders[j].size == 0:
            continue
        rate = 1j * bal.forcing_orders[j] * w0  # d/dt of exp(i p ω₀ t)
        amp = bal.ke[j] + lin.mesh_damping[j] * rate * bal.e[j]
        F[bal.forcing_orders[j] + H] += np.multiply.outer(amp, lin.G[j])
    Gv = lin.G[list(bal.varying)]  # (J_v, m)
    J = Gv.shape[0]
    rhs = np.concatenate([F[:, :, None], np.broadcast_to(Gv.T, (n_p, m, J))], axis=2)
    sol = np.linalg.solve(Z, rhs)  # (n_p, m, 1 + J): Z⁻¹ F and Z⁻¹ Gᵀ
    if J == 0:
        return sol[:, :, 0]
    ZF, ZG = sol[:, :, 0], sol[:, :, 1:]
    R = np.einsum("im,pmj->pij", Gv, ZG)  # (n_p, J, J)
    # S[(p, i), (q, j)] = δ + R_p[i, j] T_j[p, q]
    S = np.einsum("pij,jpq->piqj", R, bal.toeplitz).reshape(n_p * J, n_p * J)
    S[np.diag_indices_from(S)] += 1.0
    delta = np.linalg.solve(S, (ZF @ Gv.T).ravel()).reshape(n_p, J)
    coupling = np.einsum("jpq,qj->pj", bal.toeplitz, delta)  # (n_p, J): mesh force harmonics, N
    return ZF - np.einsum("pmj,pj->pm", ZG, coupling)


def _series(X: np.ndarray, w0: float, N: int) -> tuple[np.ndarray, np.ndarray]:
    """x(t) and ẋ(t) at t = l T / N from two-sided coefficients (2H+1, m)."""
    H = (X.shape[0] - 1) // 2
    p = np.arange(-H, H + 1)
    if N < 2 * H + 1:  # fewer samples than harmonics: sum directly
        basis = np.exp(2j * np.pi * np.outer(np.arange(N) / N, p))
        return (basis @ X).real, (basis @ (X * (1j * p * w0)[:, None])).real
    full = np.zeros((N, X.shape[1]), complex)
    full[np.mod(p, N)] = X
    x = np.fft.ifft(full, axis=0).real * N
    fullv = np.zeros_like(full)
    fullv[np.mod(p, N)] = X * (1j * p * w0)[:, None]
    v = np.fft.ifft(fullv, axis=0).real * N
    return x, v


# -- mesh forces over one period -----------------------------------------------------------------------
def _mesh_forces(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, t_over_T: np.ndarray, x: np.ndarray, v: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(N, J) mesh forces (N) and deflections δ (m) along the lines of action."""
    f0 = plan.fundamental * speed
    J = len(lin.names)
    force = np.empty((t_over_T.size, J))
    delta = x @ lin.G.T
    rate = v @ lin.G.T
    for j in range(J):
        o = int(plan.orders[j])
        tau = plan.signs[j] * o * t_over_T
        k: Any
        e: Any
        e_dot: Any
        if o:
            k = lin.mean_stiffness[j] * interpolate(lin.profiles[j], tau)
            e = interpolate(lin.errors[j], tau)
            e_dot = interpolated_slope(lin.errors[j], tau) * plan.signs[j] * o * f0
        else:
            k, e, e_dot = lin.mean_stiffness[j], 0.0, 0.0
        x_rel = delta[:, j] - e
        b = lin.backlash[j]
        if b is None:
            h, contact = x_rel, np.ones(x_rel.shape, bool)
        else:
            contact = (x_rel > 0) | (x_rel < -b)
            h = np.where(x_rel > 0, x_rel, np.where(x_rel < -b, x_rel + b, 0.0))
        force[:, j] = k * h + lin.mesh_damping[j] * (rate[:, j] - e_dot) * contact
    return force, delta


def _grid(lin: LinearPeriodic, plan: PeriodPlan, H: int) -> int:
    """Time samples per period: resolve the profiles (4 per sample interval) and the harmonics."""
    need = [4 * p.size * int(o) for p, o in zip(lin.profiles, plan.orders, strict=True) if o]
    return int(max([2 * H + 2, 256, *need]))


# -- shooting ------------------------------------------------------------------------------------------
def _shoot_linear(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, integrator: str, substeps: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Times (fractions of T), x and ẋ of the periodic solution of the linear system, and Φ(T)."""
    m = lin.m
    d = 2 * m
    if integrator == "ivp":
        n_seg = segments(lin, plan, 1)
        E = ivp_propagators(lin, plan, speed, n_seg, forced=True)
    else:
        n_seg = segments(lin, plan, substeps, speed)
        E = propagators(lin, plan, speed, n_seg, forced=True)
    t = np.arange(n_seg) / n_seg
    Phi = ordered_product(E)
    keep = np.delete(np.arange(d), [] if lin.idle is None else [lin.idle])  # the rigid angle: 0
    y0 = np.zeros(d)
    y0[keep] = np.linalg.solve(np.eye(keep.size) - Phi[np.ix_(keep, keep)], Phi[keep, d])
    z = np.empty((n_seg, d + 1))
    z[0] = np.append(y0, 1.0)
    for k in range(n_seg - 1):
        z[k + 1] = E[k] @ z[k]
    return t, z[:, :m], z[:, m:d], Phi[:d, :d]


_FlowError = FlowError


def _flow(
    lin: LinearPeriodic,
    plan: PeriodPlan,
    speed: float,
    y0: np.ndarray,
    t_eval: np.ndarray | None,
    periods: int = 1,
    variational: bool = True,
    rtol: float = 1e-10,
) -> tuple[np.ndarray, np.ndarray]:
    """Periods of the nonlinear (backlash) flow and, with ``variational``, its Jacobian (saltation at
    every contact change, :class:`._nonsmooth.NonsmoothFlow`): the states at ``t_eval`` (fractions of
    the last period) and at the end."""
    samples, end, _ = NonsmoothFlow(lin, plan, speed, rtol).run(y0, t_eval, periods, variational)
    return samples, end


def _settle_periods(lin: LinearPeriodic, plan: PeriodPlan, speed: float) -> int:
    """Periods in which the slowest mode of the mean system decays by e⁻⁶ (at most 100)."""
    m = lin.m
    A = np.block(
        [
            [np.zeros((m, m)), np.eye(m)],
            [-np.linalg.solve(lin.M, lin.held_stiffness), -np.linalg.solve(lin.M, lin.C)],
        ]
    )
    decay = -np.linalg.eigvals(lin.deflate(A)).real.max()
    T = plan.period(speed)
    return int(min(100, max(1, np.ceil(6.0 / max(decay * T, 1e-12)))))


def _settle(lin: LinearPeriodic, plan: PeriodPlan, speed: float, y: np.ndarray) -> np.ndarray:
    """The state after a run from ``y`` for :func:`_settle_periods` periods at ``speed``: near the
    orbit that attracts ``y`` (what a slow sweep reaches after a jump)."""
    periods = _settle_periods(lin, plan, speed)
    return _flow(lin, plan, speed, y, None, periods=periods, variational=False, rtol=1e-7)[1]


def _warm_start(lin: LinearPeriodic, plan: PeriodPlan, speed: float) -> np.ndarray:
    """A start for Newton near the attracting orbit: the static deflection run for the periods in which
    the slowest mode of the mean system decays by e⁻⁶ (at most 100)."""
    y = np.concatenate([lin.static(lin.force(speed)), np.zeros(lin.m)])
    return _settle(lin, plan, speed, y)


def _shoot_nonlinear(
    lin: LinearPeriodic,
    plan: PeriodPlan,
    speed: float,
    y0: np.ndarray,
    N: int,
    tol: float = 1e-7,
    periods: int = 1,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool, np.ndarray, float]:
    """Damped Newton on y(kT; y₀) = y₀ (k = ``periods``: 2 for a period-doubled orbit), the Jacobian
    Φ − I from the variational equations with the saltation matrices of the contact changes (the
    mesh damping in ``lin.C`` is switched by the contact). Converged where the residual is below
    ``tol`` relative to the largest deflection and speed of the state. The times returned are in
    periods T of the mesh plan (0 … k), N samples a period."""
    m = lin.m
    d = 2 * m
    flow = NonsmoothFlow(lin, plan, speed)

    def residual(y: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        try:
            end = flow.run(y, None, periods)[1]
        except (FlowError, ValueError):  # ValueError: solve_ivp refuses a state that is not finite
            return np.full(d, np.inf), np.eye(d), float("inf")
        r = end[:d] - y
        scale = np.concatenate([np.full(m, np.abs(y[:m]).max()), np.full(m, np.abs(y[m:]).max())]) + 1e-300
        return r, end[d:].reshape(d, d), float(np.abs(r / scale).max())

    converged = False
    r, Phi, size = residual(y0)
    for _ in range(40):
        if size <= tol:
            converged = True
            break
        if not np.isfinite(size):
            break
        step = np.linalg.lstsq(Phi - np.eye(d), -r, rcond=None)[0]
        for _halving in range(8):  # backtrack until the residual falls
            trial = y0 + step
            r_t, Phi_t, size_t = residual(trial)
            if size_t < size:
                break
            step = step / 2
        else:
            break
        y0, r, Phi, size = trial, r_t, Phi_t, size_t
    t = np.arange(N) / N
    try:
        parts, y = [], y0
        for _ in range(periods):  # each period sampled in turn
            states, end = flow.run(y, t, variational=False)[:2]
            parts.append(states)
            y = end[:d]
        states = np.concatenate(parts, axis=1)
        closure = _closure(y0, end)
    except FlowError:
        states, closure = np.full((d, N * periods), np.nan), float("nan")
    times = (np.arange(periods)[:, None] + t[None, :]).ravel()
    return times, states[:m].T, states[m:d].T, converged, Phi, closure


def _period_doubled(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, Phi: np.ndarray | None, y0: np.ndarray, N: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool, np.ndarray, float] | None:
    """The stable orbit of two periods where the orbit of one period is unstable or not found: past a
    flip (the leading Floquet multiplier real and below −1, a period-doubling bifurcation: Nayfeh &
    Balachandran, *Applied Nonlinear Dynamics*, 1995, §5.4.3) the period-2T orbit born there attracts.
    Newton over two periods starts from the state a run of the flow reaches (from the unstable orbit
    nudged along the flip's eigenvector where ``Phi`` gives it, else from ``y0``). None where ``Phi``
    shows no flip, Newton fails, the orbit found is unstable or is the period-T orbit again."""
    start = y0
    if Phi is not None:
        mu, vectors = np.linalg.eig(lin.deflate(Phi))
        lead = int(np.argmax(np.abs(mu)))
        if not (mu[lead].real < -1.0 - UNSTABLE_MARGIN and abs(mu[lead].imag) <= _REAL_RTOL * abs(mu[lead])):
            return None
        keep = np.delete(np.arange(y0.size), [] if lin.idle is None else [lin.idle])
        direction = np.zeros(y0.size)
        direction[keep] = vectors[:, lead].real
        m = lin.m
        size = max(np.abs(y0[:m]).max(), 1e-300) / max(np.abs(direction[:m]).max(), 1e-300)
        start = y0 + 1e-2 * size * direction
    try:
        start = _settle(lin, plan, speed, start)
    except FlowError:
        return None
    found = _shoot_nonlinear(lin, plan, speed, start, N, periods=2)
    if not found[3] or _spectral(found[4], lin)[1] > 1.0 + UNSTABLE_MARGIN:
        return None
    first = np.concatenate([found[1][0], found[2][0]])
    after_one = np.concatenate([found[1][N], found[2][N]])
    if _closure(first, after_one) < 1e-5:
        return None  # the period-T orbit again
    return found


def _closure(y0: np.ndarray, end: np.ndarray) -> float:
    """How far the orbit misses itself after one period: the largest mismatch of the deflections
    and of the speeds, each relative to its largest value in y₀, dimensionless."""
    m = y0.size // 2
    r = end[: 2 * m] - y0
    scale = np.concatenate([np.full(m, np.abs(y0[:m]).max()), np.full(m, np.abs(y0[m:]).max())]) + 1e-300
    return float(np.abs(r / scale).max())


# -- results ------------------------------------------------------------------------------------------
def _static_forces(lin: LinearPeriodic, speed: float) -> np.ndarray:
    return lin.mean_stiffness * (lin.G @ lin.static(lin.force(speed)))


def _dynamic_factor(force: np.ndarray, static: np.ndarray) -> np.ndarray:
    """max of the force in the sense of the static one over the static force (NaN without load)."""
    sense = np.sign(static)
    loaded = np.abs(static) > 1e-9 * np.abs(force).max(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        kv = np.max(force * sense, axis=0) / np.abs(static)
    return np.where(loaded, kv, np.nan)


@dataclass(frozen=True, repr=False)
class SteadyState(Result):
    """The periodic steady state of a drivetrain at one speed.

    Attributes
    ----------
    speed : float
        Reference speed Ω, rad/s.
    period : float
        The common mesh period T, s.
    time : ndarray
        (N,) times over one period, s.
    mesh_names : tuple of str
    mesh_force : ndarray
        (N, J) dynamic mesh forces along the lines of action, N.
    deflection : ndarray
        (N, J) mesh deflections δ = g · x (the dynamic transmission error), m.
    static_force : ndarray
        (J,) mesh forces of the mean load at mean stiffness, N.
    coordinates : ndarray
        (N, n) vibration of the system's coordinates about the nominal rotation, rad.
    method : str
    converged : bool
        False where Newton's method (backlash) did not reach the periodic solution.
    notes : tuple of str
    drive : str
        How the train was driven, in words.
    harmonics : int
        Harmonics of each mesh frequency kept by harmonic balance (0 for shooting), count.
    harmonics_error : float
        The estimated largest relative error of K_v from the truncation (the change when the
        harmonics are doubled, :func:`mechdyn.gear_dynamics._harmonics.estimated_error`),
        dimensionless; NaN for shooting.
    periods : int
        Mesh periods T the orbit spans: 1, or 2 for a period-doubled orbit (backlash, past a flip);
        :attr:`time` then covers both.
    """

    speed: float
    period: float
    time: np.ndarray
    mesh_names: tuple[str, ...]
    mesh_force: np.ndarray
    deflection: np.ndarray
    static_force: np.ndarray
    coordinates: np.ndarray
    method: str
    converged: bool = True
    notes: tuple[str, ...] = field(default=())
    drive: str = ""
    harmonics: int = 0
    harmonics_error: float = float("nan")
    periods: int = 1

    @property
    def dynamic_factor(self) -> np.ndarray:
        """(J,) K_v = max dynamic mesh force / static mesh force, dimensionless (NaN without load)."""
        return _dynamic_factor(self.mesh_force, self.static_force)

    @property
    def dte_amplitude(self) -> np.ndarray:
        """(J,) half the peak-to-peak dynamic transmission error, m."""
        return 0.5 * np.ptp(self.deflection, axis=0)

    def summary(self) -> dict[str, Any]:
        """Speed (rad/s), period (s) and, per mesh, force extremes and RMS (N), K_v, DTE amplitude (m)."""
        f = self.mesh_force
        return {
            "speed_rad_s": self.speed,
            "period_s": self.period,
            "method": self.method,
            "meshes": {
                n: {
                    "force_max_N": float(f[:, j].max()),
                    "force_min_N": float(f[:, j].min()),
                    "force_rms_N": float(np.sqrt(np.mean(f[:, j] ** 2))),
                    "static_force_N": float(self.static_force[j]),
                    "dynamic_factor_ratio": float(self.dynamic_factor[j]),
                    "dte_amplitude_m": float(self.dte_amplitude[j]),
                }
                for j, n in enumerate(self.mesh_names)
            },
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per time step: time (s), each mesh's force (N) and deflection (m)."""
        import pandas as pd

        cols: dict[str, Any] = {"time_s": self.time}
        for j, n in enumerate(self.mesh_names):
            cols[f"{n}_force_N"] = self.mesh_force[:, j]
            cols[f"{n}_dte_m"] = self.deflection[:, j]
        return pd.DataFrame(cols)

    @property
    def warnings(self) -> tuple[str, ...]:
        """Notes on the period and on convergence (Newton's, and the harmonics')."""
        return (
            self.notes
            + (() if self.converged else ("Newton's method did not converge",))
            + _truncation_warning(self.harmonics, self.harmonics_error)
        )


def _check_sweep_cost(
    lin: LinearPeriodic,
    plan: PeriodPlan,
    s: np.ndarray,
    H: int,
    given: int | None,
    balance: bool,
    stability: bool,
    *,
    solver_substeps: int,
    refine: int,
) -> None:
    """Refuse (or warn on) a sweep that its counts make too large (:mod:`._cost`), naming the field."""
    low = float(s.min())
    if balance and given is None:
        need = needed_harmonics(lin, plan, low)
        if need > MAX_AUTO:
            from mechdyn.units import convert

            ok = low * need / MAX_AUTO
            low_rpm, ok_rpm = (float(convert(v, "rad/s", "rpm")) for v in (low, ok))
            raise ModelError(
                f"at the lowest speed, {low_rpm:.4g} rpm, the mesh frequency is so far below the train's "
                f"highest natural frequency that {need} harmonics would be needed (at most {MAX_AUTO} are "
                f"chosen); start the range at {ok_rpm:.4g} "
                "rpm or above, or give harmonics (and read the estimated error it states)",
                element="gear dynamics",
                field="speed_range",
            )
    nonlinear = any(b is not None for b in lin.backlash)
    top = int(plan.orders.max()) if plan.orders.size else 1
    seg = segments(lin, plan, solver_substeps, low) if (stability or nonlinear) else 0
    n_speeds = int(s.size * (1.3 if refine else 1.0)) + 2
    cost = sweep_cost(
        n_speeds, int(np.count_nonzero(plan.orders)), H, top, 2 * lin.m, seg, stability, nonlinear
    )
    memory_bound = 16.0 * (np.count_nonzero(plan.orders) * (2 * H * max(top, 1) + 1)) ** 2 >= cost.bytes
    field = ("harmonics" if given is not None else "speed_range") if memory_bound else "points"
    check_cost(
        cost,
        "gear dynamics",
        field,
        "give fewer speeds (points), a higher lowest speed or fewer harmonics, or no stability check",
    )


def _truncation_warning(H: int, error: float) -> tuple[str, ...]:
    if not error > HARMONICS_RTOL:
        return ()
    return (
        f"K_v may be off by {100 * error:.2g} % with {H} harmonics per mesh (the change when they are "
        f"doubled): give more (harmonics = {min(4 * H, 2000)}) or leave the count to be chosen",
    )


def _check_method(method: str) -> None:
    if method not in _METHODS:
        raise ModelError(
            f"method {method!r}: give 'auto', 'harmonic_balance' or 'shooting'",
            element="gear dynamics",
            field="method",
        )


def _check_integrator(integrator: str) -> None:
    if integrator not in ("magnus", "ivp"):
        raise ModelError(
            f"integrator {integrator!r}: give 'magnus' or 'ivp'", element="gear dynamics", field="integrator"
        )


def _choose(lin: LinearPeriodic, method: str) -> str:
    nonlinear = any(b is not None for b in lin.backlash)
    if method == "auto":
        return "shooting" if nonlinear else "harmonic_balance"
    if method == "harmonic_balance" and nonlinear:
        raise ModelError(
            "harmonic balance here is linear (teeth in contact) and a mesh has backlash; use "
            "method='shooting' (Newton on the nonlinear flow) or remove the backlash",
            element="gear dynamics",
            field="method",
        )
    return method


Drive = Literal["motor", "torque", "speed"]
_DRIVES = ("motor", "torque", "speed")


def _model(
    system: Any, reference: str, load: Mapping[str, Any] | None, drive: str | None, motor: Any
) -> LinearPeriodic:
    """The linear periodic model for a drive: ``"motor"`` (the motor free, on its curve),
    ``"torque"`` (free, a constant torque at the reference disk) or ``"speed"`` (the reference disk
    held); None: the motor where one is given, else the constant torque."""
    if drive is None:
        drive = "motor" if motor is not None else "torque"
    if drive not in _DRIVES:
        raise ModelError(
            f"drive {drive!r}: give 'motor' (the motor free on its torque-speed curve), 'torque' (free, a "
            "constant torque at the reference disk) or 'speed' (the reference disk held at each speed)",
            element="gear dynamics",
            field="drive",
        )
    if drive == "motor" and motor is None:
        raise ModelError(
            "drive 'motor' needs the motor: give motor=MotorTorque(...) (or a [motor] table in the file), "
            "or drive='torque'",
            element="gear dynamics",
            field="motor",
        )
    boundary: Boundary = {"motor": "motor", "torque": "free", "speed": "prescribed"}[drive]  # type: ignore[assignment]
    return linear_periodic(
        system, reference=reference, boundary=boundary, load=load, motor=motor if drive == "motor" else None
    )


def _harmonics_given(harmonics: Any) -> int | None:
    """The count given, checked; None for ``"auto"`` (or None): chosen by
    :func:`._harmonics.harmonics_for`."""
    if harmonics is None or (isinstance(harmonics, str) and harmonics == "auto"):
        return None
    return check_count("gear dynamics", "harmonics", harmonics, low=1, high=2000, what="harmonics")


def _truncation_error(lin: LinearPeriodic, plan: PeriodPlan, H: int, speeds: list[float]) -> float:
    """The estimated largest relative error of K_v with H harmonics at ``speeds`` (rad/s), from the
    same with 2H (:func:`._harmonics.estimated_error`), dimensionless."""
    kv = []
    for h in (H, 2 * H):
        solver = _Solver(lin, plan, "harmonic_balance", h, 4, "magnus")
        row = []
        for speed in speeds:
            t, x, v, _ = solver.solve(speed)
            force, _ = _mesh_forces(lin, plan, speed, t, x, v)
            row.append(_dynamic_factor(force, _static_forces(lin, speed)))
        kv.append(np.array(row))
    return estimated_error(kv[0], kv[1])


def _harmonics_words(H: int, auto: bool, error: float) -> str:
    how = "chosen to reach twice the highest natural frequency at the lowest speed" if auto else "as given"
    size = f"{100 * error:.2g} %" if error >= 1e-4 else "0.01 %"
    est = (
        f"; K_v within an estimated {size} of the converged answer (against {2 * H})"
        if np.isfinite(error)
        else ""
    )
    return f"harmonic balance ({H} harmonics per mesh, {how}{est})"


class _Solver:
    """One speed's periodic solution by the chosen method, sharing the speed-independent parts."""

    def __init__(
        self,
        lin: LinearPeriodic,
        plan: PeriodPlan,
        method: str,
        harmonics: int,
        substeps: int,
        integrator: str,
        points: int | None = None,
        stability: bool = False,
    ) -> None:
        self.lin, self.plan, self.method, self.points = lin, plan, method, points
        self.stability = stability
        self.rho = float("nan")
        self.closure = float("nan")  # the last orbit's closure after one period (backlash)
        self.multiple = 1  # periods T of the last orbit (2: period-doubled)
        self.harmonics, self.substeps, self.integrator = harmonics, substeps, integrator
        self.nonlinear = any(b is not None for b in lin.backlash)
        self.bal = (
            _balance(lin, plan, harmonics) if (method == "harmonic_balance" or self.nonlinear) else None
        )
        self.start: np.ndarray | None = None  # continuation: the last periodic state

    def solve(
        self, speed: float, *, start: np.ndarray | None = None, settle: bool = True
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
        """Times (fractions of T), x, ẋ and convergence; :attr:`rho` the spectral radius where known.

        With backlash, Newton starts from ``start`` (default: the last periodic state, or a run from the
        static deflection); with ``settle``, where it fails or lands on an unstable orbit, it starts
        again from a run of :func:`_settle_periods` periods from that start at this speed (the orbit a
        slow sweep reaches: after a jump, the other branch), up to four runs in a row."""
        lin, plan = self.lin.at_speed(speed), self.plan
        self.rho = float("nan")
        self.closure = float("nan")
        self.multiple = 1
        if self.method == "harmonic_balance":
            assert self.bal is not None
            X = _hb_solve(lin, plan, self.bal, speed)
            N = _grid(lin, plan, self.bal.H) if self.points is None else self.points
            x, v = _series(X, 2 * np.pi * plan.fundamental * speed, N)
            if self.stability:
                self.rho = _spectral(_monodromy(lin, plan, speed, "magnus", self.substeps), lin)[1]
            return np.arange(N) / N, x, v, True
        if not self.nonlinear:
            t, x, v, Phi = _shoot_linear(lin, plan, speed, self.integrator, self.substeps)
            self.rho = _spectral(Phi, lin)[1]
            return t, x, v, True
        assert self.bal is not None
        if start is None:
            if self.start is None:  # a run from the static deflection starts Newton
                self.start = _warm_start(lin, plan, speed)
            start = self.start
        N = _grid(lin, plan, self.bal.H)
        t, x, v, ok, Phi, closure = _shoot_nonlinear(lin, plan, speed, start, N)
        rho = _spectral(Phi, lin)[1] if ok else float("inf")
        settled = start
        for _round in range(_SETTLE_ROUNDS if settle else 0):
            if rho <= 1.0 + UNSTABLE_MARGIN:
                break
            try:
                settled = _settle(lin, plan, speed, settled)
            except FlowError:
                break
            again = _shoot_nonlinear(lin, plan, speed, settled, N)
            rho_again = _spectral(again[4], lin)[1] if again[3] else float("inf")
            if again[3] and rho_again < rho:
                t, x, v, ok, Phi, closure = again
                rho = rho_again
        if settle and (not ok or rho > 1.0 + UNSTABLE_MARGIN):
            orbit = np.concatenate([x[0], v[0]]) if ok else settled
            doubled = _period_doubled(lin, plan, speed, Phi if ok else None, orbit, N)
            if doubled is not None:
                t, x, v, ok, Phi, closure = doubled
                rho = _spectral(Phi, lin)[1]
                self.multiple = 2
        self.closure = closure
        if ok:
            self.start = np.concatenate([x[0], v[0]])
            self.rho = rho
        return t, x, v, ok


def steady_state(
    system: Any,
    speed: float,
    *,
    reference: str,
    load: Mapping[str, Any] | None = None,
    method: Method = "auto",
    harmonics: int | Literal["auto"] = "auto",
    integrator: Literal["magnus", "ivp"] = "magnus",
    substeps: int = 4,
    points: int | None = None,
    drive: Drive | None = None,
    motor: Any = None,
) -> SteadyState:
    """The periodic steady state of a drivetrain at one constant speed.

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain.
    speed : float
        Speed Ω of the reference disk, rad/s, positive.
    reference : str
        The disk whose speed is Ω (a motor disk).
    load : mapping of str to float, optional
        Torque drawn at each named disk, N·m (or quantities), resisting its rotation.
    method : {"auto", "harmonic_balance", "shooting"}
        ``"auto"``: harmonic balance, or shooting with Newton where a mesh has backlash.
    harmonics : int or "auto"
        Harmonics of each mesh frequency kept by harmonic balance, a count from 1 to 2000, or
        ``"auto"``: enough to reach twice the highest natural frequency
        (:func:`mechdyn.gear_dynamics._harmonics.harmonics_for`), checked by doubling them
        (:attr:`SteadyState.harmonics_error`).
    integrator : {"magnus", "ivp"}
        The propagator of linear shooting (:func:`mechdyn.gear_dynamics.floquet.monodromy`).
    substeps : int
        Magnus segments per profile sample interval, a count from 1 to 1000.
    points : int, optional
        Time samples per period of the harmonic-balance response, a count from 8 (default: 4 per
        profile sample interval, at least 256 and 2H + 2). Shooting samples at its segment ends.
    drive : {"motor", "torque", "speed"}, optional
        How the train is driven. ``"motor"``: no disk held, ``motor`` drives, its torque following its
        torque–speed curve about the torque that holds the load (its slope damps the rigid rotation,
        :mod:`mechdyn.gear_dynamics._operating`): what :func:`simulate` integrates; ``"torque"``: no disk
        held, a constant torque at the reference disk balances the load; ``"speed"``: the reference
        disk held at exactly Ω (a kinematic input, which moves the train's modes: a held motor rotor
        becomes a node). Default: ``"motor"`` where ``motor`` is given, else ``"torque"``.
    motor : MotorTorque, optional
        The motor (:class:`mechdyn.gear_dynamics.loads.MotorTorque`) of ``drive="motor"``.

    Returns
    -------
    SteadyState

    Notes
    -----
    Harmonic balance of a linear periodic system (Nayfeh & Mook, *Nonlinear Oscillations*, 1979,
    §5.4); shooting (Nayfeh & Balachandran, *Applied Nonlinear Dynamics*, 1995, §7.1).
    """
    _check_method(method)
    _check_integrator(integrator)
    given = _harmonics_given(harmonics)
    substeps = check_count("gear dynamics", "substeps", substeps, low=1, high=1000, what="substeps")
    speed = _check_speed("speed", speed)
    lin = _model(system, reference, load, drive, motor)
    chosen = _choose(lin, method)
    plan = period_plan(lin)
    if points is not None:
        points = check_count("gear dynamics", "points", points, low=8, high=10**7, what="time samples")
    H = given if given is not None else harmonics_for(lin, plan, speed)
    solver = _Solver(lin, plan, chosen, H, substeps, integrator, points)
    t, x, v, ok = solver.solve(speed)
    error = _truncation_error(lin, plan, H, [speed]) if chosen == "harmonic_balance" else float("nan")
    force, delta = _mesh_forces(lin, plan, speed, t, x, v)
    T = plan.period(speed)
    return SteadyState(
        speed=speed,
        period=T,
        time=t * T,
        mesh_names=lin.names,
        mesh_force=force,
        deflection=delta,
        static_force=_static_forces(lin, speed),
        coordinates=x @ lin.basis.T,
        method=(
            _harmonics_words(H, given is None, error)
            if chosen == "harmonic_balance"
            else f"shooting ({integrator})"
        ),
        converged=ok,
        notes=(plan.note,) if plan.note else (),
        drive=lin.drive,
        harmonics=H if chosen == "harmonic_balance" else 0,
        harmonics_error=error,
        periods=solver.multiple,
    )


# -- speed sweep -----------------------------------------------------------------------------------------
@dataclass(frozen=True, repr=False)
class SpeedSweepResult(Result):
    """Periodic steady state of a drivetrain over speed: mesh forces, dynamic factors, DTE, resonances.

    Attributes
    ----------
    speeds : ndarray
        (n_s,) reference speeds Ω, rad/s, ascending (the given ones and those added near peaks).
    reference : str
        The disk whose speed is Ω.
    mesh_names : tuple of str
    mesh_cycles : ndarray
        (J,) mesh cycles per radian of the reference disk (f_mesh = cycles · Ω), dimensionless.
    force_max, force_min, force_rms : ndarray
        (n_s, J) largest, smallest and root-mean-square mesh force over a period, N.
    static_force : ndarray
        (n_s, J) mesh force of the mean load at mean stiffness, N.
    dte_amplitude : ndarray
        (n_s, J) half peak-to-peak dynamic transmission error along the line of action, m.
    iso_dynamic_factor : ndarray
        (n_s, J) ISO 6336-1 K_v of the meshes whose gear data were given (NaN for the others),
        dimensionless.
    converged : ndarray
        (n_s,) False where Newton's method (backlash) did not converge.
    spectral_radius : ndarray
        (n_s,) largest Floquet multiplier modulus of the periodic solution (the teeth-in-contact
        system for harmonic balance; the orbit's own monodromy for shooting), dimensionless; NaN
        where not computed.
    method : str
    harmonics : int
        Harmonics of each mesh frequency (harmonic balance; 0 for shooting), count.
    harmonics_error : float
        The estimated largest relative error of K_v from the truncation, from doubling the harmonics
        at the lowest speed and at the speed of the largest K_v, dimensionless; NaN for shooting.
    notes : tuple of str
        What the user should know (the period chosen, a missing load): the result's warnings.
    assumptions : tuple of str
        What ISO 6336-1's K_v took where the gear data do not say (an accuracy grade's deviations, no
        tip relief): stated under the table, not warnings.
    closure : ndarray or None
        (n_s,) with backlash: how far each orbit misses itself after one period, the largest mismatch
        of the deflections and of the speeds relative to their largest values, dimensionless (NaN
        where Newton failed and without backlash).
    direction : str
        ``"up"`` or ``"down"``: the order in which the speeds were visited (continuation).
    down : SpeedSweepResult or None
        With ``direction="both"``: the down sweep over the same speeds (None otherwise).
    drive : str
        How the train was driven at each speed, in words (the motor free on its curve, a constant
        torque, or the reference disk held).
    iso_resonance_speed : ndarray or None
        (J,) the reference speed at which ISO 6336-1's pair alone resonates (its n_E1 over the
        pinion's speed ratio), rad/s; NaN for meshes without gear data.
    natural_frequencies_hz : ndarray or None
        The train's natural frequencies with the meshes at mean stiffness and the sweep's drive
        (no rigid-body mode), Hz: where the mesh orders meet them the computed K_v peaks
        (:meth:`train_resonances`).
    period_multiple : ndarray or None
        (n_s,) the periods T of each speed's orbit: 1, or 2 where the orbit of one period is unstable
        (past a flip) and the period-doubled orbit is the one shown (backlash).
    jump_speeds : tuple of float
        With backlash: where the branch the sweep followed ends and it jumps to another, each located
        by bisection to within :data:`EDGE_RTOL` of the speed, rad/s.
    """

    speeds: np.ndarray
    reference: str
    mesh_names: tuple[str, ...]
    mesh_cycles: np.ndarray
    force_max: np.ndarray
    force_min: np.ndarray
    force_rms: np.ndarray
    static_force: np.ndarray
    dte_amplitude: np.ndarray
    iso_dynamic_factor: np.ndarray
    converged: np.ndarray
    spectral_radius: np.ndarray
    method: str
    harmonics: int
    notes: tuple[str, ...] = field(default=())
    assumptions: tuple[str, ...] = field(default=())
    harmonics_error: float = float("nan")
    closure: np.ndarray | None = None
    direction: str = "up"
    down: SpeedSweepResult | None = None
    drive: str = ""
    iso_resonance_speed: np.ndarray | None = None
    natural_frequencies_hz: np.ndarray | None = None
    period_multiple: np.ndarray | None = None
    jump_speeds: tuple[float, ...] = ()

    @property
    def stable(self) -> np.ndarray:
        """(n_s,) False where the periodic solution is unstable (largest Floquet multiplier above 1:
        a parametric resonance, where the steady state shown is not reached); True where ρ ≤ 1 or not
        computed."""
        return ~(self.spectral_radius > 1.0 + UNSTABLE_MARGIN)

    @property
    def dynamic_factor(self) -> np.ndarray:
        """(n_s, J) K_v = max dynamic mesh force / static mesh force (in the static force's sense),
        dimensionless; NaN where there is no load."""
        sense = np.sign(self.static_force)
        extreme = np.where(sense >= 0, self.force_max, -self.force_min)
        loaded = np.abs(self.static_force) > 1e-9 * np.maximum(np.abs(self.force_max), np.abs(self.force_min))
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(loaded, extreme / np.abs(self.static_force), np.nan)

    @property
    def force_amplitude(self) -> np.ndarray:
        """(n_s, J) half peak-to-peak mesh force, N."""
        return 0.5 * (self.force_max - self.force_min)

    @property
    def mesh_frequencies_hz(self) -> np.ndarray:
        """(n_s, J) mesh frequencies, Hz."""
        return np.abs(self.mesh_cycles)[None, :] * self.speeds[:, None]

    def resonances(self) -> dict[str, list[float]]:
        """Per mesh, the speeds (rad/s) of the peaks of its force amplitude, each refined by a parabola
        through the peak sample and its neighbours: the local maxima whose prominence is at least
        :data:`PEAK_PROMINENCE` of their height (so that ripples are not listed)."""
        out: dict[str, list[float]] = {}
        s = self.speeds
        for j, name in enumerate(self.mesh_names):
            y = self.force_amplitude[:, j]
            peaks = []
            for i in _peaks(y):
                x0, x1, x2 = s[i - 1 : i + 2]
                y0, y1, y2 = y[i - 1 : i + 2]
                den = (x0 - x1) * (x0 - x2) * (x1 - x2)
                a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / den
                b = (x2**2 * (y0 - y1) + x1**2 * (y2 - y0) + x0**2 * (y1 - y2)) / den
                peaks.append(float(-b / (2 * a)) if a < 0 and x0 < -b / (2 * a) < x2 else float(x1))
            out[name] = peaks
        return out

    def train_resonances(self) -> dict[str, list[tuple[int, int, float, float]]]:
        """Per mesh, where an order (1, 2) of its frequency meets a natural frequency of the train
        within the swept range: (mode number, order, frequency in Hz, reference speed in rad/s)
        (:func:`mechdyn.gear_dynamics._resonance.crossings`); empty without natural frequencies."""
        if self.natural_frequencies_hz is None:
            return {n: [] for n in self.mesh_names}
        low, high = float(self.speeds.min()), float(self.speeds.max())
        return {
            n: crossings(self.natural_frequencies_hz, self.mesh_cycles[j], low, high)
            for j, n in enumerate(self.mesh_names)
        }

    def hysteresis(self) -> dict[str, tuple[float, float] | None]:
        """With a down sweep (``direction="both"``): per mesh, the lowest and highest speed (rad/s) at
        which the up and the down sweep, both converged and stable, differ in force amplitude by more than
        :data:`HYSTERESIS_RTOL` of the larger (the band of the jump phenomenon), or None where they
        agree; empty without a down sweep."""
        if self.down is None:
            return {}
        common, iu, idn = np.intersect1d(self.speeds, self.down.speeds, return_indices=True)
        # an unstable orbit is no branch a machine runs on: it never counts in the band
        ok = self.converged[iu] & self.down.converged[idn] & self.stable[iu] & self.down.stable[idn]
        out: dict[str, tuple[float, float] | None] = {}
        for j, name in enumerate(self.mesh_names):
            a, b = self.force_amplitude[iu, j], self.down.force_amplitude[idn, j]
            differ = ok & (np.abs(a - b) > HYSTERESIS_RTOL * np.maximum(np.abs(a), np.abs(b)))
            if not differ.any():
                out[name] = None
                continue
            low, high = float(common[differ].min()), float(common[differ].max())
            # the edges where the branches end, located by bisection, where the sweeps jumped there
            down_jumps = [v for v in self.down.jump_speeds if v <= low]
            up_jumps = [v for v in self.jump_speeds if v >= high]
            out[name] = (max(down_jumps) if down_jumps else low, min(up_jumps) if up_jumps else high)
        return out

    def _doubling_notes(self) -> list[str]:
        """The speeds where a period-doubled orbit is shown, in words (rpm)."""
        from mechdyn.units import convert

        out = []
        for sweep in (self, self.down):
            if sweep is None or sweep.period_multiple is None or not (sweep.period_multiple == 2).any():
                continue
            doubled = sweep.speeds[sweep.period_multiple == 2]
            low, high = (float(convert(v, "rad/s", "rpm")) for v in (doubled.min(), doubled.max()))
            out.append(
                f"Swept {sweep.direction}, the orbit of one mesh period is unstable at {doubled.size} speeds "
                f"from {low:.4g} to {high:.4g} rpm (a flip: a Floquet multiplier below −1): there the "
                "period-doubled orbit, of two mesh periods, is shown."
            )
        return out

    def _hysteresis_notes(self) -> list[str]:
        """The jump in words, where a down sweep was made (rpm)."""
        if self.down is None:
            return []
        from mechdyn.units import convert

        out = []
        for name, band in self.hysteresis().items():
            if band is None:
                out.append(f"Swept up and down, {name!r} has one branch (no jump).")
            else:
                low, high = (float(convert(v, "rad/s", "rpm")) for v in band)
                out.append(
                    f"Swept up and down, {name!r} has two branches from {low:.4g} to {high:.4g} rpm (the "
                    "jump): the table is the up sweep's."
                )
        return out

    def summary(self) -> dict[str, Any]:
        """Speed range (rad/s), method, and per mesh the largest K_v and where (rad/s), the static
        force (N), the largest DTE amplitude (m) and the resonance speeds (rad/s); with a down sweep
        also the speeds (rad/s) between which the up and down sweeps differ."""
        kv = self.dynamic_factor
        res = self.resonances()
        meshes = {}
        for j, name in enumerate(self.mesh_names):
            finite = np.isfinite(kv[:, j])
            i = int(np.nanargmax(np.where(finite, kv[:, j], -np.inf))) if finite.any() else 0
            meshes[name] = {
                "dynamic_factor_max_ratio": float(kv[i, j]) if finite.any() else float("nan"),
                "dynamic_factor_max_at_rad_s": float(self.speeds[i]),
                "static_force_N": float(self.static_force[0, j]),
                "force_max_N": float(self.force_max[:, j].max()),
                "dte_amplitude_max_m": float(self.dte_amplitude[:, j].max()),
                "resonance_speeds_rad_s": res[name],
            }
            if self.down is not None:
                band = self.hysteresis()[name]
                meshes[name]["hysteresis_speeds_rad_s"] = list(band) if band else []
            meshes[name]["train_resonance_speeds_rad_s"] = [c[3] for c in self.train_resonances()[name]]
            if np.isfinite(self.iso_dynamic_factor[:, j]).any():
                meshes[name]["iso_dynamic_factor_max_ratio"] = float(np.nanmax(self.iso_dynamic_factor[:, j]))
                if self.iso_resonance_speed is not None:
                    meshes[name]["iso_resonance_speed_rad_s"] = float(self.iso_resonance_speed[j])
        return {
            "reference": self.reference,
            "drive": self.drive,
            "method": self.method,
            "harmonics": int(self.harmonics),
            "harmonics_error_ratio": float(self.harmonics_error),
            "speed_min_rad_s": float(self.speeds.min()),
            "speed_max_rad_s": float(self.speeds.max()),
            "points": int(self.speeds.size),
            "unstable_points": int((~self.stable).sum()),
            "period_doubled_points": (
                int((self.period_multiple == 2).sum()) if self.period_multiple is not None else 0
            ),
            "meshes": meshes,
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per speed: speed (rad/s, rpm) and per mesh its frequency (Hz), force max, min, RMS
        and static (N), K_v, ISO K_v and DTE amplitude (m)."""
        import pandas as pd

        from mechdyn.units import convert

        cols: dict[str, Any] = {
            "speed_rad_s": self.speeds,
            "speed_rpm": np.asarray(convert(self.speeds, "rad/s", "rpm")),
        }
        kv = self.dynamic_factor
        for j, n in enumerate(self.mesh_names):
            cols[f"{n}_mesh_frequency_hz"] = self.mesh_frequencies_hz[:, j]
            cols[f"{n}_force_max_N"] = self.force_max[:, j]
            cols[f"{n}_force_min_N"] = self.force_min[:, j]
            cols[f"{n}_force_rms_N"] = self.force_rms[:, j]
            cols[f"{n}_static_force_N"] = self.static_force[:, j]
            cols[f"{n}_dynamic_factor_ratio"] = kv[:, j]
            cols[f"{n}_iso_dynamic_factor_ratio"] = self.iso_dynamic_factor[:, j]
            cols[f"{n}_dte_amplitude_m"] = self.dte_amplitude[:, j]
        cols["converged"] = self.converged
        cols["spectral_radius_ratio"] = self.spectral_radius
        cols["stable"] = self.stable
        return pd.DataFrame(cols)

    def tables(self, **display_units: str) -> list[Table]:
        """Per mesh: largest K_v and where (rpm), static force, largest DTE amplitude, resonances (rpm);
        then where the train's modes meet the mesh orders, beside ISO's pair resonance."""
        from mechdyn.units import convert, readable

        force_unit = display_units.get("force_unit")
        rows = []
        s = self.summary()["meshes"]
        for name, m in s.items():
            f = m["static_force_N"]
            f_shown = (float(convert(f, "N", force_unit)), force_unit) if force_unit else readable(f, "N")
            dte, dte_unit = readable(m["dte_amplitude_max_m"], "m")
            rpm = [f"{float(convert(v, 'rad/s', 'rpm')):.5g}" for v in m["resonance_speeds_rad_s"]]
            rows.append(
                [
                    name,
                    m["dynamic_factor_max_ratio"],
                    float(convert(m["dynamic_factor_max_at_rad_s"], "rad/s", "rpm")),
                    m.get("iso_dynamic_factor_max_ratio"),
                    f"{f_shown[0]:.4g} {f_shown[1]}",
                    f"{dte:.4g} {dte_unit}",
                    ", ".join(rpm) or "none",
                ]
            )
        return [
            Table(
                f"speed sweep of disk {self.reference!r}: dynamic mesh forces",
                [
                    "mesh",
                    "K_v max",
                    "at [rpm]",
                    "ISO K_v max (pair alone)",
                    "static force",
                    "DTE amplitude max",
                    "resonances [rpm]",
                ],
                rows,
                note=" ".join(
                    (
                        f"Computed by {self.method}.",
                        *((f"Drive: {self.drive}.",) if self.drive else ()),
                        *self._hysteresis_notes(),
                        *self._doubling_notes(),
                        *(n.rstrip(".") + "." for n in self.notes + self.assumptions),
                    )
                ),
            ),
            *self._resonance_table(),
        ]

    def _resonance_table(self) -> list[Table]:
        """The train's resonances within the range per mesh, beside ISO's pair resonance."""
        from mechdyn.units import convert

        rows: list[list[Any]] = []
        with_iso = []
        for j, (name, found) in enumerate(self.train_resonances().items()):
            iso = self.iso_resonance_speed[j] if self.iso_resonance_speed is not None else np.nan
            iso_rpm = float(convert(iso, "rad/s", "rpm")) if np.isfinite(iso) else None
            if iso_rpm is not None:
                with_iso.append(name)
            for mode, order, f, speed in found or [(0, 0, np.nan, np.nan)]:
                rows.append(
                    [
                        name,
                        f"{mode}" if mode else "none in range",
                        f if mode else None,
                        f"{order} × mesh" if mode else None,
                        float(convert(speed, "rad/s", "rpm")) if mode else None,
                        iso_rpm,
                    ]
                )
        if not rows:
            return []
        return [
            Table(
                "where the train's modes meet the mesh frequency, and ISO 6336-1's pair alone",
                [
                    "mesh",
                    "train mode",
                    "frequency [Hz]",
                    "excited by",
                    "at [rpm]",
                    "ISO pair resonance [rpm]",
                ],
                rows,
                note=iso_note(with_iso),
            )
        ]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``speed_sweep.png``: K_v (and ISO K_v) over speed per mesh; ``speed_sweep_dte.png``: DTE."""
        from mechdyn.gear_dynamics.sweep_plots import plot_speed_sweep, plot_sweep_dte

        return {
            "speed_sweep.png": lambda: plot_speed_sweep(self, **display_units),
            "speed_sweep_dte.png": lambda: plot_sweep_dte(self, **display_units),
        }

    @property
    def warnings(self) -> tuple[str, ...]:
        """The period chosen, missing loads, speeds where Newton did not converge."""
        out = list(self.notes)
        for sweep in (self, self.down):
            if sweep is not None and not sweep.converged.all():
                bad = sweep.speeds[~sweep.converged]
                out.append(
                    f"Newton's method did not converge at {bad.size} speeds (from {bad.min():.4g} rad/s)"
                    + (" sweeping down" if sweep is self.down else "")
                )
        out.extend(_truncation_warning(self.harmonics, self.harmonics_error))
        if not self.stable.all():
            bad = self.speeds[~self.stable]
            out.append(
                f"the periodic solution is unstable (parametric resonance, Floquet ρ > 1) at {bad.size} "
                f"speeds between {bad.min():.4g} and {bad.max():.4g} rad/s: there the forces shown are not "
                "reached"
            )
        return tuple(out)


def _stack_kv(stack: list[np.ndarray]) -> np.ndarray:
    """(n_s, J) K_v of the stacked rows (force max, min, …, static force)."""
    force_max, force_min, static = stack[0], stack[1], stack[3]
    extreme = np.where(np.sign(static) >= 0, force_max, -force_min)
    with np.errstate(invalid="ignore", divide="ignore"):
        return extreme / np.abs(static)


def _sweep_kv(stack: list[np.ndarray]) -> np.ndarray:
    force_max, force_min, static = stack[0], stack[1], stack[3]
    loaded = np.abs(static) > 1e-9 * np.maximum(np.abs(force_max), np.abs(force_min))
    return np.where(loaded, 1.0, np.nan)


def _peaks(y: np.ndarray) -> np.ndarray:
    """Indices of the interior local maxima of ``y`` whose prominence (:func:`scipy.signal.find_peaks`)
    is at least :data:`PEAK_PROMINENCE` of their own value, and above 1e-9 of the largest value."""
    from scipy.signal import find_peaks

    y = np.asarray(y, float)
    finite = np.isfinite(y)
    if y.size < 3 or not finite.any():
        return np.zeros(0, int)
    y = np.where(finite, y, y[finite].min())  # a speed where Newton failed is no peak
    idx, props = find_peaks(y, prominence=0.0)
    scale = np.abs(y).max()
    keep = (props["prominences"] >= PEAK_PROMINENCE * np.abs(y[idx])) & (np.abs(y[idx]) > 1e-9 * scale)
    return idx[keep] if scale > 0 else idx[:0]


def _iso_factors(
    system: Any, lin: LinearPeriodic, speeds: np.ndarray, static: np.ndarray, gear_pairs: Mapping[str, Any]
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """ISO 6336-1 K_v per speed for the meshes whose gear pair is given (NaN elsewhere), the reference
    speed of each pair's own resonance n_E1 (rad/s, NaN elsewhere), and notes."""
    out = np.full((speeds.size, len(lin.names)), np.nan)
    resonance = np.full(len(lin.names), np.nan)
    notes: list[str] = []
    for name in gear_pairs:
        if name not in lin.names:
            raise ModelError(
                f"gear data for {name!r}, which is not a flexible mesh; give one of {', '.join(lin.names)}",
                element="gear dynamics",
                field="gear_pairs",
            )
    if not gear_pairs:
        return out, resonance, notes
    from mechdyn.gears.iso6336 import iso_dynamic_factor as iso

    dt = system.drivetrain
    meshes = {m.name: m for m in system.meshes}
    for name, pair in gear_pairs.items():
        j = lin.names.index(name)
        pinion_ratio = float(np.abs(np.asarray(meshes[name].phase_row, float) @ lin.rigid))
        pinion_speed = pinion_ratio * speeds
        force = float(np.mean(np.abs(static[:, j])))
        if force == 0.0:
            notes.append(f"mesh {name!r}: no load, so no ISO 6336-1 K_v")
            continue
        element = dt.element(name)
        inertia_a, inertia_b = (float(dt.disks[dt.disk_index[d]].inertia) for d in element.disks)
        inertias = (inertia_a, inertia_b)
        factor = iso(
            pair,
            pinion_speed,
            force * pair.pinion.base_radius,
            inertias=inertias,  # T₁ = F_bn r_b1
        )
        out[:, j] = np.asarray(factor.K_v, float)
        resonance[j] = float(factor.resonance_speed) / pinion_ratio
        notes.extend(f"ISO 6336-1 K_v of {name!r}: {n}" for n in factor.notes)
    return out, resonance, notes


def speed_sweep(
    system: Any,
    speeds: Any,
    *,
    reference: str,
    load: Mapping[str, Any] | None = None,
    method: Method = "auto",
    harmonics: int | Literal["auto"] = "auto",
    refine: int = 3,
    gear_pairs: Mapping[str, Any] | None = None,
    integrator: Literal["magnus", "ivp"] = "magnus",
    substeps: int = 4,
    stability: bool = True,
    direction: Direction = "up",
    drive: Drive | None = None,
    motor: Any = None,
) -> SpeedSweepResult:
    """Dynamic mesh forces, dynamic factors and DTE of a drivetrain over its running speed.

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain (:class:`mechdyn.gear_dynamics.GearSystem`).
    speeds : array_like
        Speeds Ω of the reference disk, rad/s, positive (sorted; duplicates dropped).
    reference : str
        The disk held at Ω (a motor disk; a kinematic input).
    load : mapping of str to float, optional
        Torque drawn at each named disk, N·m (or quantities), resisting its rotation; the static mesh
        forces of K_v follow from it. Without a load K_v is NaN.
    method : {"auto", "harmonic_balance", "shooting"}
        ``"auto"``: harmonic balance, or shooting with Newton continued over speed where a mesh has
        backlash.
    harmonics : int or "auto"
        Harmonics of each mesh frequency kept by harmonic balance, a count from 1 to 2000, or
        ``"auto"``: enough to reach twice the highest natural frequency at the lowest speed
        (:func:`mechdyn.gear_dynamics._harmonics.harmonics_for`), doubled until K_v changes by less
        than 1 % (estimated) at the lowest speed and at the speed of the largest K_v. Either way the
        result states the estimated error (:attr:`SpeedSweepResult.harmonics_error`) and warns above 1 %.
    refine : int
        Rounds of adding speeds either side of every local maximum of a mesh's force amplitude (so
        that the peaks are resolved), a count from 0 to 20.
    gear_pairs : mapping of str to GearPair, optional
        Mesh name → its :class:`mechdyn.gears.GearPair`: adds ISO 6336-1's K_v to the result.
    integrator : {"magnus", "ivp"}
        The propagator of linear shooting.
    substeps : int
        Magnus segments per profile sample interval, a count from 1 to 1000.
    stability : bool
        Also compute each periodic solution's largest Floquet multiplier (harmonic balance: the
        monodromy matrix by the Magnus product, :func:`mechdyn.gear_dynamics.floquet.monodromy`;
        shooting has it anyway) and flag the speeds where it is unstable.
    direction : {"up", "down", "both"}
        The order in which the speeds are visited, which matters with backlash only (each speed starts
        from the solution of the one before, so that a sweep follows one branch of the response
        until it ends and then jumps, as a slowly run-up or run-down machine does): ``"up"``
        (ascending), ``"down"`` (descending) or ``"both"`` (up, then down from the top; the result is
        the up sweep with the down sweep as its :attr:`SpeedSweepResult.down`).
    drive : {"motor", "torque", "speed"}, optional
        How the train is driven at each speed (see :func:`steady_state`); default ``"motor"`` where
        ``motor`` is given, else ``"torque"``. ``"speed"`` holds the reference disk (a kinematic input):
        where that disk is a motor rotor, the train's first mode and resonances move.
    motor : MotorTorque, optional
        The motor of ``drive="motor"`` (:class:`mechdyn.gear_dynamics.loads.MotorTorque`).

    Returns
    -------
    SpeedSweepResult

    Notes
    -----
    Each speed's periodic solution as :func:`steady_state` (harmonic balance: one sparse solve per
    speed, the speed-independent stiffness coupling assembled once). With backlash, Newton's method
    on the event-located flow starts from the previous speed's solution (natural continuation); where
    it fails or finds an unstable orbit, the step is halved up to three times, and then the previous
    solution is run for the periods in which the slowest mode decays by e⁻⁶ at the new speed and
    Newton starts from there: past the end of a branch (a fold of the softening backlash
    nonlinearity) the sweep jumps to the other branch, so that the up and down sweeps differ inside
    the band of multiple solutions (Kahraman & Singh, *J. Sound Vib.* 142 (1990) 49–75). A speed where
    Newton still fails is kept with ``converged`` False. K_v = max f / f_static follows ISO 6336-1
    (2019), clause 6's definition of the dynamic factor as the ratio of the largest to the nominal tooth load.
    """
    _check_method(method)
    _check_integrator(integrator)
    given = _harmonics_given(harmonics)
    refine = check_count("gear dynamics", "refine", refine, low=0, high=20, what="refinement rounds")
    substeps = check_count("gear dynamics", "substeps", substeps, low=1, high=1000, what="substeps")
    if direction not in _DIRECTIONS:
        raise ModelError(
            f"direction {direction!r}: give 'up', 'down' or 'both'",
            element="gear dynamics",
            field="direction",
        )
    s = np.unique(_speeds(speeds))
    lin = _model(system, reference, load, drive, motor)
    if not lin.names:
        raise ModelError(
            "the drivetrain has no flexible gear mesh; give a mesh a stiffness",
            element="gear dynamics",
            field="system",
        )
    chosen = _choose(lin, method)
    plan = period_plan(lin)
    balance = chosen == "harmonic_balance"
    H = given if given is not None else (harmonics_for(lin, plan, float(s.min())) if balance else 16)
    _check_sweep_cost(lin, plan, s, H, given, balance, stability, solver_substeps=substeps, refine=refine)
    iso_cache: dict[bytes, tuple[np.ndarray, np.ndarray, list[str]]] = {}
    natural = _natural_frequencies(lin)

    def result(sweep: str) -> SpeedSweepResult:
        grid, stack, jumps = _sweep(solver, s, sweep, refine)
        error = float("nan")
        if balance:  # the truncation checked where it matters most: lowest speed, largest K_v
            kv = _sweep_kv(stack) * _stack_kv(stack)
            worst = [float(grid[0])]
            if np.isfinite(kv).any():
                worst.append(float(grid[int(np.nanargmax(np.nanmax(kv, axis=1)))]))
            error = _truncation_error(lin, plan, H, sorted(set(worst)))
        key = grid.tobytes()
        if key not in iso_cache:
            iso_cache[key] = _iso_factors(system, lin, grid, stack[3], dict(gear_pairs or {}))
        iso, iso_resonance, iso_notes = iso_cache[key]
        notes = [plan.note] if plan.note else []
        if not np.isfinite(_sweep_kv(stack)).any():
            notes.append("no load given: the dynamic factor K_v needs a static mesh force (give load=...)")
        return SpeedSweepResult(
            speeds=grid,
            reference=reference,
            mesh_names=lin.names,
            mesh_cycles=lin.cycles,
            force_max=stack[0],
            force_min=stack[1],
            force_rms=stack[2],
            static_force=stack[3],
            dte_amplitude=stack[4],
            iso_dynamic_factor=iso,
            iso_resonance_speed=iso_resonance,
            natural_frequencies_hz=natural,
            converged=stack[5][:, 0].astype(bool),
            spectral_radius=stack[5][:, 1],
            closure=stack[5][:, 2],
            period_multiple=stack[5][:, 3].astype(int),
            jump_speeds=tuple(jumps),
            method=(
                _harmonics_words(H, given is None, error)
                if balance
                else (
                    f"shooting with Newton's method on the backlash flow, continued over speed ({sweep})"
                    if solver.nonlinear
                    else f"shooting ({integrator})"
                )
            ),
            harmonics=H if balance else 0,
            harmonics_error=error,
            notes=tuple(notes),
            assumptions=tuple(iso_notes),
            direction=sweep,
            drive=lin.drive,
        )

    while True:  # chosen harmonics: doubled until K_v is converged to HARMONICS_RTOL
        solver = _Solver(lin, plan, chosen, H, substeps, integrator, stability=stability)
        first = result("up" if direction == "both" else direction)
        if given is None and first.harmonics_error > HARMONICS_RTOL and 2 * H <= MAX_AUTO:
            H *= 2
            continue
        break
    if direction == "both":
        down = result("down") if solver.nonlinear else replace(first, direction="down")
        return replace(first, down=down)
    return first


def _sweep(
    solver: _Solver, s: np.ndarray, direction: str, refine: int
) -> tuple[np.ndarray, list[np.ndarray], list[float]]:
    """The speeds computed (ascending), the stacked rows (force max, min, RMS, static force, DTE
    amplitude, [converged, ρ, closure, periods]) of one sweep over the ascending speeds ``s``, visited
    upwards or downwards, and the speeds where the sweep jumped (rad/s). With backlash each speed
    starts Newton from the periodic state of the speed before; where that fails (or the orbit found is
    unstable) the branch is followed by bisection from the last good orbit to within
    :data:`EDGE_RTOL` of the speed of its end, and where it ends short of the speed (a fold or a
    grazing) the last state is run for a while at the new speed before Newton (the jump)."""
    lin, plan = solver.lin, solver.plan
    J = len(lin.names)
    rows: dict[float, tuple[np.ndarray, ...]] = {}
    states: dict[float, np.ndarray] = {}
    jumps: list[float] = []

    def run(speed: float, *, start: np.ndarray | None = None, settle: bool = True, keep: bool = True) -> bool:
        t, x, v, ok = solver.solve(speed, start=start, settle=settle)
        good = ok and not solver.rho > 1.0 + UNSTABLE_MARGIN
        if not (good or keep):
            return False
        force, delta = _mesh_forces(lin, plan, speed, t, x, v)
        rows[speed] = (
            force.max(axis=0),
            force.min(axis=0),
            np.sqrt(np.mean(force**2, axis=0)),
            _static_forces(lin, speed),
            0.5 * np.ptp(delta, axis=0),
            np.array([ok, solver.rho, solver.closure, solver.multiple]),
        )
        if ok and solver.nonlinear:
            states[speed] = np.concatenate([x[0], v[0]])
        return good

    order = s if direction == "up" else s[::-1]
    previous = None
    for speed in order.tolist():
        if not solver.nonlinear:  # a unique solution at each speed
            run(speed)
            continue
        ok = run(speed, settle=previous is None)
        if not ok and previous is not None and previous in states:
            # the branch followed to its end by bisection from the last good orbit; where it ends short
            # of this speed (a fold or a grazing: the jump), the end is located and the last state run
            # at this speed for a while before Newton (the branch a slow sweep lands on)
            lo, hi = previous, speed
            while abs(hi - lo) > EDGE_RTOL * speed:
                mid = 0.5 * (lo + hi)
                if run(mid, start=states[lo], settle=False, keep=False):
                    lo = mid
                else:
                    hi = mid
            if not run(speed, start=states[lo], settle=False, keep=False):
                jumps.append(0.5 * (lo + hi))
                solver.start = states[lo]
                run(speed, settle=True)
        elif not ok and previous is not None:  # no orbit at the speed before: start afresh by a run
            run(speed, settle=True)
        previous = speed
    for _ in range(refine):
        grid = np.array(sorted(rows))
        amp = np.array([0.5 * (rows[g][0] - rows[g][1]) for g in grid]).reshape(grid.size, J)
        new: set[float] = set()
        for j in range(J):
            for i in _peaks(amp[:, j]):
                new.update({0.5 * (grid[i - 1] + grid[i]), 0.5 * (grid[i] + grid[i + 1])})
        new -= set(rows)
        if not new:
            break
        for speed in sorted(new, reverse=direction == "down"):
            start = None
            if solver.nonlinear:  # from the speed visited before it, on the same branch
                before = [g for g in states if (g < speed if direction == "up" else g > speed)]
                if before:
                    start = states[max(before) if direction == "up" else min(before)]
            run(float(speed), start=start)
    grid = np.array(sorted(rows))
    return grid, [np.array([rows[g][k] for g in grid]).reshape(grid.size, -1) for k in range(6)], jumps
