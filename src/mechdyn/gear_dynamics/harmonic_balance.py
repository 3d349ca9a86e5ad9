"""Harmonic balance: the periodic response of the linear periodic model in one linear solve.

x = Σ_p X_p exp(i p ω₀ t), p = −H … H, on the fundamental ω₀ of the common mesh period
(:func:`~mechdyn.gear_dynamics.periodic.period_plan`). The stiffness harmonics of mesh j, whose
frequency is the order m_j of ω₀, couple X_p to X_(p − h m_j), so one linear system in the
coefficients gives the response exactly up to the truncation (Nayfeh & Mook, *Nonlinear
Oscillations*, 1979, §5.4, Hill's determinant; Blankenship & Kahraman, *J. Sound Vib.* 185 (1995)
743–765 for gear pairs). The system is condensed onto the meshes' deflections (:func:`_hb_solve`);
its speed-independent part is assembled once per sweep (:func:`_balance`).

The coefficients of the stiffness and of the excitation k e are those of the piecewise-linear
interpolants of the sampled profiles, exactly (:func:`interpolant_harmonics`,
:func:`product_harmonics`): the method sees the same profile as the time-domain solvers. The fast
path of :mod:`.steady` and :mod:`.sweep` where no mesh has backlash (it is linear: teeth in contact).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechdyn.gear_dynamics.periodic import LinearPeriodic, PeriodPlan, interpolate

__all__ = ["interpolant_harmonics", "product_harmonics"]


def interpolant_harmonics(samples: np.ndarray, orders: np.ndarray) -> np.ndarray:
    """Exact Fourier coefficients of the periodic linear interpolant of samples.

    The interpolant is the samples convolved with the hat function of width 2/P, so its coefficient of
    order h is the discrete Fourier coefficient S_(h mod P) times sinc²(h/P) (e.g. Bracewell, *The
    Fourier Transform and Its Applications*, 3rd ed., 2000, ch. 10); f(τ) = Σ_h c_h exp(2πi h τ).

    Parameters
    ----------
    samples : ndarray
        (P,) values at τ = i/P, in their own unit.
    orders : ndarray
        Integer orders h (negative ones included), dimensionless.
    """
    P = samples.size
    S = np.fft.fft(samples) / P
    h = np.asarray(orders, int)
    return S[np.mod(h, P)] * np.sinc(h / P) ** 2


def _moments(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """I_k(θ) = ∫₀¹ u^k exp(−iθu) du for k = 0, 1, 2 (series near θ = 0, recursion elsewhere)."""
    th = np.asarray(theta, float)
    small = np.abs(th) < 0.5
    out = []
    z = -1j * th
    e = np.exp(z)
    with np.errstate(divide="ignore", invalid="ignore"):
        I0 = np.where(small, 0.0, (e - 1.0) / np.where(small, 1.0, z))
        I1 = np.where(small, 0.0, (e - I0) / np.where(small, 1.0, z))
        I2 = np.where(small, 0.0, (e - 2.0 * I1) / np.where(small, 1.0, z))
    for k, moment in enumerate((I0, I1, I2)):
        series = np.zeros(th.shape, complex)
        term = np.ones(th.shape, complex)
        for n in range(24):  # Σ (−iθ)^n / (n! (n + k + 1)), |θ| < 0.5: 24 terms reach 1e-30
            series = series + term / (n + k + 1)
            term = term * z / (n + 1)
        out.append(np.where(small, series, moment))
    return out[0], out[1], out[2]


def product_harmonics(a: np.ndarray, b: np.ndarray, orders: np.ndarray) -> np.ndarray:
    """Exact Fourier coefficients of the product of the periodic linear interpolants of two sample
    sets taken at the same phases τ = i/P.

    On each interval the product is a quadratic a_i + b_i u + c_i u² in u = Pτ − i, so its coefficient
    of order h is Σ_k DFT(coefficient k)_h · I_k(2πh/P) with I_k(θ) = ∫₀¹ u^k exp(−iθu) du (direct
    integration; with b ≡ 1 it reduces to :func:`interpolant_harmonics`).

    Parameters
    ----------
    a, b : ndarray
        (P,) samples of the two factors, in their own units (the product carries both).
    orders : ndarray
        Integer orders h, dimensionless.
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    P = a.size
    da, db = np.roll(a, -1) - a, np.roll(b, -1) - b
    c0, c1, c2 = a * b, a * db + b * da, da * db
    h = np.asarray(orders, int)
    I0, I1, I2 = _moments(2 * np.pi * h / P)
    idx = np.mod(h, P)
    out: np.ndarray = (
        np.fft.fft(c0)[idx] / P * I0 + np.fft.fft(c1)[idx] / P * I1 + np.fft.fft(c2)[idx] / P * I2
    )
    return out


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
