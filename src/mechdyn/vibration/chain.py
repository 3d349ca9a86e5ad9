"""A chain's natural frequencies to high relative accuracy: the Cholesky factor of a chain's
stiffness is bidiagonal without a subtraction, and the singular values of a bidiagonal matrix are
found to high relative accuracy (Golub–Kahan; Demmel & Kahan, SIAM J. Sci. Stat. Comput. 11 (1990)
873–912), with a count of those below a bound from the Golub–Kahan tridiagonal's Sturm sequence to
verify them. Used by :func:`mechdyn.vibration.solve_eigen` where the model is a chain."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

__all__ = ["bidiagonal_chain", "golub_kahan", "verified"]

_TINY = float(np.finfo(float).tiny)


def bidiagonal_chain(F: sp.csr_array, mass: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The Golub–Kahan off-diagonal of a lower bidiagonal W with W Wᵀ = P A Pᵀ, or None if not a chain.

    A chain: every row of F holds one coordinate (a grounded spring) or two that are neighbours in the
    reverse Cuthill–McKee order, and no two rows join the same neighbours. Cholesky factorisation
    along that order, K = L Lᵀ, then needs no subtraction: with e_p the stiffness that holds
    coordinate p to the ground through the coordinates before it, d_p = e_p + a_p² and
    e_(p+1) = g_(p+1) + b_p² e_p / d_p (row (a_p, b_p) between p and p+1, g the grounded springs), so
    every entry of W = M^-½ L is found to a few ulps: W_pp = √(d_p/m_p),
    W_(p+1,p) = a_p b_p / √(d_p m_(p+1)).
    """
    n = mass.size
    nnz = np.diff(F.indptr)
    if nnz.max(initial=0) > 2:
        return None
    P = abs(F)
    perm = csgraph.reverse_cuthill_mckee(sp.csr_array(P.T @ P), symmetric_mode=True)
    pos = np.empty(n, dtype=int)
    pos[perm] = np.arange(n)
    two = np.flatnonzero(nnz == 2)
    one = np.flatnonzero(nnz == 1)
    starts = F.indptr[two]
    ca, cb = pos[F.indices[starts]], pos[F.indices[starts + 1]]
    va, vb = F.data[starts], F.data[starts + 1]
    swap = ca > cb
    ca, cb = np.where(swap, cb, ca), np.where(swap, ca, cb)
    va, vb = np.where(swap, vb, va), np.where(swap, va, vb)
    if np.any(cb - ca != 1) or np.bincount(ca, minlength=n).max(initial=0) > 1:
        return None
    a = np.zeros(n)
    b = np.zeros(n)
    a[ca], b[ca] = va, vb
    g = np.zeros(n)
    np.add.at(g, pos[F.indices[F.indptr[one]]], F.data[F.indptr[one]] ** 2)
    if not g.any():  # nothing grounds the chain: e ≡ 0 and W is G itself, reordered
        dd = a**2
    else:
        dd = np.empty(n)
        e_p = 0.0
        for p in range(n):
            e_p += g[p]
            dd[p] = e_p + a[p] * a[p]
            e_p = b[p] * b[p] * e_p / dd[p] if dd[p] > 0 else 0.0
    mp = mass[perm]
    w_diag = np.sqrt(dd / mp)
    root = np.sqrt(np.where(dd > 0, dd, 1.0))
    w_sub = np.where(dd[:-1] > 0, a[:-1] * b[:-1] / (root[:-1] * np.sqrt(mp[1:])), 0.0)
    e = np.empty(2 * n - 1)
    e[0::2] = w_diag
    e[1::2] = w_sub
    return e, perm


def _tgk_count(e: np.ndarray, x: float) -> int:
    """Number of eigenvalues ≤ x of the Golub–Kahan matrix (zero diagonal, off-diagonal e).

    LAPACK ``dstebz`` over (−big, x] with a tolerance wider than the interval: its Sturm counts and no
    bisection step.
    """
    big = 2.0 * float(np.abs(e).max(initial=1.0)) + abs(x) + 1.0
    m, *_, info = sla.lapack.dstebz(np.zeros(e.size + 1), e, 1, -big, x, 0, 0, 2 * big, b"B")
    if info != 0:
        raise np.linalg.LinAlgError(f"LAPACK dstebz failed (info = {info})")
    return int(m)


def verified(e: np.ndarray, n: int, z: int, sigma: np.ndarray, accuracy: float) -> bool:
    """Whether the j-th flexible singular value lies within accuracy/2 (relative) of sigma[j], every j.

    The Golub–Kahan matrix has n − z negative eigenvalues and 2z zeros below the flexible σ, so σ_j
    (0-based among the flexible ones) is its eigenvalue number n + z + j (0-based).
    """
    tau = accuracy / 2.0
    for j, s in enumerate(sigma):
        if not s > 0:
            return False
        if not _tgk_count(e, s * (1.0 - tau)) <= n + z + j < _tgk_count(e, s * (1.0 + tau)):
            return False
    return True


def golub_kahan(
    e: np.ndarray, perm: np.ndarray, mass: np.ndarray, z: int, n_flex: int
) -> tuple[np.ndarray, np.ndarray]:
    """The z rigid-body and the n_flex lowest flexible pairs of a chain from its bidiagonal factor.

    Bisection to full relative accuracy (LAPACK ``dstebz``) and inverse iteration (``dstein``) on the
    Golub–Kahan form; its eigenvector for σ interleaves the right and left singular vectors of Wᵀ, and
    the right ones (even entries) are the eigenvectors of A = W Wᵀ.
    """
    n = mass.size
    m = e.size + 1
    d = 1.0 / np.sqrt(mass[perm])
    Yp = np.zeros((n, z + n_flex))
    lam = np.zeros(z + n_flex)
    # rigid-body modes: a zero W_pp ends a free group; y solves Wᵀ y = 0 along the group
    w_diag, w_sub = e[0::2], e[1::2]
    ends = np.flatnonzero(w_diag == 0)
    breaks = np.flatnonzero(w_sub == 0)  # W_(p+1,p) = 0: p ends a group
    for r, end in enumerate(ends[:z]):
        before = breaks[breaks < end]
        start = int(before[-1]) + 1 if before.size else 0
        ratio = -w_sub[start:end] / w_diag[start:end]  # y_p = ratio_p y_(p+1)
        logs = np.concatenate([np.cumsum(np.log(np.abs(ratio))[::-1])[::-1], [0.0]])
        signs = np.concatenate([np.cumprod(np.sign(ratio)[::-1])[::-1], [1.0]])
        y = signs * np.exp(logs - logs.max())
        Yp[start : end + 1, r] = y / np.linalg.norm(y)
    il = n + z + 1
    mm, w, iblock, isplit, info = sla.lapack.dstebz(
        np.zeros(m), e, 2, 0.0, 0.0, il, il + n_flex - 1, 2 * _TINY, b"B"
    )
    if info != 0 or mm != n_flex:
        raise np.linalg.LinAlgError(f"LAPACK dstebz failed (info = {info})")
    Z, info = sla.lapack.dstein(np.zeros(m), e, w[:mm], iblock, isplit)
    if info != 0:
        raise np.linalg.LinAlgError(f"LAPACK dstein failed (info = {info})")
    order = np.argsort(w[:mm], kind="stable")
    U = Z[0::2, order]
    Yp[:, z:] = U / np.linalg.norm(U, axis=0)
    lam[z:] = w[:mm][order] ** 2
    Q = np.empty_like(Yp)
    Q[perm] = d[:, None] * Yp
    return lam, Q
