"""Propagators of the linear periodic model over its period, and the monodromy matrix.

The first-order form of :class:`~mechdyn.gear_dynamics.periodic.LinearPeriodic`, y = (x, ẋ),
ẏ = A(t) y (:func:`system_matrices`, augmented by a constant 1 with the forcing in its last column),
is propagated over uniform segments of one period T: ``"magnus"``, a product of matrix exponentials
with the fourth-order Magnus step (Blanes, Casas, Oteo & Ros, *Physics Reports* 470, 2009, eq. 253),
exact when the stiffness is constant on each segment (:func:`propagators`, :func:`expm_stack`); or
``"ivp"``, the state-transition matrix of each segment integrated by
:func:`scipy.integrate.solve_ivp` (DOP853) at tight tolerance (:func:`ivp_propagators`). Their ordered
product (:func:`ordered_product`) over the period is the monodromy matrix Φ(T) (:func:`monodromy`),
whose eigenvalues are the Floquet multipliers (:mod:`.floquet`); with the forcing it is the
one-period map that linear shooting solves for the periodic orbit (:mod:`.shooting`).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, Literal

import numpy as np

from mechdyn.checks import check_count
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics.periodic import (
    Boundary,
    LinearPeriodic,
    PeriodPlan,
    _check_speed,
    _highest_frequency,
    interpolate,
    interpolated_slope,
    linear_periodic,
    period_plan,
)

__all__ = [
    "expm_stack",
    "ivp_propagators",
    "monodromy",
    "ordered_product",
    "propagators",
    "segments",
    "system_matrices",
]

Integrator = Literal["magnus", "ivp"]

_ATOL_PER_RTOL = 1e-3  # solve_ivp's absolute tolerance per relative one (the states are of order 1)
#: The most Magnus segments per period the accuracy rule of :func:`segments` adds up to.
MAX_SEGMENTS = 1 << 16


def _phases(lin: LinearPeriodic, plan: PeriodPlan, t_over_T: np.ndarray) -> np.ndarray:
    """(J, N) mesh phases τ_j at fractions of the period (meshes held at mean: phase 0)."""
    return (plan.signs * plan.orders)[:, None] * np.asarray(t_over_T, float)[None, :]


def _stiffness_matrices(lin: LinearPeriodic, plan: PeriodPlan, t_over_T: np.ndarray) -> np.ndarray:
    """(N, m, m) K(t) at fractions of the period."""
    tau = _phases(lin, plan, t_over_T)
    K = np.broadcast_to(lin.K, (tau.shape[1], lin.m, lin.m)).copy()
    for j in range(len(lin.names)):
        k = lin.mean_stiffness[j] * (interpolate(lin.profiles[j], tau[j]) if plan.orders[j] else 1.0)
        K += np.multiply.outer(np.broadcast_to(k, tau.shape[1]), np.outer(lin.G[j], lin.G[j]))
    return K


def _excitation(lin: LinearPeriodic, plan: PeriodPlan, speed: float, t_over_T: np.ndarray) -> np.ndarray:
    """(N, m) F(t): constant load plus Σ_j g_j (k_j e_j + c_j ė_j) at fractions of the period, N·m."""
    tau = _phases(lin, plan, t_over_T)
    F = np.broadcast_to(lin.force(speed), (tau.shape[1], lin.m)).copy()
    omega0 = plan.fundamental * speed  # fundamental in cycles per second
    for j in range(len(lin.names)):
        if not plan.orders[j] or not np.any(lin.errors[j]):
            continue
        k = lin.mean_stiffness[j] * interpolate(lin.profiles[j], tau[j])
        e = interpolate(lin.errors[j], tau[j])
        rate = plan.signs[j] * plan.orders[j] * omega0  # dτ/dt, cycles/s
        e_dot = interpolated_slope(lin.errors[j], tau[j]) * rate
        F += np.multiply.outer(k * e + lin.mesh_damping[j] * e_dot, lin.G[j])
    return F


def system_matrices(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, t_over_T: np.ndarray, *, forced: bool
) -> np.ndarray:
    """(N, d, d) first-order system matrices A(t) at fractions of the period.

    The state is y = (x, ẋ); A = [[0, I], [−M⁻¹K(t), −M⁻¹C]]; with ``forced`` the state is augmented
    by a constant 1 and the last column carries (0, M⁻¹F(t)), so that one propagator holds both the
    state-transition matrix and the particular solution.

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    speed : float
        Reference speed Ω, rad/s.
    t_over_T : ndarray
        Times as fractions of the period, dimensionless.
    forced : bool
        Augment by the forcing column.
    """
    m = lin.m
    N = np.asarray(t_over_T).size
    d = 2 * m + (1 if forced else 0)
    A = np.zeros((N, d, d))
    Minv = np.linalg.inv(lin.M)
    A[:, :m, m : 2 * m] = np.eye(m)
    A[:, m : 2 * m, :m] = -Minv @ _stiffness_matrices(lin, plan, t_over_T)
    A[:, m : 2 * m, m : 2 * m] = -Minv @ lin.C
    if forced:
        A[:, m : 2 * m, 2 * m] = _excitation(lin, plan, speed, t_over_T) @ Minv.T
    return A


_PADE13 = (
    64764752532480000.0,
    32382376266240000.0,
    7771770303897600.0,
    1187353796428800.0,
    129060195264000.0,
    10559470521600.0,
    670442572800.0,
    33522128640.0,
    1323241920.0,
    40840800.0,
    960960.0,
    16380.0,
    182.0,
    1.0,
)


def expm_stack(A: np.ndarray) -> np.ndarray:
    """Matrix exponentials of a stack of square matrices, (N, d, d).

    Scaling and squaring with the [13/13] Padé approximant (Higham, *SIAM J. Matrix Anal. Appl.* 26,
    2005, Algorithm 2.3), one scaling for the whole stack; vectorised, unlike a loop of
    :func:`scipy.linalg.expm` calls.

    Parameters
    ----------
    A : ndarray
        (N, d, d) matrices, in the unit of their entries times time (dimensionless).
    """
    A = np.asarray(A, float)
    if A.size == 0:
        return A.copy()
    d = A.shape[-1]
    norm = float(np.abs(A).sum(axis=-2).max())
    s = max(0, math.ceil(math.log2(norm / 5.371920351148152))) if norm > 0 else 0
    A = A / 2.0**s
    b = _PADE13
    eye = np.broadcast_to(np.eye(d), A.shape)
    A2 = A @ A
    A4 = A2 @ A2
    A6 = A4 @ A2
    U = A @ (A6 @ (b[13] * A6 + b[11] * A4 + b[9] * A2) + b[7] * A6 + b[5] * A4 + b[3] * A2 + b[1] * eye)
    V = A6 @ (b[12] * A6 + b[10] * A4 + b[8] * A2) + b[6] * A6 + b[4] * A4 + b[2] * A2 + b[0] * eye
    R = np.linalg.solve(V - U, V + U)
    for _ in range(s):
        R = R @ R
    return R


def ordered_product(E: np.ndarray) -> np.ndarray:
    """E[N−1] ⋯ E[1] E[0] of a stack (N, d, d), by pairwise products (log₂ N vectorised steps).

    Parameters
    ----------
    E : ndarray
        (N, d, d) propagators of consecutive segments, dimensionless.
    """
    E = np.asarray(E)
    while E.shape[0] > 1:
        if E.shape[0] % 2:
            last = E[-1:]
            E = np.concatenate([E[1:-1:2] @ E[0:-1:2], last], axis=0)
        else:
            E = E[1::2] @ E[0::2]
    return E[0]


def segments(lin: LinearPeriodic, plan: PeriodPlan, substeps: int, speed: float | None = None) -> int:
    """Segments per period for the Magnus product.

    Every profile sample interval of every mesh is a whole number of segments where the lengths allow
    (then the product is exact for piecewise constant and fourth-order for piecewise linear
    stiffness), at least ``substeps`` per interval; at ``speed`` the count is raised (by whole
    multiples, up to :data:`MAX_SEGMENTS`) until a segment spans at most 0.1 rad of the highest
    natural frequency, where the fourth-order error of a varying segment falls below about 1e-8.

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    substeps : int
        Segments per profile sample interval, a count.
    speed : float, optional
        Reference speed Ω, rad/s.
    """
    counts = [
        p.size * int(o)
        for p, e, o in zip(lin.profiles, lin.errors, plan.orders, strict=True)
        if o and (np.ptp(p) > 0 or np.ptp(e) > 0)
    ]
    if not counts:
        return max(1, substeps)
    common = math.lcm(*counts)
    n = substeps * (common if common <= 16 * max(counts) else max(counts))
    if speed is not None:
        need = _highest_frequency(lin) * plan.period(speed) / 0.1
        n *= max(1, min(math.ceil(need / n), MAX_SEGMENTS // n))
    return n


def propagators(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, n_segments: int, *, forced: bool
) -> np.ndarray:
    """(N, d, d) fourth-order Magnus propagators of N uniform segments of one period.

    exp(Ω_k) with Ω_k = h/2 (A₁ + A₂) + (√3/12) h² [A₂, A₁], A at the two Gauss points of the segment
    (Blanes, Casas, Oteo & Ros, *Physics Reports* 470, 2009, eq. 253); exact when A is constant on it.

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    speed : float
        Reference speed Ω, rad/s.
    n_segments : int
        Segments per period, a count.
    forced : bool
        Augment by the forcing (see :func:`system_matrices`).
    """
    T = plan.period(speed)
    h = 1.0 / n_segments
    start = np.arange(n_segments) * h
    g1, g2 = 0.5 - math.sqrt(3) / 6, 0.5 + math.sqrt(3) / 6
    A1 = system_matrices(lin, plan, speed, start + g1 * h, forced=forced)
    A2 = system_matrices(lin, plan, speed, start + g2 * h, forced=forced)
    dt = T * h
    Om = 0.5 * dt * (A1 + A2) + (math.sqrt(3) / 12) * dt**2 * (A2 @ A1 - A1 @ A2)
    return expm_stack(Om)


def ivp_propagators(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, n_segments: int, *, forced: bool, rtol: float = 1e-11
) -> np.ndarray:
    """(N, d, d) state-transition matrices of N uniform segments of one period, by solve_ivp.

    Each segment is integrated on its own (DOP853 from the identity), so that no step straddles a
    corner of the piecewise linear stiffness when the segments follow the profile samples
    (:func:`segments` with ``substeps=1``).

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    speed : float
        Reference speed Ω, rad/s.
    n_segments : int
        Segments per period, a count.
    forced : bool
        Augment by the forcing (see :func:`system_matrices`).
    rtol : float
        Relative tolerance of the integration, dimensionless.
    """
    from scipy.integrate import solve_ivp

    T = plan.period(speed)
    d = 2 * lin.m + (1 if forced else 0)
    out = np.empty((n_segments, d, d))
    edges = T * np.arange(n_segments + 1) / n_segments

    # A(t) = A₀ + Σ_j k_j(t) B_j (+ the forcing column), its parts computed once
    m = lin.m
    A0 = system_matrices(
        lin, replace(plan, orders=np.zeros_like(plan.orders)), speed, np.zeros(1), forced=forced
    )[0]
    Minv = np.linalg.inv(lin.M)
    A0[m : 2 * m, :m] = -Minv @ lin.K
    if forced:
        A0[m : 2 * m, 2 * m] = Minv @ lin.force(speed)
    B = [-(Minv @ np.outer(g, g)) for g in lin.G]
    MG = [Minv @ g for g in lin.G]
    f0 = plan.fundamental * speed
    o = plan.orders * plan.signs

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        A = A0.copy()
        for j in range(len(B)):
            tau = o[j] * f0 * t
            k = lin.mean_stiffness[j] * (float(interpolate(lin.profiles[j], tau)) if o[j] else 1.0)
            A[m : 2 * m, :m] += k * B[j]
            if forced and o[j] and lin.errors[j].any():
                e = float(interpolate(lin.errors[j], tau))
                e_dot = float(interpolated_slope(lin.errors[j], tau)) * o[j] * f0
                A[m : 2 * m, 2 * m] += (k * e + lin.mesh_damping[j] * e_dot) * MG[j]
        return (A @ y.reshape(d, d)).ravel()

    for k in range(n_segments):
        sol = solve_ivp(
            rhs,
            (edges[k], edges[k + 1]),
            np.eye(d).ravel(),
            method="DOP853",
            rtol=rtol,
            atol=rtol * _ATOL_PER_RTOL,
        )
        if not sol.success:  # pragma: no cover - DOP853 on a linear system with bounded coefficients
            raise ModelError(f"the state-transition matrix could not be integrated: {sol.message}")
        out[k] = sol.y[:, -1].reshape(d, d)
    return out


def _check_method(method: str) -> None:
    if method not in ("magnus", "ivp"):
        raise ModelError(
            f"method {method!r}: give 'magnus' (product of matrix exponentials) or 'ivp' (solve_ivp)",
            element="gear dynamics",
            field="method",
        )


def _monodromy(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, method: str, substeps: int, rtol: float = 1e-11
) -> np.ndarray:
    if method == "ivp":
        return ordered_product(
            ivp_propagators(lin, plan, speed, segments(lin, plan, 1), forced=False, rtol=rtol)
        )
    return ordered_product(propagators(lin, plan, speed, segments(lin, plan, substeps, speed), forced=False))


def monodromy(
    system: Any,
    speed: float,
    *,
    reference: str,
    boundary: Boundary = "prescribed",
    method: Integrator = "magnus",
    substeps: int = 4,
) -> np.ndarray:
    """The monodromy matrix Φ(T) of a drivetrain's linear vibration at a constant speed.

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain (backlash ignored: teeth in contact).
    speed : float
        Speed Ω of the reference disk, rad/s, positive.
    reference : str
        The disk turning at Ω.
    boundary : {"prescribed", "free"}
        How the rigid-body motion is removed (see :func:`.periodic.linear_periodic`).
    method : {"magnus", "ivp"}
        Product of fourth-order Magnus exponentials over uniform segments, or solve_ivp (DOP853,
        rtol 1e-11) on the state-transition matrix.
    substeps : int
        Magnus segments per profile sample interval, a count from 1 to 1000.

    Returns
    -------
    ndarray
        (2m, 2m) Φ(T) on the state (x, ẋ), dimensionless and 1/s, s blocks; T is the common mesh
        period (:func:`.periodic.period_plan`).

    Notes
    -----
    Floquet theory of linear periodic systems: Nayfeh & Mook, *Nonlinear Oscillations* (1979), §5.2.
    """
    _check_method(method)
    substeps = check_count("gear dynamics", "substeps", substeps, low=1, high=1000, what="substeps")
    lin = linear_periodic(system, reference=reference, boundary=boundary)
    speed = _check_speed("speed", speed)
    return _monodromy(lin, period_plan(lin), speed, method, substeps)
