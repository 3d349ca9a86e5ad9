"""Symmetric eigen solvers for K q = ω² M q (dense, banded and sparse paths).

A full mass matrix (a rigid machine on mounts, its inertia tensor coupling the coordinates) goes to LAPACK's
generalised solver. With M diagonal (a drivetrain), the problem becomes the standard one A y = λ y with A =
M^-½ K M^-½. A chain of disks gives a tridiagonal A and a geared tree a narrow band after reverse
Cuthill–McKee ordering, so the banded path avoids the dense O(n³) reduction (divide and conquer on the
tridiagonal); the sparse path (shift-invert Lanczos, ARPACK) returns the lowest modes of very large models.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as spla

__all__ = ["SOLVERS", "solve_eigen"]

Solver = Literal["auto", "dense", "banded", "sparse"]
SOLVERS: tuple[str, ...] = ("auto", "dense", "banded", "sparse")

_DENSE_LIMIT = 800
_BAND_LIMIT = 32


def _standard(K: sp.csr_array, mass: np.ndarray) -> tuple[sp.csr_array, np.ndarray]:
    d = 1.0 / np.sqrt(mass)
    D = sp.diags_array(d)
    return sp.csr_array(D @ K @ D), d


def _bandwidth(A: sp.csr_array) -> int:
    coo = A.tocoo()
    return int(np.abs(coo.row - coo.col).max()) if coo.nnz else 0


def _dense_array(A: Any) -> np.ndarray:
    """A sparse or dense matrix as a dense float array."""
    return A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)


def _dense(A: np.ndarray, k: int, B: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    n = A.shape[0]
    select = None if k == n else (0, k - 1)
    if B is None:
        return sla.eigh(A, subset_by_index=select, driver="evr" if select else "evd")
    return sla.eigh(A, B, subset_by_index=select, driver="gvx" if select else "gvd")


def solve_eigen(
    K: sp.csr_array | np.ndarray,
    mass: np.ndarray,
    *,
    n_modes: int | None = None,
    solver: Solver = "auto",
) -> tuple[np.ndarray, np.ndarray, str]:
    """Lowest eigenpairs of K q = λ M q for symmetric semi-definite K and positive-definite M.

    Parameters
    ----------
    K : sparse array or ndarray
        Stiffness, (n, n), symmetric positive semi-definite, in the model's SI units (N/m, N·m/rad).
    mass : ndarray
        Diagonal of M, (n,), all positive, in the model's SI units (kg, kg·m²); or the full (n, n)
        symmetric positive-definite M, which is solved densely (LAPACK ``sygvd``/``sygvx``).
    n_modes : int, optional
        Number of lowest eigenpairs; all when None.
    solver : {"auto", "dense", "banded", "sparse"}
        ``dense``: LAPACK ``syevr`` via :func:`scipy.linalg.eigh`. ``banded``: reverse Cuthill–McKee
        ordering, then LAPACK ``dstevd`` (band 1, all pairs), ``dstebz``/``dstein`` (band 1, lowest
        pairs) or :func:`scipy.linalg.eig_banded`. ``sparse``: :func:`scipy.sparse.linalg.eigsh`
        in shift-invert mode just below zero (needs ``n_modes`` < n − 1). ``auto`` picks dense for
        small models, banded when the reordered band is narrow (chains, geared trees), sparse for a
        few modes of a wide-band model, dense otherwise.

    Returns
    -------
    lam : ndarray
        Eigenvalues λ = ω², ascending, (rad/s)².
    Q : ndarray
        M-normalised eigenvectors (Qᵀ M Q = I), one per column.
    used : str
        The solver that ran.
    """
    if solver not in SOLVERS:
        raise ValueError(f"unknown eigen solver {solver!r}; expected one of {', '.join(SOLVERS)}")
    mass = np.asarray(mass, dtype=float)
    n = mass.shape[0]
    k = n if n_modes is None else max(1, min(int(n_modes), n))
    if mass.ndim == 2:
        if np.count_nonzero(mass - np.diag(np.diagonal(mass))):
            Kd = _dense_array(K)
            lam, Q = _dense(Kd, k, mass)
            return np.asarray(lam), Q, "dense"
        mass = np.diagonal(mass).copy()
    if n <= _DENSE_LIMIT and solver in ("auto", "dense"):
        # small models: no sparse round trip (it costs more than the solve below ~50 coordinates)
        d = 1.0 / np.sqrt(mass)
        Kd = _dense_array(K)
        lam, Y = _dense(d[:, None] * Kd * d[None, :], k)
        return np.asarray(lam), d[:, None] * Y, "dense"
    A, d = _standard(sp.csr_array(K), mass)
    perm = None
    if solver == "auto":
        if n <= _DENSE_LIMIT:
            solver = "dense"
        else:
            perm = csgraph.reverse_cuthill_mckee(A, symmetric_mode=True)
            if _bandwidth(A[perm][:, perm]) <= _BAND_LIMIT:
                solver = "banded"
            elif k < n // 10 and k < 200:
                solver = "sparse"
            else:
                solver = "dense"
    if solver == "sparse" and k >= n - 1:
        solver = "dense"
    if solver == "dense":
        lam, Y = _dense(A.toarray(), k)
    elif solver == "banded":
        if perm is None:
            perm = csgraph.reverse_cuthill_mckee(A, symmetric_mode=True)
        Ap = A[perm][:, perm]
        b = _bandwidth(Ap)
        select = "a" if k == n else "i"
        rng = None if k == n else (0, k - 1)
        if b == 0:
            lam_p = Ap.diagonal()
            order = np.argsort(lam_p)[:k]
            lam, Yp = lam_p[order], np.eye(n)[:, order]
        elif b == 1:
            diag, off = Ap.diagonal(), Ap.diagonal(1)
            if k == n:  # divide and conquer (LAPACK dstevd): all pairs, far faster than MRRR here
                lam, Yp, info = sla.lapack.dstevd(diag, off, compute_v=1)
                if info != 0:
                    raise np.linalg.LinAlgError(f"LAPACK dstevd failed (info = {info})")
            else:  # bisection and inverse iteration: O(n k) for the k lowest pairs
                lam, Yp = sla.eigh_tridiagonal(diag, off, select="i", select_range=rng, lapack_driver="stebz")
        else:
            band = np.zeros((b + 1, n))
            for i in range(b + 1):
                band[i, : n - i] = Ap.diagonal(i)
            lam, Yp = sla.eig_banded(band, lower=True, select=select, select_range=rng)
        # back to the original order and M-normalised in one pass: Q[perm] = D[perm] Yp
        Yp *= d[perm][:, None]
        return np.asarray(lam), Yp[np.argsort(perm)], solver
    elif solver == "sparse":
        scale = float(np.abs(A.diagonal()).max())
        sigma = -1e-9 * scale
        lam, Y = spla.eigsh(A.tocsc(), k=k, sigma=sigma, which="LM")
        order = np.argsort(lam)
        lam, Y = lam[order], Y[:, order]
    return np.asarray(lam), d[:, None] * Y, solver
