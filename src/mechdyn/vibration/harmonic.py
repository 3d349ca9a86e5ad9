"""Forced harmonic response: the dynamic stiffness K + iωC − ω²M, solved frequency by frequency.

For a load F e^{iωt} the steady state is X e^{iωt} with (K + iωC − ω²M) X = F (e.g. Rao,
*Mechanical Vibrations*, 6th ed., §6.14). Each frequency is one complex solve of the model's own
size, so memory does not grow with the number of frequencies: a sparse model (a drivetrain chain)
stays sparse and is factorised by SuperLU, a dense one (a machine on mounts) by LAPACK.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

__all__ = ["dynamic_stiffness", "harmonic_solve"]

# below this size a dense LAPACK solve beats building and factorising a sparse matrix
_DENSE_LIMIT = 200
_BLOCK_ENTRIES = 1 << 18  # 4 MiB of complex entries


def dynamic_stiffness(K: Any, C: Any, M: Any, omega: float | np.ndarray) -> Any:
    """The dynamic stiffness Z(ω) = K + iωC − ω²M (sparse in, sparse out).

    Parameters
    ----------
    K, C, M : ndarray or sparse array
        Stiffness (N/m or N·m/rad), damping (N·s/m or N·m·s/rad) and mass (kg or kg·m²), (n, n).
    omega : float or ndarray
        Circular frequency, rad/s (an array of shape (n_f, 1, 1) with dense (1, n, n) matrices gives
        a stack).

    Returns
    -------
    ndarray or sparse array
        (n, n) complex.
    """
    return K + (1j * omega) * C - omega**2 * M


def harmonic_solve(K: Any, C: Any, M: Any, F: Any, omega: Any) -> np.ndarray:
    """Steady-state amplitudes X(ω) of (K + iωC − ω²M) X = F at each frequency.

    Parameters
    ----------
    K, C, M : ndarray or sparse array
        (n, n) model matrices (SI).
    F : array_like
        (n,) load amplitudes, the same at every frequency, or (n_f, n), one row per frequency (SI:
        N or N·m).
    omega : array_like
        (n_f,) circular frequencies, rad/s.

    Returns
    -------
    ndarray
        (n_f, n) complex amplitudes (m or rad). Memory: the model's matrices and this output, never
        (n_f, n, n).
    """
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    F = np.asarray(F)
    n = F.shape[-1]
    rows = np.broadcast_to(F, (w.size, n))
    out = np.empty((w.size, n), dtype=complex)
    # all three sparse and the model large: SuperLU; any of them full (modal damping couples every
    # coordinate): LAPACK on blocks of frequencies
    sparse = all(sp.issparse(A) for A in (K, C, M)) and n > _DENSE_LIMIT
    if sparse:
        from scipy.sparse.linalg import splu

        K, C, M = (sp.csc_array(A, dtype=complex) for A in (K, C, M))
        for i, wi in enumerate(w):
            out[i] = splu(sp.csc_array(dynamic_stiffness(K, C, M, wi))).solve(rows[i].astype(complex))
        return out
    K, C, M = (A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float) for A in (K, C, M))
    # frequencies in blocks of at most _BLOCK_ENTRIES matrix entries: batched LAPACK calls for small
    # models, bounded memory for large ones
    step = max(1, _BLOCK_ENTRIES // (n * n))
    for lo in range(0, w.size, step):
        Z = dynamic_stiffness(K[None], C[None], M[None], w[lo : lo + step, None, None])
        out[lo : lo + step] = np.linalg.solve(Z, rows[lo : lo + step, :, None])[..., 0]
    return out
