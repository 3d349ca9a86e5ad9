"""Checks of assembled matrices: symmetry, semi-definiteness and the rigid-body mode count.

Every model's matrices are assembled, never typed, and then checked here before any solve: M and K
symmetric, M positive definite, K positive semi-definite, and exactly as many zero modes as the model
has free rigid-body motions (one per free drivetrain branch; none for a machine standing on its
mounts).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mechdyn.checks import check_array, check_number
from mechdyn.errors import ModelCheckError

__all__ = ["check_matrices"]

_TOL = 1e-10


def check_matrices(
    M: np.ndarray,
    K: np.ndarray,
    *,
    expected_rigid_body_modes: int,
    dof_names: Sequence[str] | None = None,
    rigid_body_vectors: np.ndarray | None = None,
    rtol: float = 1e-9,
) -> None:
    """Check a (possibly hand-made) pair of mass and stiffness matrices.

    Parameters
    ----------
    M, K : array_like
        Square mass (kg or kg·m²) and stiffness (N/m or N·m/rad) matrices.
    expected_rigid_body_modes : int
        Number of free branches (1 for a free drivetrain, 0 for a grounded one).
    dof_names : sequence of str, optional
        Names of the degrees of freedom for the messages.
    rigid_body_vectors : ndarray, optional
        (n, n_free) expected rigid-body motions (e.g. :attr:`Assembly.rigid_body_vectors`); rows of
        K that do not annihilate them are named. Without them, the rows whose entries do not sum to
        zero are named, which is right for a chain without gears.
    rtol : float
        Eigenvalues of M⁻¹K below ``rtol`` times the largest count as zero; dimensionless, in
        (0, 1).

    Raises
    ------
    ModelCheckError
        Naming the first asymmetric entry, an M that is not positive definite (a consistent mass matrix
        with a coordinate that carries no inertia), the negative eigenvalue of K, or the zero-mode
        count and the degrees of freedom whose stiffness row does not balance (a stray grounding term).
    mechdyn.errors.ModelError
        For a NaN or an infinity in M or K (naming the entry), or ``rtol`` out of range.
    """
    rtol = check_number(
        "check_matrices", "rtol", rtol, positive=True, high=1.0, high_open=True, what="tolerance"
    )
    M = check_array("check_matrices", "M", M, bounded=False, what="mass matrix entries")
    K = check_array("check_matrices", "K", K, bounded=False, what="stiffness matrix entries")
    n = K.shape[0]
    names = list(dof_names) if dof_names is not None else [f"dof {i + 1}" for i in range(n)]
    for label, A in (("M", M), ("K", K)):
        if A.shape != (n, n):
            raise ModelCheckError(f"{label} has shape {A.shape}; expected ({n}, {n})")
        diff = np.abs(A - A.T)
        if diff.max() > _TOL * np.abs(A).max():
            i, j = np.unravel_index(np.argmax(diff), diff.shape)
            raise ModelCheckError(
                f"{label} is not symmetric: {label}[{names[i]}, {names[j]}] = {A[i, j]:.6g} but "
                f"{label}[{names[j]}, {names[i]}] = {A[j, i]:.6g}"
            )
    from scipy.linalg import eigh

    try:  # M must be positive definite: every coordinate carries mass, consistent or lumped
        np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        lowest = np.linalg.eigvalsh(M)
        worst = names[int(np.argmin(np.diagonal(M)))]
        raise ModelCheckError(
            f"M is not positive definite (eigenvalue {lowest.min():.4g}; smallest diagonal entry at "
            f"{worst}): every degree of freedom needs inertia"
        ) from None
    lam, vec = eigh(K, M)
    big = np.abs(lam).max()
    R = np.ones((n, 1)) if rigid_body_vectors is None else np.asarray(rigid_body_vectors).reshape(n, -1)
    residual = np.abs(K @ R).max(axis=1) if R.size else np.zeros(n)
    row_scale = np.abs(K).max(axis=1) * (np.abs(R).max() if R.size else 0.0)
    unbalanced = [names[i] for i in range(n) if residual[i] > rtol * row_scale[i]]
    hint = (
        f"; rows of K that resist the rigid-body motion: {', '.join(unbalanced)}"
        if unbalanced and expected_rigid_body_modes
        else ""
    )
    if lam.min() < -rtol * big:
        worst = names[int(np.argmax(np.abs(vec[:, 0])))]
        raise ModelCheckError(
            f"K is not positive semi-definite (eigenvalue {lam.min():.4g}, mostly at {worst}){hint}"
        )
    zero = int(np.sum(np.abs(lam) <= rtol * big))
    if zero != expected_rigid_body_modes:
        raise ModelCheckError(
            f"K has {zero} zero (rigid-body) mode(s); expected {expected_rigid_body_modes}, one per "
            f"free branch{hint}"
        )
