"""Band storage of a drivetrain's reduced matrices, and the solves that use it.

A chain of disks gives tridiagonal K, M and C; a geared tree a narrow band once its coordinates are put
in reverse Cuthill–McKee order. Stored as LAPACK band arrays, the dynamic stiffness
Z(ω) = K + iωC − ω²M of one frequency costs O(n b²) to factor and solve (LAPACK ``zgtsv`` for band 1,
``zgbsv`` otherwise), against O(n³) dense, and the static solve of the flexible modes (K with one
coordinate of every free branch held) costs the same once. Models whose band stays wide go to SuperLU.
Nothing here grows with the number of frequencies: each solve keeps only the rows asked for.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from mechdyn.errors import ModelError

__all__ = ["BandForm", "band_form", "direct_response", "singular_error", "static_flexible"]

#: Widest band (after reverse Cuthill–McKee ordering) stored as LAPACK band arrays; wider ones use SuperLU.
BAND_LIMIT = 64


@dataclass(frozen=True)
class BandForm:
    """K, C and M on the coordinates put in band order, as LAPACK band arrays.

    Attributes
    ----------
    perm : ndarray
        (n,) the band order: row p of the band arrays is coordinate ``perm[p]``.
    position : ndarray
        (n,) the inverse: coordinate i is row ``position[i]``.
    band : int
        Half-bandwidth b (1 for a chain).
    K, C, M : ndarray
        (2b + 1, n) ``solve_banded`` layout, ``A[u + i − j, j] = A_ij`` with u = b, in N·m/rad,
        N·m·s/rad and kg·m²; C is zeros where the model has no damping.
    """

    perm: np.ndarray
    position: np.ndarray
    band: int
    K: np.ndarray
    C: np.ndarray
    M: np.ndarray


def _pattern(*matrices: sp.sparray) -> sp.csr_array:
    P = sp.csr_array(abs(matrices[0]))
    for A in matrices[1:]:
        P = sp.csr_array(P + abs(A))
    return P


def _to_band(A: sp.sparray, position: np.ndarray, b: int) -> np.ndarray:
    coo = sp.coo_array(A)
    kept = coo.data != 0  # an element's block may store zeros beyond the band
    i, j = position[coo.row[kept]], position[coo.col[kept]]
    out = np.zeros((2 * b + 1, A.shape[0]))
    np.add.at(out, (b + i - j, j), coo.data[kept])
    return out


def band_form(K: sp.sparray, C: sp.sparray, M: sp.sparray) -> BandForm | None:
    """The band arrays of K, C and M in reverse Cuthill–McKee order; None when the band is wider than
    :data:`BAND_LIMIT`.

    Parameters
    ----------
    K, C, M : sparse array
        (n, n) stiffness (N·m/rad), damping (N·m·s/rad) and mass (kg·m²) on the same coordinates.

    Returns
    -------
    BandForm or None
    """
    n = K.shape[0]
    pattern = _pattern(K, C, M)
    coo = sp.coo_array(pattern)
    if coo.nnz and np.all(np.abs(coo.row - coo.col) <= 1):  # already a chain in this order
        perm = np.arange(n)
    else:
        perm = csgraph.reverse_cuthill_mckee(pattern, symmetric_mode=True).astype(np.intp)
    position = np.empty(n, dtype=np.intp)
    position[perm] = np.arange(n)
    b = int(np.abs(position[coo.row] - position[coo.col]).max()) if coo.nnz else 0
    if b > BAND_LIMIT:
        return None
    return BandForm(
        perm, position, b, _to_band(K, position, b), _to_band(C, position, b), _to_band(M, position, b)
    )


def singular_error(w: float) -> ModelError:
    """The error for a dynamic stiffness that is singular at ω (rad/s)."""
    return ModelError(
        f"the dynamic stiffness K + iωC − ω²M is singular at ω = {w:g} rad/s ({w / (2 * np.pi):g} Hz): an "
        "undamped natural frequency, or 0 rad/s on a free model; leave that frequency out or add damping",
        element="harmonic response",
        field="omega",
    )


def direct_response(
    K: sp.sparray,
    C: sp.sparray,
    M: sp.sparray,
    F: np.ndarray,
    w: np.ndarray,
    rows: np.ndarray,
    form: BandForm | None,
) -> np.ndarray:
    """Rows ``rows`` of X(ω) with (K + iωC − ω²M) X = F at every ω, one factorisation per frequency.

    Parameters
    ----------
    K, C, M : sparse array
        (n, n) reduced stiffness (N·m/rad), damping (N·m·s/rad) and mass (kg·m²).
    F : ndarray
        (n,) complex load amplitudes, N·m.
    w : ndarray
        (n_f,) circular frequencies, rad/s.
    rows : ndarray
        The coordinates wanted.
    form : BandForm or None
        The band arrays of K, C, M (:func:`band_form`); None solves with SuperLU.

    Returns
    -------
    ndarray
        (n_f, len(rows)) complex amplitudes, rad. Memory: the model's band arrays, one complex copy
        of them and this output.

    Notes
    -----
    Band 1 (a chain): LAPACK ``zgtsv``, Gaussian elimination with partial pivoting on the tridiagonal
    Z(ω); wider bands ``zgbsv`` through :func:`scipy.linalg.solve_banded`; otherwise SuperLU
    (:func:`scipy.sparse.linalg.splu`). Each is backward stable; a singular Z(ω) (an undamped
    resonance) is refused naming the frequency.
    """
    out = np.empty((w.size, rows.size), dtype=complex)
    if form is None:
        from scipy.sparse.linalg import splu

        Kc, Cc, Mc = (sp.csc_array(A, dtype=complex) for A in (K, C, M))
        for i, wi in enumerate(w):
            try:
                lu = splu(sp.csc_array(Kc + (1j * wi) * Cc - wi**2 * Mc))
            except RuntimeError as exc:  # "Factor is exactly singular"
                raise singular_error(float(wi)) from exc
            out[i] = lu.solve(F)[rows]
        return out
    b = form.band
    at = form.position[rows]
    Fp = np.ascontiguousarray(F[form.perm], dtype=complex)
    Z = np.empty(form.K.shape, dtype=complex)
    damped = bool(np.any(form.C))
    gtsv = sla.lapack.zgtsv
    for i, wi in enumerate(w):
        np.multiply(form.M, -(wi**2), out=Z)
        Z += form.K
        if damped:
            Z += (1j * wi) * form.C
        if b == 1:
            *_, x, info = gtsv(Z[2, :-1], Z[1], Z[0, 1:], Fp[:, None], 1, 1, 1, 0)
            if info > 0:
                raise singular_error(float(wi))
            out[i] = x[at, 0]
        elif b == 0:
            d = Z[0]
            if np.any(d == 0):
                raise singular_error(float(wi))
            out[i] = Fp[at] / d[at]
        else:
            try:
                x = sla.solve_banded((b, b), Z, Fp, overwrite_ab=True, check_finite=False)
            except np.linalg.LinAlgError:
                raise singular_error(float(wi)) from None
            out[i] = x[at]
    return out


def static_flexible(
    K: sp.sparray, M: sp.sparray, R: np.ndarray, F: np.ndarray, form: BandForm | None
) -> np.ndarray:
    """y = Σ_flex φ φᵀ F / λ over every flexible mode, by one factorisation of K.

    Parameters
    ----------
    K, M : sparse array
        (n, n) reduced stiffness (N·m/rad) and mass (kg·m²).
    R : ndarray
        (n, n_rb) the rigid-body modes, M-orthonormal (Rᵀ M R = I), one per free branch.
    F : ndarray
        (n,) complex loads, N·m.
    form : BandForm or None
        The band arrays (:func:`band_form`); None factors K with SuperLU.

    Returns
    -------
    ndarray
        (n,) complex angles, rad: the static response of the flexible modes to F.

    Notes
    -----
    The load's rigid-body part is removed, F' = F − M R Rᵀ F, and one coordinate of each free branch
    is held (its row and column of K replaced by the identity, its load set to 0): the held K is
    non-singular and its solution y satisfies K y = F' on every row, since rᵀK = 0 and rᵀF' = 0 for each
    rigid motion r. Removing the rigid part of y, y − R Rᵀ M y, leaves Σ_flex φ φᵀ F / λ (the flexible
    modes are M-orthogonal to R, so φᵀF' = φᵀF).
    """
    n = K.shape[0]
    Fp = np.asarray(F, dtype=complex)
    held = np.zeros(0, dtype=np.intp)
    if R.shape[1]:
        Fp = Fp - np.asarray(M @ R) @ (R.T @ Fp)
        held = np.unique(np.argmax(np.abs(R), axis=0))
        Fp[held] = 0.0
    rhs = np.column_stack([Fp.real, Fp.imag])
    if form is None:
        from scipy.sparse.linalg import splu

        Kh = sp.lil_array(K)
        if held.size:
            Kh[held, :] = 0.0
            Kh[:, held] = 0.0
            Kh[held, held] = 1.0
        y = splu(sp.csc_array(Kh)).solve(rhs)
    else:
        b = form.band
        ab = form.K.copy()
        for c in form.position[held]:
            for j in range(max(0, c - b), min(n, c + b + 1)):
                ab[b + c - j, j] = 0.0  # row c
                ab[b + j - c, c] = 0.0  # column c
            ab[b, c] = 1.0
        y = sla.solve_banded((b, b), ab, rhs[form.perm], check_finite=False)[form.position]
    x = y[:, 0] + 1j * y[:, 1]
    if R.shape[1]:
        x = x - R @ (R.T @ np.asarray(M @ x))
    return x
