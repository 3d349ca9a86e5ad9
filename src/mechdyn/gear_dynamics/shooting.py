"""Shooting: the periodic orbit as the fixed point of the period map, with and without backlash.

Teeth in contact (linear): the one-period propagator [[Φ, y_p], [0, 1]] of the forced system (the
Magnus product or solve_ivp, :mod:`.propagators`) and y₀ = (I − Φ)⁻¹ y_p (e.g. Nayfeh & Balachandran,
*Applied Nonlinear Dynamics*, 1995, §7.1): :func:`_shoot_linear`.

With backlash the same fixed point y(T; y₀) = y₀ is found by Newton's method on the nonlinear flow,
integrated from one contact change to the next (located events, :class:`._nonsmooth.NonsmoothFlow`),
its Jacobian from the variational equations mapped by the saltation matrix at every contact change:
:func:`_shoot_nonlinear`. Newton starts near the attracting orbit, from a run of the flow for the
periods in which the slowest mode of the mean system decays (:func:`_warm_start`, :func:`_settle`).
Past a flip (a Floquet multiplier below −1) the orbit of one period is unstable and the stable orbit of
two periods born there is sought instead (:func:`_period_doubled`). The continuation over speed that
strings these orbits into branches is :mod:`.sweep`'s, and through a branch's folds (the same period
map with the speed an unknown, pseudo-arclength) :mod:`.continuation`'s.
"""

from __future__ import annotations

import numpy as np

from mechdyn.gear_dynamics._nonsmooth import FlowError, NonsmoothFlow
from mechdyn.gear_dynamics._stability import UNSTABLE_MARGIN, _spectral
from mechdyn.gear_dynamics.periodic import LinearPeriodic, PeriodPlan
from mechdyn.gear_dynamics.propagators import ivp_propagators, ordered_product, propagators, segments

__all__: list[str] = []

#: A Floquet multiplier is real where its imaginary part is below this fraction of its modulus.
_REAL_RTOL = 1e-9


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
