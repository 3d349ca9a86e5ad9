"""Forced harmonic response: the dynamic stiffness K + iωC − ω²M, solved frequency by frequency,
or the same response summed over the modes where the damping does not couple them.

For a load F e^{iωt} the steady state is X e^{iωt} with (K + iωC − ω²M) X = F (e.g. Rao,
*Mechanical Vibrations*, 6th ed., §6.14). :func:`harmonic_solve` does one complex solve of the
model's own size per frequency, so memory does not grow with the number of frequencies: a sparse
model (a drivetrain chain) stays sparse and is factorised by SuperLU, a dense one (a machine on
mounts) by LAPACK. :func:`modal_superposition` sums the complete set of M-normalised modes instead,
exact when ΦᵀCΦ is diagonal (modal or proportional damping): one matrix product per block of
frequencies.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from mechdyn.checks import check_array
from mechdyn.errors import ModelError

__all__ = ["dynamic_stiffness", "finite_matrices", "finite_response", "harmonic_solve", "modal_superposition"]

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
        Circular frequency, rad/s, finite and at most 1e8 rad/s in magnitude (an array of shape
        (n_f, 1, 1) with dense (1, n, n) matrices gives a stack).

    Returns
    -------
    ndarray or sparse array
        (n, n) complex.

    Raises
    ------
    mechdyn.errors.ModelError
        For a frequency that is not finite or beyond any machine.
    """
    omega = check_array("dynamic stiffness", "omega", omega, "rad/s", what="circular frequencies")
    return K + (1j * omega) * C - omega**2 * M


def finite_matrices(owner: str, **matrices: Any) -> None:
    """Refuse a model matrix (dense or sparse) with a NaN or an infinity, naming it and the entry.

    Parameters
    ----------
    owner : str
        The analysis, for the message.
    **matrices : ndarray or sparse array
        The matrices by name (``K=..., M=...``).

    Raises
    ------
    mechdyn.errors.ModelError
        Naming the matrix, the first entry that is not finite and its value.
    """
    for name, A in matrices.items():
        if sp.issparse(A):
            coo = sp.coo_array(A)
            bad = ~np.isfinite(coo.data)
            if bad.any():
                k = int(np.argmax(bad))
                i, j, v = int(coo.coords[0][k]), int(coo.coords[1][k]), coo.data[k]
                raise ModelError(
                    f"{name}[{i}, {j}] = {v} is not finite; give finite matrices in SI",
                    element=owner,
                    field=name,
                )
        else:
            check_array(
                owner, name, A, complex_values=np.iscomplexobj(A), bounded=False, what="entries in SI"
            )


def harmonic_solve(K: Any, C: Any, M: Any, F: Any, omega: Any) -> np.ndarray:
    """Steady-state amplitudes X(ω) of (K + iωC − ω²M) X = F at each frequency.

    Parameters
    ----------
    K, C, M : ndarray or sparse array
        (n, n) model matrices (SI).
    F : array_like
        (n,) load amplitudes, the same at every frequency, or (n_f, n), one row per frequency (SI:
        N or N·m), finite.
    omega : array_like
        (n_f,) circular frequencies, rad/s, finite, at most 1e8 rad/s in magnitude.

    Returns
    -------
    ndarray
        (n_f, n) complex amplitudes (m or rad). Memory: the model's matrices and this output, never
        (n_f, n, n).

    Raises
    ------
    mechdyn.errors.ModelError
        For a NaN or an infinity in the matrices, a frequency or a load out of range, or a dynamic
        stiffness that is singular at a frequency (an undamped resonance, a free body at 0 rad/s).
    """
    w = np.atleast_1d(check_array("harmonic response", "omega", omega, "rad/s", what="circular frequencies"))
    F = check_array("harmonic response", "F", F, complex_values=True, bounded=False, what="load amplitudes")
    finite_matrices("harmonic response", K=K, C=C, M=M)
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
            try:
                lu = splu(sp.csc_array(dynamic_stiffness(K, C, M, wi)))
            except RuntimeError as exc:  # "Factor is exactly singular"
                raise _singular(wi) from exc
            out[i] = lu.solve(rows[i].astype(complex))
        return finite_response(out, w)
    K, C, M = (A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float) for A in (K, C, M))
    # frequencies in blocks of at most _BLOCK_ENTRIES matrix entries: batched LAPACK calls for small
    # models, bounded memory for large ones
    step = max(1, _BLOCK_ENTRIES // (n * n))
    for lo in range(0, w.size, step):
        Z = dynamic_stiffness(K[None], C[None], M[None], w[lo : lo + step, None, None])
        try:
            out[lo : lo + step] = np.linalg.solve(Z, rows[lo : lo + step, :, None])[..., 0]
        except np.linalg.LinAlgError:
            bad = next(i for i in range(Z.shape[0]) if _is_singular(Z[i]))
            raise _singular(w[lo + bad]) from None
    return finite_response(out, w)


def modal_superposition(
    shapes: np.ndarray, lam: np.ndarray, damping: np.ndarray, load: np.ndarray, omega: Any
) -> np.ndarray:
    """Steady-state amplitudes summed over a complete set of modes with uncoupled damping.

    Parameters
    ----------
    shapes : ndarray
        (n_out, n_modes) the M-normalised modes (ΦᵀMΦ = I, all n of them) at the wanted outputs: one
        row per output coordinate (m or rad per unit modal amplitude).
    lam : ndarray
        (n_modes,) eigenvalues λ_r = ω_r², (rad/s)², zero for a rigid-body mode.
    damping : ndarray
        (n_modes,) modal damping c_r = φ_rᵀ C φ_r, 1/s (2 ζ_r ω_r for a damping ratio ζ_r).
    load : ndarray
        (n_modes,) complex modal loads φ_rᵀ F, N·m or N per unit modal amplitude.
    omega : array_like
        (n_f,) circular frequencies, rad/s, finite, at most 1e8 rad/s in magnitude.

    Returns
    -------
    ndarray
        (n_f, n_out) complex amplitudes (m or rad). Memory: the output and a block of at most
        ``_BLOCK_ENTRIES`` modal amplitudes, never (n_f, n_modes) whole.

    Raises
    ------
    mechdyn.errors.ModelError
        For a frequency out of range, or a response that is not finite (an undamped resonance, a
        free body at 0 rad/s).

    Notes
    -----
    X(ω) = Σ_r φ_r (φ_rᵀ F)/(λ_r − ω² + iω c_r), exact for every ω when the modes are complete and
    ΦᵀCΦ = diag(c_r) (e.g. Craig & Kurdila, *Fundamentals of Structural Dynamics*, 2nd ed., 2006,
    §10.4; Ewins, *Modal Testing*, 2nd ed., 2000, §2.3). The sum is a product of an (n_f, n_modes)
    block with the (n_modes, n_out) shapes: its cost is n_f · n_modes · n_out multiply-adds, where a
    direct solve of a dense model costs n_f · n³/3.
    """
    w = np.atleast_1d(check_array("harmonic response", "omega", omega, "rad/s", what="circular frequencies"))
    shapes = np.asarray(shapes, dtype=complex)  # one complex product per block (zgemm)
    lam, c = np.asarray(lam, dtype=float), np.asarray(damping, dtype=float)
    g = np.asarray(load, dtype=complex)
    out = np.empty((w.size, shapes.shape[0]), dtype=complex)
    step = max(1, _BLOCK_ENTRIES // max(1, lam.size))
    with np.errstate(divide="ignore", invalid="ignore"):
        for lo in range(0, w.size, step):
            wb = w[lo : lo + step, None]
            Y = g / (lam - wb**2 + 1j * wb * c)  # (block, n_modes) modal amplitudes
            out[lo : lo + step] = Y @ shapes.T
    return finite_response(out, w)


def finite_response(out: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``out``, or a ModelError naming the first frequency whose response is not finite.

    Parameters
    ----------
    out : ndarray
        (frequencies, …) the response, one row per frequency.
    w : ndarray
        (frequencies,) ω, rad/s.
    """
    bad = ~np.isfinite(out).all(axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        raise ModelError(
            f"the response at ω = {w[k]:g} rad/s ({w[k] / (2 * np.pi):g} Hz) is not finite (it overflows: "
            "the dynamic stiffness is nearly singular there, an undamped resonance, a free model near "
            "0 rad/s, or the load is too large); leave that frequency out, add damping or check the model",
            element="harmonic response",
            field="omega",
        )
    return out


def _is_singular(Z: np.ndarray) -> bool:
    try:
        np.linalg.solve(Z, np.ones(Z.shape[0]))
    except np.linalg.LinAlgError:
        return True
    return False


def _singular(w: float) -> ModelError:
    return ModelError(
        f"the dynamic stiffness K + iωC − ω²M is singular at ω = {w:g} rad/s ({w / (2 * np.pi):g} Hz): an "
        "undamped natural frequency, or 0 rad/s on a free model; leave that frequency out or add damping",
        element="harmonic response",
        field="omega",
    )
