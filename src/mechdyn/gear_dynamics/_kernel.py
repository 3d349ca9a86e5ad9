"""The compiled right-hand side of a geared drivetrain in time (numba), its Jacobian and its events.

Imported on first use by :mod:`mechdyn.gear_dynamics.simulate`; compiled once and cached on disk. The
state is y = [z, ż, W_in, W_diss, W_par] with q = A z (z: the rigid-body
angle of each free branch and the deflections relative to it), so that the error control of the
integrator sees the small deflections, not the large rigid rotation.

Per flexible mesh j: δ = g·q, τ = ph·q (ph = z_a/(2π) × the row of θ_a), the profile p(τ) and the
error e(τ) interpolated linearly between P samples per cycle; contact mode 0 (drive side, or no
backlash: h = x), 1 (in the gap: no force) or 2 (back side: h = x + b), x = δ − e(τ), the force that
of the one contact law, :func:`._contact.mesh_force`. The mode is a discrete state the integrator's
events switch; the force does not read the sign of x, so that a root located a rounding error on
either side of the boundary cannot make it chatter. The events read x itself (linear in the state),
each boundary x = 0 and x = −b on its own: a product such as x (x + b) keeps its sign when a step
crosses the whole backlash.
"""

import numba
import numpy as np

from mechdyn.gear_dynamics._contact import GAP, mesh_force

__all__ = ["event_value", "event_values", "jacobian", "rhs"]


@numba.njit(cache=True, error_model="numpy")
def _interp(row, p, tau):
    """Value and slope (per cycle) of a periodic linear interpolant of row[:p] at phase tau."""
    x = tau * p
    base = np.floor(x)
    frac = x - base
    i = int(base) % p
    k = (i + 1) % p
    a = row[i]
    b = row[k]
    return a + (b - a) * frac, (b - a) * p


@numba.njit(cache=True, error_model="numpy")
def rhs(y, out, n, A, W, K, C, Q, G, PH, prof, err, P, kbar, cm, gap, mode):
    """dy/dt into ``out``; returns nothing. See the module docstring for the arguments."""
    q = np.zeros(n)
    qd = np.zeros(n)
    for i in range(n):
        s = 0.0
        sd = 0.0
        for k in range(n):
            s += A[i, k] * y[k]
            sd += A[i, k] * y[n + k]
        q[i] = s
        qd[i] = sd
    f = np.empty(n)
    w_in = 0.0
    w_diss = 0.0
    for i in range(n):
        s = Q[i]
        c = 0.0
        for k in range(n):
            s -= K[i, k] * q[k]
            c += C[i, k] * qd[k]
        f[i] = s - c
        w_in += Q[i] * qd[i]
        w_diss += qd[i] * c
    w_par = 0.0
    for j in range(G.shape[0]):
        d = 0.0
        dd = 0.0
        t = 0.0
        td = 0.0
        for k in range(n):
            d += G[j, k] * q[k]
            dd += G[j, k] * qd[k]
            t += PH[j, k] * q[k]
            td += PH[j, k] * qd[k]
        pj, dp = _interp(prof[j], P[j], t)
        e, de = _interp(err[j], P[j], t)
        xd = dd - de * td
        fj, h, active = mesh_force(kbar[j] * pj, cm[j], d - e, xd, gap[j], mode[j])
        if not active:
            continue
        for k in range(n):
            f[k] -= G[j, k] * fj
        w_diss += cm[j] * xd * xd
        w_par += 0.5 * kbar[j] * dp * td * h * h - de * td * fj
    for i in range(n):
        out[i] = y[n + i]
        s = 0.0
        for k in range(n):
            s += W[i, k] * f[k]
        out[n + i] = s
    out[2 * n] = w_in
    out[2 * n + 1] = w_diss
    out[2 * n + 2] = w_par


@numba.njit(cache=True, error_model="numpy")
def jacobian(y, n, A, W, K, C, G, PH, prof, P, kbar, cm, mode):
    """∂(dy/dt)/∂y with the meshes at their present stiffness (the phase's own dependence left out:
    an implicit integrator's Newton iteration needs an approximation only)."""
    q = np.zeros(n)
    for i in range(n):
        s = 0.0
        for k in range(n):
            s += A[i, k] * y[k]
        q[i] = s
    Ke = K.copy()
    Ce = C.copy()
    for j in range(G.shape[0]):
        if mode[j] == GAP:  # out of contact: the law's force depends on neither x nor ẋ
            continue
        t = 0.0
        for k in range(n):
            t += PH[j, k] * q[k]
        pj, _ = _interp(prof[j], P[j], t)
        kj = kbar[j] * pj
        for a in range(n):
            for b in range(n):
                gg = G[j, a] * G[j, b]
                Ke[a, b] += kj * gg
                Ce[a, b] += cm[j] * gg
    KA = Ke @ A
    CA = Ce @ A
    m = 2 * n + 3
    J = np.zeros((m, m))
    for i in range(n):
        J[i, n + i] = 1.0
    JK = W @ KA
    JC = W @ CA
    for i in range(n):
        for k in range(n):
            J[n + i, k] = -JK[i, k]
            J[n + i, n + k] = -JC[i, k]
    return J


@numba.njit(cache=True, error_model="numpy")
def event_values(y, n, A, G, PH, err, P, out):
    """x = δ − e(τ) of every mesh into ``out``, m: the contact boundaries are x = 0 and x = −b."""
    q = np.zeros(n)
    for i in range(n):
        s = 0.0
        for k in range(n):
            s += A[i, k] * y[k]
        q[i] = s
    for j in range(G.shape[0]):
        d = 0.0
        t = 0.0
        for k in range(n):
            d += G[j, k] * q[k]
            t += PH[j, k] * q[k]
        e, _ = _interp(err[j], P[j], t)
        out[j] = d - e


@numba.njit(cache=True, error_model="numpy")
def event_value(y, n, A, G, PH, err, P, j):
    """x = δ − e(τ) of mesh ``j`` alone, m (the root finder asks for one mesh at a time)."""
    d = 0.0
    t = 0.0
    for i in range(n):
        s = 0.0
        for k in range(n):
            s += A[i, k] * y[k]
        d += G[j, i] * s
        t += PH[j, i] * s
    e, _ = _interp(err[j], P[j], t)
    return d - e
