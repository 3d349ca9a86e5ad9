"""Small dense systems in bulk: LU with partial pivoting, determinant and solution in one pass.

Many small systems (one per crank angle) share nothing but their size; NumPy's batched ``solve``
and ``det`` each factor them again. This compiled kernel factors each once (Doolittle LU with row
pivoting, e.g. Golub & Van Loan, *Matrix Computations*, §3.4) and returns both.
"""

from __future__ import annotations

import numpy as np

__all__ = ["solve_with_det"]

_KERNEL = None


def _kernel():
    global _KERNEL
    if _KERNEL is None:
        import numba

        from mechdyn._compiled import announce

        @numba.njit(cache=True)
        def run(A, b, x, det):
            K, n, _ = A.shape
            for k in range(K):
                a = A[k].copy()
                y = b[k].copy()
                d = 1.0
                for c in range(n):
                    p = c
                    big = abs(a[c, c])
                    for r in range(c + 1, n):
                        if abs(a[r, c]) > big:
                            big = abs(a[r, c])
                            p = r
                    if p != c:
                        for j in range(n):
                            a[c, j], a[p, j] = a[p, j], a[c, j]
                        y[c], y[p] = y[p], y[c]
                        d = -d
                    piv = a[c, c]
                    d *= piv
                    if piv == 0.0:
                        continue
                    for r in range(c + 1, n):
                        f = a[r, c] / piv
                        if f != 0.0:
                            for j in range(c + 1, n):
                                a[r, j] -= f * a[c, j]
                            y[r] -= f * y[c]
                det[k] = d
                for r in range(n - 1, -1, -1):
                    s = y[r]
                    for j in range(r + 1, n):
                        s -= a[r, j] * x[k, j]
                    x[k, r] = s / a[r, r] if a[r, r] != 0.0 else np.nan

        announce(run)
        _KERNEL = run
    return _KERNEL


def solve_with_det(A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve A x = b for a stack of square systems and return (x, det A).

    Parameters
    ----------
    A : ndarray
        (..., n, n).
    b : ndarray
        (..., n).

    Returns
    -------
    x : ndarray
        (..., n); NaN where A is exactly singular.
    det : ndarray
        (...) determinants.
    """
    shape = A.shape[:-2]
    n = A.shape[-1]
    Af = np.ascontiguousarray(A, dtype=float).reshape(-1, n, n)
    bf = np.ascontiguousarray(np.broadcast_to(b, (*shape, n)), dtype=float).reshape(-1, n)
    x = np.empty_like(bf)
    det = np.empty(Af.shape[0])
    _kernel()(Af, bf, x, det)
    return x.reshape(*shape, n), det.reshape(shape)
