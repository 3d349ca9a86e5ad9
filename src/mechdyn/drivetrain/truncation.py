"""The lowest modes of a large drivetrain up to a frequency, and what the others add statically.

A forced response over a frequency band needs the modes near and below it; the modes far above respond
quasi-statically. :func:`modes_below` finds every flexible mode up to a cut-off, and
:func:`truncation_factor` bounds, frequency by frequency, the error of replacing the modes above the
cut-off by their static response (the residual flexibility; e.g. Craig & Kurdila, *Fundamentals of
Structural Dynamics*, 2nd ed., 2006, §11.3 on mode acceleration and residual flexibility).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from mechdyn.drivetrain.assembly import Assembly
from mechdyn.drivetrain.banded import BandForm

__all__ = ["chain_form", "modes_below", "rigid_modes", "truncation_factor"]


def chain_form(asm: Assembly, form: BandForm | None) -> tuple[np.ndarray, np.ndarray] | None:
    """The diagonal and off-diagonal of A = M^-½ K M^-½ in band order, where A is tridiagonal (a
    diagonal M and a band of 1); else None.

    Parameters
    ----------
    asm : Assembly
    form : BandForm or None
        The model's band arrays (:func:`mechdyn.drivetrain.banded.band_form`).
    """
    if asm.mass_diagonal is None or form is None or form.band > 1:
        return None
    d = 1.0 / np.sqrt(asm.mass_diagonal[form.perm])
    if form.band == 0:
        return form.K[0] * d * d, np.zeros(max(0, d.size - 1))
    return form.K[1] * d * d, form.K[2, :-1] * d[:-1] * d[1:]


def _count_below(diag: np.ndarray, off: np.ndarray, x: float) -> int:
    """Number of eigenvalues ≤ x of the symmetric tridiagonal (diag, off): LAPACK ``dstebz`` Sturm count
    with a tolerance wider than the interval (no bisection step)."""
    big = 2.0 * float(np.abs(diag).max(initial=0.0) + 2.0 * np.abs(off).max(initial=0.0)) + abs(x) + 1.0
    m, *_, info = sla.lapack.dstebz(diag, off, 1, -big, x, 0, 0, 2 * big, b"B")
    if info != 0:  # pragma: no cover - LAPACK failure
        raise np.linalg.LinAlgError(f"LAPACK dstebz failed (info = {info})")
    return int(m)


def _orthonormal(Y: np.ndarray) -> np.ndarray:
    """An orthonormal basis of the columns of Y (full column rank, not far from orthogonal): Cholesky
    QR applied twice, two matrix products and two triangular solves (Fukaya, Nakatsukasa, Yanagisawa
    & Yamamoto, "CholeskyQR2", 2014); a Householder QR where the Cholesky factor fails."""
    for _ in range(2):
        try:
            U = sla.cholesky(Y.T @ Y, lower=False, check_finite=False)
        except np.linalg.LinAlgError:
            return sla.qr(Y, mode="economic", check_finite=False)[0]
        # U is well conditioned here: its inverse times Y is one matrix product (faster than a
        # triangular solve with n right-hand sides)
        Y = Y @ sla.solve_triangular(U, np.eye(U.shape[0]), lower=False, check_finite=False)
    return Y


def _chain_modes(
    diag: np.ndarray, off: np.ndarray, rigid: np.ndarray, first: int, last: int
) -> tuple[np.ndarray, np.ndarray] | None:
    """Eigenpairs ``first`` to ``last`` (0-based, inclusive) of the tridiagonal A, orthonormal and
    orthogonal to ``rigid`` (its null vectors, orthonormal columns); None where the Ritz values do
    not reproduce the eigenvalues to 1e-8 of the largest.

    Bisection (LAPACK ``dstebz``) gives the eigenvalues to an absolute accuracy of about ε‖A‖; two
    sweeps of inverse iteration with them as shifts (``dgtsv``, O(n) each) give a basis of their
    eigenvectors, and a Rayleigh–Ritz step on that basis (the eigenpairs of the projected k × k pencil)
    makes the vectors orthonormal to working accuracy, which inverse iteration
    alone does not for the close eigenvalues at the low end of a long chain (Parlett, *The Symmetric
    Eigenvalue Problem*, 1998, §4.3 and ch. 11). O(n k) for the eigenvalues and vectors, O(n k²) for
    the Rayleigh–Ritz step.
    """
    n = diag.size
    k = last - first + 1
    _, w, *_, info = sla.lapack.dstebz(diag, off, 2, 0.0, 0.0, first + 1, last + 1, 0.0, b"E")
    if info != 0:  # pragma: no cover - LAPACK failure
        raise np.linalg.LinAlgError(f"LAPACK dstebz failed (info = {info})")
    lam = np.sort(np.asarray(w[:k]))
    Y = np.random.default_rng(0).standard_normal((k, n)).T  # columns contiguous
    tiny = np.finfo(float).eps * max(float(np.abs(diag).max()), 1e-300)
    gtsv = sla.lapack.dgtsv
    for j in range(k):
        x = Y[:, j : j + 1]
        for _ in range(2):
            *_, y, info = gtsv(off, diag - lam[j], off, x, 0, 1, 0, 0)
            if info > 0:  # a pivot is exactly zero (the shift is an eigenvalue): nudge the shift
                *_, y, info = gtsv(off, diag - (lam[j] + tiny), off, x, 0, 1, 0, 0)
            x = y / np.linalg.norm(y)
        Y[:, j] = x[:, 0]
    if rigid.shape[1]:
        Y -= rigid @ (rigid.T @ Y)
    A = sp.csr_array(sp.diags_array([off, diag, off], offsets=[-1, 0, 1]))
    # Rayleigh–Ritz on span(Y) as the generalised problem (YᵀAY) s = θ (YᵀY) s: Y S is then
    # orthonormal without orthonormalising Y first (inverse iteration leaves it nearly orthogonal)
    H = Y.T @ (A @ Y)
    try:
        theta, S = sla.eigh(0.5 * (H + H.T), Y.T @ Y, check_finite=False)
    except np.linalg.LinAlgError:  # two vectors of a multiple eigenvalue came out alike: orthonormalise
        Y = _orthonormal(Y)
        H = Y.T @ (A @ Y)
        theta, S = np.linalg.eigh(0.5 * (H + H.T))
    # the Ritz values must be the bisection's eigenvalues (else the basis missed an eigenvector)
    if not np.all(np.abs(theta - lam) <= 1e-8 * max(float(lam[-1]), 1e-300)):
        return None
    return theta, Y @ S


def modes_below(
    asm: Assembly,
    lam_cut: float,
    chain: tuple[np.ndarray, np.ndarray] | None,
    form: BandForm | None,
    limit: int,
) -> tuple[np.ndarray, np.ndarray] | None:
    """Every flexible mode with λ = ω² ≤ ``lam_cut``: eigenvalues, (rad/s)², and M-normalised shapes on
    the assembly's coordinates; None when there are more than ``limit``.

    Parameters
    ----------
    asm : Assembly
    lam_cut : float
        The cut-off, (rad/s)².
    chain : tuple of ndarray or None
        :func:`chain_form` of the model: a tridiagonal A takes the bisection path.
    form : BandForm or None
        Its band arrays (for the band order of ``chain``).
    limit : int
        The most modes to compute.

    Notes
    -----
    A chain: the count below the cut-off is exact (Sylvester's law of inertia, as a Sturm count on
    the tridiagonal A), the pairs come from :func:`_chain_modes`. Other models: the lowest modes by
    :func:`mechdyn.drivetrain.modal` (shift-invert Lanczos on K and M for a large model, ARPACK),
    doubling their number until one lies above the cut-off.
    """
    n_rb = asm.n_rigid_body
    n_flex = asm.n - n_rb
    if chain is not None and form is not None:
        diag, off = chain
        count = _count_below(diag, off, lam_cut) - n_rb
        if count <= 0:
            return np.zeros(0), np.zeros((asm.n, 0))
        if count > limit:
            return None
        assert asm.mass_diagonal is not None  # a chain form has a diagonal M
        rigid = np.zeros((asm.n, 0))
        if n_rb:
            root = np.sqrt(asm.mass_diagonal[form.perm])
            rigid = np.linalg.qr(root[:, None] * _rigid_coordinates(asm)[form.perm])[0]
        pairs = _chain_modes(diag, off, rigid, n_rb, n_rb + count - 1)
        if pairs is not None:
            lam, Yp = pairs
            Phi = np.empty_like(Yp)
            Phi[form.perm] = Yp / np.sqrt(asm.mass_diagonal[form.perm])[:, None]
            return lam, Phi
    from mechdyn.drivetrain.modal import modal

    k = min(n_flex, 32)
    while True:
        modes = modal(asm, n_modes=k)
        lam = modes.omega**2
        if lam.size == n_flex or lam[-1] > lam_cut:
            keep = lam <= lam_cut
            if np.count_nonzero(keep) > limit:
                return None
            return lam[keep], modes.reduced_shapes[:, keep]
        if k >= limit:
            return None
        k = min(n_flex, 2 * k, limit + 1)


def _rigid_coordinates(asm: Assembly) -> np.ndarray:
    """The rigid-body motions on the assembly's coordinates (each coordinate is the disk named by
    :attr:`Assembly.coordinate_names`, where T = 1)."""
    if asm.T.shape[0] == asm.T.shape[1]:  # no rigid mesh: the coordinates are the degrees of freedom
        return asm.rigid_body_vectors
    idx = asm.drivetrain.dof_index
    return asm.rigid_body_vectors[[idx[c] for c in asm.coordinate_names]]


def rigid_modes(asm: Assembly) -> np.ndarray:
    """The rigid-body modes on the assembly's coordinates, M-orthonormal (Rᵀ M R = I).

    Parameters
    ----------
    asm : Assembly

    Returns
    -------
    ndarray
        (n, n_rigid_body), rad per unit modal amplitude.
    """
    R = _rigid_coordinates(asm)
    if R.shape[1] == 1:  # one free branch: a scaling
        return R / np.sqrt(float(R[:, 0] @ asm.mass_times(R[:, 0])))
    if R.shape[1]:
        L = np.linalg.cholesky(R.T @ asm.mass_times(R))
        R = np.linalg.solve(L, R.T).T
    return R


def truncation_factor(
    w: np.ndarray, lam_cut: float, beta: float, alpha: float, zeta_max: float
) -> np.ndarray:
    """Bound on the relative error of the stand-in for every mode above the cut-off, per ω.

    Parameters
    ----------
    w : ndarray
        (n_f,) circular frequencies, rad/s.
    lam_cut : float
        Every left-out mode has λ_r > lam_cut, (rad/s)².
    beta, alpha : float
        Stiffness- (s) and mass-proportional (1/s) damping of the left-out modes: c_r = α + β λ_r
        (+ 2 ζ_r ω_r).
    zeta_max : float
        The largest modal damping ratio of the left-out modes.

    Returns
    -------
    ndarray
        (n_f,) e(ω): each left-out mode's term 1/(λ_r s − ω² + iωd_r), s = 1 + iωβ,
        d_r = α + 2ζ_r ω_r, differs from its stand-in 1/(λ_r s) + ω²/(λ_r s)² by at most e(ω) times
        |1/(λ_r s)|; inf where the bound fails (ω near the cut-off).

    Notes
    -----
    With u = (ω² − iωd_r)/(λ_r s), the term is (1/(λ_r s))(1 + u + u²/(1 − u)) and the stand-in keeps
    1 + ω²/(λ_r s): what is left is −iωd_r/(λ_r s) + u²/(1 − u). With ρ = ω/√λ_cut ≥ ω/ω_r and
    v = (ρ² + 2ζρ + αω/λ_cut)/|s| ≥ |u|, its magnitude is at most
    e = (2ζρ + αω/λ_cut)/|s| + v²/(1 − v): second order in ω/ω_r, first order only in the damping of
    the left-out modes (the second term of the mode-acceleration series; Craig & Kurdila,
    *Fundamentals of Structural Dynamics*, 2nd ed., 2006, §11.3).
    """
    rho = w / np.sqrt(lam_cut)
    s = np.abs(1.0 + 1j * w * beta)
    damped = (2.0 * zeta_max * rho + alpha * w / lam_cut) / s
    v = rho**2 / s + damped
    with np.errstate(divide="ignore"):
        return np.where(v < 1, damped + v**2 / np.where(v < 1, 1.0 - v, 1.0), np.inf)
