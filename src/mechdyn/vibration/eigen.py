"""Symmetric eigen solvers for K q = ω² M q (dense, banded and sparse paths, and accurate ones).

A full mass matrix (a rigid machine on mounts, its inertia tensor coupling the coordinates; a drivetrain
whose shafts carry consistent inertia) goes to LAPACK's generalised solver, or to shift-invert Lanczos for
the lowest modes of a large sparse one. With M diagonal (a drivetrain of disks), the problem becomes the
standard one A y = λ y with A = M^-½ K M^-½. A chain of disks gives a tridiagonal A and a geared tree a
narrow band after reverse Cuthill–McKee ordering, so the banded path avoids the dense O(n³) reduction
(divide and conquer on the tridiagonal); the sparse path (shift-invert Lanczos, ARPACK) returns the lowest
modes of very large models.

These fast paths are backward stable: every eigenvalue comes with an *absolute* error of about ε‖A‖, so a
model whose inertias or stiffnesses spread over many decades (‖A‖/λ large) can get its low natural
frequencies wrong, even as zero. Given the stiffness as a factor K = Fᵀ F (one row per spring, as a
drivetrain assembles it), :func:`solve_eigen` checks the fast result and, where it cannot be trusted to
1e-6, computes the frequencies as singular values of G = F M^-½ to high *relative* accuracy: bisection
on the Golub–Kahan form of a bidiagonal factor for chains, one-sided Jacobi (LAPACK ``dgejsv``) for
other models of up to 2000 coordinates; otherwise it warns with the condition estimate.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import Any, Literal

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph
import scipy.sparse.linalg as spla

from mechdyn.errors import ModelWarning
from mechdyn.vibration.chain import bidiagonal_chain, golub_kahan, verified

__all__ = ["SOLVERS", "dense_modes", "solve_eigen"]

Solver = Literal["auto", "dense", "banded", "sparse"]
SOLVERS: tuple[str, ...] = ("auto", "dense", "banded", "sparse")

# below this many coordinates a dense LAPACK solve beats the reordered banded one (all pairs of a
# chain: 1.2 ms each at 100, dense 4.0 against banded 2.7 ms at 200, 16 against 6.2 ms at 400)
_DENSE_LIMIT = 150
_BAND_LIMIT = 32

#: Relative accuracy promised on every flexible natural frequency ω = √λ.
ACCURACY = 1e-6
#: The fast paths' error estimate ε‖A‖/(2λ) must stay this many times below :data:`ACCURACY`.
_MARGIN = 100.0
#: Largest model (coordinates) solved by dense one-sided Jacobi when the fast paths cannot be trusted.
_JACOBI_LIMIT = 2000
_EPS = float(np.finfo(float).eps)
_TINY = float(np.finfo(float).tiny)


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


def dense_modes(K: np.ndarray, mass: np.ndarray, n_rigid: int) -> tuple[np.ndarray, np.ndarray] | None:
    """All modes of a small model with a diagonal M by one LAPACK call, where they can be trusted.

    The path :func:`solve_eigen` takes for such a model (``dense``: LAPACK ``dsyevd``, divide and
    conquer, on A = M^-½ K M^-½, Q = M^-½ Y), without its general entry's per-call work (argument and
    finite checks of a model checked where it entered, the dispatch), which on a 10-disk model costs
    more than the solve; its accuracy test is the same (:func:`doubt_below` on the first flexible λ).

    Parameters
    ----------
    K : ndarray (n, n)
        Dense stiffness matrix, N·m/rad (or N/m), symmetric.
    mass : ndarray (n,)
        The diagonal of M, kg·m² (or kg), positive.
    n_rigid : int
        Rigid-body modes (λ = 0) of the model, fewer than n.

    Returns
    -------
    tuple of ndarray or None
        λ (rad/s)² ascending and the M-normalised Q; None where LAPACK did not converge or a flexible
        λ is in doubt (then :func:`solve_eigen`, with its accurate paths, is the answer).
    """
    from scipy.linalg.lapack import dsyevd

    d = 1.0 / np.sqrt(mass)
    lam, Y, info = dsyevd(d[:, None] * K * d[None, :], compute_v=1, lower=1)
    if info != 0 or lam[n_rigid] < doubt_below(max(abs(lam[0]), abs(lam[-1]))):
        return None
    Y *= d[:, None]
    return lam, Y


def doubt_below(norm: Any) -> Any:
    """The eigenvalue below which a backward-stable solve cannot promise :data:`ACCURACY`.

    Parameters
    ----------
    norm : float or ndarray
        ‖A‖ of A = M^-½ K M^-½, (rad/s)².

    Returns
    -------
    float or ndarray
        ε ‖A‖ · _MARGIN / (2 · ACCURACY), (rad/s)²: a flexible λ below it has an error estimate
        ε‖A‖/(2λ) on its ω = √λ above ``ACCURACY``/_MARGIN.
    """
    return _EPS * norm * _MARGIN / (2.0 * ACCURACY)


def solve_eigen(
    K: sp.csr_array | np.ndarray,
    mass: np.ndarray,
    *,
    n_modes: int | None = None,
    solver: Solver = "auto",
    factor: sp.csr_array | np.ndarray | Callable[[], sp.csr_array | np.ndarray] | None = None,
    n_rigid: int | None = None,
    check_finite: bool = True,
) -> tuple[np.ndarray, np.ndarray, str]:
    """Lowest eigenpairs of K q = λ M q for symmetric semi-definite K and positive-definite M.

    Parameters
    ----------
    K : sparse array or ndarray
        Stiffness, (n, n), symmetric positive semi-definite, in the model's SI units (N/m, N·m/rad).
    mass : ndarray or sparse array
        Diagonal of M, (n,), all positive, in the model's SI units (kg, kg·m²); or the full (n, n)
        symmetric positive-definite M, dense or sparse. A diagonal one takes the paths below; any
        other is solved as the generalised problem: densely (LAPACK ``sygvd``/``sygvx``, M = L Lᵀ by
        Cholesky and the standard problem of L⁻¹ K L⁻ᵀ), or for a few lowest modes of a large sparse
        model (``sparse``, or ``auto`` as for a wide band below) by shift-invert Lanczos with M
        (:func:`scipy.sparse.linalg.eigsh`).
    n_modes : int, optional
        Number of lowest eigenpairs; all when None.
    solver : {"auto", "dense", "banded", "sparse"}
        ``dense``: LAPACK ``syevr`` via :func:`scipy.linalg.eigh`. ``banded``: reverse Cuthill–McKee
        ordering, then LAPACK ``dstevd`` (band 1, all pairs), ``dstebz``/``dstein`` (band 1, lowest
        pairs) or :func:`scipy.linalg.eig_banded`. ``sparse``: :func:`scipy.sparse.linalg.eigsh`
        in shift-invert mode just below zero (needs ``n_modes`` < n − 1). ``auto`` picks dense for
        small models, banded when the reordered band is narrow (chains, geared trees), sparse for a
        few modes of a wide-band model, dense otherwise.
    factor : sparse array, ndarray or callable, optional
        F, (m, n), with K = Fᵀ F: one row per spring, √k times the spring's deflection per unit
        coordinate (a drivetrain's shafts, meshes and grounded springs), in √(N·m/rad); or a function
        of no arguments that returns it, called only when the fast result is in doubt. With it (and a
        diagonal M), a result of the fast paths that cannot be trusted to :data:`ACCURACY` is replaced by
        one accurate to it (see Notes).
    n_rigid : int, optional
        Number of zero (rigid-body) eigenvalues, set aside when judging the accuracy of the others.
        Inferred from ``factor`` when not given (one per connected group of coordinates that no row of
        one coordinate holds to the ground). Without ``factor`` and ``n_rigid`` no check is made.
    check_finite : bool
        Refuse a NaN or an infinity in K and M (default). A caller whose matrices were checked where
        the model entered (a drivetrain's assembly) passes False: the check reads every entry, and on
        a small model costs as much as the solve.

    Returns
    -------
    lam : ndarray
        Eigenvalues λ = ω², ascending, (rad/s)²; the ``n_rigid`` rigid-body ones first.
    Q : ndarray
        M-normalised eigenvectors (Qᵀ M Q = I), one per column.
    used : str
        The solver that ran: one of ``solver``'s values, ``"jacobi"`` or ``"bidiagonal"``.

    Warns
    -----
    ModelWarning
        When some flexible natural frequencies may be wrong by more than :data:`ACCURACY` (relative) and no
        accurate path applies (no ``factor``; a mass matrix that is not diagonal; a model of more than 2000
        coordinates that is not a chain; a branch closed by a loop of springs whose scaled condition is poor,
        such as a loop of flexible meshes whose ratios nearly agree). The message gives the condition estimate
        and how far the frequencies may be off.

    Notes
    -----
    Every fast path is backward stable: each eigenvalue carries an absolute error of about ε‖A‖, A =
    M^-½ K M^-½, so the relative error of a flexible ω = √λ is about ε‖A‖/(2λ). Where that estimate
    exceeds ``ACCURACY``/100 for a wanted flexible mode (and ``n_rigid`` or ``factor`` is given), the
    result is checked or recomputed from the factor: λ are the squared singular values of G = F M^-½
    (Gᵀ G = A), which are determined to high relative accuracy by the entries of G when the springs
    form a tree (its bipartite graph of coordinates and springs is acyclic), whatever the spread of
    inertias and stiffnesses (Demmel, Gu, Eisenstat, Slapničar, Veselić & Drmač, "Computing the
    singular value decomposition with high relative accuracy", *Linear Algebra Appl.* 299, 1999).

    * Chains (every spring joins neighbours along a path, or grounds one coordinate), of any length:
      G is reduced, without cancellation, to a bidiagonal W with A = W Wᵀ (Cholesky factorisation
      along the chain, series combination of the springs); its singular values are determined to high
      relative accuracy (Demmel & Kahan, "Accurate singular values of bidiagonal matrices", *SIAM J.
      Sci. Stat. Comput.* 11, 1990) and Sturm counts on its Golub–Kahan form (LAPACK ``dstebz``) are
      relatively accurate. Two counts per doubtful frequency verify the fast result to
      ``ACCURACY``/2; if one fails, bisection to full relative accuracy and inverse iteration on the
      Golub–Kahan form (``dstein``) replace the doubtful pairs and ``used`` is ``"bidiagonal"``.
    * Other models of up to 2000 coordinates: one-sided Jacobi SVD of each connected group's G (or Gᵀ,
      so that the rigid-body mode of a free tree is structural and never computed), LAPACK ``dgejsv``
      with row and column pivoting (Demmel & Veselić, "Jacobi's method is more accurate than QR",
      *SIAM J. Matrix Anal. Appl.* 13, 1992; Drmač & Veselić, "New fast and accurate Jacobi SVD
      algorithm I/II", *SIAM J. Matrix Anal. Appl.* 29, 2008), O(n³). ``used`` is ``"jacobi"``.

    A group closed by a loop of springs (e.g. a planetary set) has no such guarantee: the Jacobi
    result is then used, and a :class:`~mechdyn.errors.ModelWarning` gives its scaled condition where
    that cannot vouch for ``ACCURACY``. Mode shapes from the accurate paths are as accurate as the
    relative gaps between the frequencies allow; the lowest ``n_rigid`` pairs are the exact zero modes.
    """
    from mechdyn.checks import check_count
    from mechdyn.errors import ModelError
    from mechdyn.vibration.harmonic import finite_matrices

    if solver not in SOLVERS:
        raise ValueError(f"unknown eigen solver {solver!r}; expected one of {', '.join(SOLVERS)}")
    if sp.issparse(mass):
        Ms = sp.csr_array(mass, dtype=float)
        if check_finite:
            finite_matrices("eigen solver", K=K, M=Ms)
        off = sp.csr_array(Ms - sp.diags_array(Ms.diagonal()))
        off.eliminate_zeros()
        mass = Ms.diagonal() if off.nnz == 0 else Ms
    else:
        mass = np.asarray(mass, dtype=float)
        if check_finite:
            finite_matrices("eigen solver", K=K, M=mass)
    masses = mass.diagonal() if mass.ndim == 2 else mass
    if not np.all(masses > 0):
        i = int(np.flatnonzero(~(masses > 0))[0])
        raise ModelError(
            f"mass entry {i} is {masses[i]:g}: every coordinate needs a positive mass (or inertia)",
            element="eigen solver",
            field="M",
        )
    n = mass.shape[0]
    k = n if n_modes is None else min(check_count("eigen solver", "n_modes", n_modes, high=10**9), n)
    if sp.issparse(mass):
        return _general(K, mass, k, solver, factor, n_rigid)
    if mass.ndim == 2:
        if np.count_nonzero(mass - np.diag(np.diagonal(mass))):
            Kd = _dense_array(K)
            lam, Q = _dense(Kd, k, mass)
            return np.asarray(lam), Q, "dense"
        mass = np.diagonal(mass).copy()
    lam, Q, used = _fast(K, mass, k, solver)
    if factor is None and n_rigid is None:
        return lam, Q, used
    return _checked(K, mass, k, lam, Q, used, factor, n_rigid)


def _general(
    K: Any, M: sp.csr_array, k: int, solver: str, factor: Any, n_rigid: int | None
) -> tuple[np.ndarray, np.ndarray, str]:
    """K q = λ M q for a sparse, non-diagonal, positive-definite M (a consistent mass matrix).

    Dense: LAPACK ``sygvd``/``sygvx`` (Cholesky M = L Lᵀ, then the standard problem of L⁻¹ K L⁻ᵀ),
    backward stable. Sparse (a few lowest modes of a large model): shift-invert Lanczos with M just
    below zero. Where the error estimate ε‖A‖/(2λ) exceeds ``ACCURACY``/100 for a wanted flexible mode
    (and ``n_rigid`` or ``factor`` is given), the one-sided Jacobi SVD of G = F L⁻ᵀ replaces the result
    (models of up to 2000 coordinates with a stiffness factor), or a
    :class:`~mechdyn.errors.ModelWarning` gives the condition estimate.
    """
    n = M.shape[0]
    Ks = sp.csr_array(K, dtype=float)
    m_diag = M.diagonal()
    d = 1.0 / np.sqrt(m_diag)
    wide = k < n // 10 and k < 200 and n > _DENSE_LIMIT
    if (solver == "sparse" or (solver == "auto" and wide)) and k < n - 1:
        scale = float(np.abs(Ks.diagonal() / m_diag).max())
        lam, Q = spla.eigsh(Ks.tocsc(), k=k, M=M.tocsc(), sigma=-1e-9 * scale, which="LM")
        order = np.argsort(lam)
        lam, Q = lam[order], Q[:, order]
        Q = Q / np.sqrt(np.einsum("ij,ij->j", Q, np.asarray(M @ Q)))  # Qᵀ M Q = I
        used = "sparse"
    else:
        lam, Q = _dense(Ks.toarray(), k, M.toarray())
        used = "dense"
    lam = np.asarray(lam)
    F = None
    if n_rigid is None:
        F = _clean_factor(factor, n) if factor is not None else None
        if F is None:
            return lam, Q, used
        n_rigid = int(np.count_nonzero(~_groups(F, n)[2]))
    if k <= n_rigid:
        return lam, Q, used
    # ‖A‖ of A = L⁻¹ K L⁻ᵀ: the largest λ when all are at hand, else Gershgorin's bound on D⁻½ K D⁻½
    # (D = diag M; a consistent mass matrix is within a factor 3 of its diagonal)
    norm = float(max(abs(lam[0]), abs(lam[-1]))) if k == n else 3.0 * float(np.max((abs(Ks) @ d) * d))
    flex = lam[n_rigid:]
    s = int(np.searchsorted(flex, doubt_below(norm)))
    if not s:
        return lam, Q, used
    if F is None and factor is not None:
        F = _clean_factor(factor, n)
    if F is None or n > _JACOBI_LIMIT:
        why = (
            "no stiffness factor K = Fᵀ F is at hand"
            if F is None
            else f"the model has more than {_JACOBI_LIMIT} coordinates"
        )
        _warn_estimate(norm, flex[:s], f"the mass matrix is not diagonal and {why}")
        return lam, Q, used
    lam_a, Q_a, doubtful = _jacobi(F, M, n_rigid)
    for kappa, modes in doubtful:
        _warn_loop(kappa, lam_a[modes])
    return lam_a[:k], Q_a[:, :k], "jacobi"


def _fast(K: Any, mass: np.ndarray, k: int, solver: str) -> tuple[np.ndarray, np.ndarray, str]:
    """The dense, banded and sparse paths on A = M^-½ K M^-½ (absolute accuracy ε‖A‖)."""
    n = mass.shape[0]
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


# -- the accuracy check and the accurate paths ---------------------------------------------------


def _checked(
    K: Any,
    mass: np.ndarray,
    k: int,
    lam: np.ndarray,
    Q: np.ndarray,
    used: str,
    factor: Any,
    n_rigid: int | None,
) -> tuple[np.ndarray, np.ndarray, str]:
    """The fast result if its error estimate allows, else the accurate one (or a warning)."""
    n = mass.size
    F = None
    if n_rigid is None:  # then factor is given: one rigid-body mode per free group of coordinates
        F = _clean_factor(factor, n)
        if F is None:
            return lam, Q, used
        n_rigid = int(np.count_nonzero(~_groups(F, n)[2]))
    if k <= n_rigid:
        return lam, Q, used
    flex = lam[n_rigid:]  # ascending, as every fast path returns them
    if k == n:
        norm = float(max(abs(lam[0]), abs(lam[-1])))
    else:  # Gershgorin bound on ‖A‖: the largest row sum of |A| = D |K| D
        d = 1.0 / np.sqrt(mass)
        Kabs = abs(sp.csr_array(K)) if sp.issparse(K) else np.abs(np.asarray(K, dtype=float))
        norm = float(np.max((Kabs @ d) * d))
    # the relative error of ω = √λ is about ε‖A‖/(2λ) (a flexible λ ≤ 0 is lost altogether): more than
    # ACCURACY/_MARGIN for the s lowest flexible λ, those below this bound
    s = int(np.searchsorted(flex, doubt_below(norm)))
    if s == 0:
        return lam, Q, used
    if F is None:
        F = _clean_factor(factor, n)
    if F is None:
        _warn_estimate(norm, flex[:s], "no stiffness factor K = Fᵀ F is at hand to solve it accurately")
        return lam, Q, used
    chain = bidiagonal_chain(F, mass)
    if chain is not None:
        e, perm = chain
        if verified(e, n, n_rigid, np.sqrt(np.clip(flex[:s], 0.0, None)), ACCURACY):
            return lam, Q, used
        lam_b, Q_b = golub_kahan(e, perm, mass, n_rigid, s)
        lam, Q = lam.copy(), Q.copy()
        lam[: n_rigid + s], Q[:, : n_rigid + s] = lam_b, Q_b
        return lam, Q, "bidiagonal"
    if n <= _JACOBI_LIMIT:
        lam_a, Q_a, doubtful = _jacobi(F, mass, n_rigid)
        for kappa, modes in doubtful:
            _warn_loop(kappa, lam_a[modes])
        return lam_a[:k], Q_a[:, :k], "jacobi"
    _warn_estimate(norm, flex[:s], f"the model has more than {_JACOBI_LIMIT} coordinates and is not a chain")
    return lam, Q, used


def _clean_factor(factor: Any, n: int) -> sp.csr_array | None:
    """The factor (called first if it is a function) as CSR without zeros or empty rows; None if none."""
    if callable(factor):
        factor = factor()
    if factor is None:
        return None
    F = sp.csr_array(factor, dtype=float)
    if F.shape[1] != n:
        raise ValueError(f"the stiffness factor has {F.shape[1]} columns; expected {n}")
    F.sum_duplicates()
    F.eliminate_zeros()
    keep = np.diff(F.indptr) > 0
    return F if keep.all() else sp.csr_array(F[np.flatnonzero(keep)])


def _groups(F: sp.csr_array, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Connected groups of coordinates: label per coordinate, group per row of F, grounded per group."""
    P = abs(F)
    P.data[:] = 1.0
    count, label = csgraph.connected_components(sp.csr_array(P.T @ P), directed=False)
    row_group = label[F.indices[F.indptr[:-1]]]
    grounded = np.zeros(count, dtype=bool)
    grounded[row_group[np.diff(F.indptr) == 1]] = True
    return label, row_group, grounded


def _dgejsv(X: np.ndarray, left: bool) -> tuple[np.ndarray, np.ndarray]:
    """Singular values (descending) and the full left (``left``) or right singular vectors of X (m ≥ n).

    ``joba=2`` is LAPACK's JOBA = 'F' (row and column pivoting: accurate for X = D₁ C D₂ with C well
    conditioned, whatever the diagonal scalings); ``jobu=1``/``jobv=0`` ask for all left/right vectors,
    3 for none; ``jobp=0`` forbids perturbing small entries.
    """
    if left:
        sva, U, _, work, _, info = sla.lapack.dgejsv(X, joba=2, jobu=1, jobv=3, jobp=0)
    else:
        sva, _, U, work, _, info = sla.lapack.dgejsv(X, joba=2, jobu=3, jobv=0, jobp=0)
    if info != 0:
        raise np.linalg.LinAlgError(f"LAPACK dgejsv failed (info = {info})")
    s = sva * (work[0] / work[1])  # dgejsv returns the singular values scaled against overflow
    order = np.argsort(-s, kind="stable")
    s = s[order]
    V = np.asarray(U)
    return s, np.concatenate([V[:, order], V[:, s.size :]], axis=1) if left else V[:, order]


def _jacobi(
    F: sp.csr_array, mass: np.ndarray | sp.csr_array, n_rigid: int
) -> tuple[np.ndarray, np.ndarray, list[tuple[float, np.ndarray]]]:
    """All eigenpairs from the one-sided Jacobi SVD of G = F M^-½, group by group.

    Returns λ (rigid-body zeros first, then ascending), M-normalised Q, and for each group closed by a
    loop whose scaled condition cannot vouch for :data:`ACCURACY`: the estimate and its modes' positions.
    A sparse, non-diagonal M (its groups those of K) enters through its Cholesky factor, M = L Lᵀ, group
    by group: G = F L⁻ᵀ and Q = L⁻ᵀ Y (a consistent mass matrix is well conditioned once scaled by its
    diagonal, so this keeps the accuracy of the springs' data).
    """
    general = sp.issparse(mass)
    n = mass.shape[0]
    full: Any = mass  # the sparse M where it is not diagonal
    d = np.ones(n) if general else 1.0 / np.sqrt(mass)
    G = F if general else sp.csr_array(F @ sp.diags_array(d))
    label, row_group, grounded = _groups(F, n)
    n_groups = grounded.size
    rows_of = np.argsort(row_group, kind="stable")
    row_bounds = np.searchsorted(row_group[rows_of], np.arange(n_groups + 1))
    cols_of = np.argsort(label, kind="stable")
    col_bounds = np.searchsorted(label[cols_of], np.arange(n_groups + 1))
    s_all = np.zeros(n)
    is_rigid = np.zeros(n, dtype=bool)
    Y = np.zeros((n, n))
    loops: list[tuple[np.ndarray, slice]] = []  # the G and the columns of Y of each loop-closed group
    candidates: list[tuple[float, int]] = []  # free loop-closed groups: (σ_min/σ_max, column of σ_min)
    structural = 0
    start = 0
    for g in range(n_groups):
        cols = cols_of[col_bounds[g] : col_bounds[g + 1]]
        rows = rows_of[row_bounds[g] : row_bounds[g + 1]]
        nc, mc = cols.size, rows.size
        span = slice(start, start + nc)
        start += nc
        if mc == 0:  # a disk on its own: one rigid-body mode
            Y[cols, span] = 1.0 / np.sqrt(full[cols][:, cols].toarray()) if general else 1.0
            is_rigid[span] = True
            structural += 1
            continue
        Gc = G[rows][:, cols].toarray()
        links = np.count_nonzero(Gc)
        if general:  # G = F L⁻ᵀ on this group
            Lc = sla.cholesky(full[cols][:, cols].toarray(), lower=True)
            Gc = sla.solve_triangular(Lc, Gc.T, lower=True).T
        if mc < nc:  # a free tree (mc = nc − 1): Gcᵀ has full column rank, Gc's null space is the rigid mode
            s, U = _dgejsv(np.asfortranarray(Gc.T), left=True)
            is_rigid[span.start + mc : span.stop] = True
            structural += nc - mc
        else:
            s, U = _dgejsv(np.asfortranarray(Gc), left=False)
            if not grounded[g]:  # closed by a loop, nothing grounds it: σ_min may be a rigid-body mode
                candidates.append((s[-1] / s[0] if s[0] > 0 else 0.0, span.stop - 1))
        s_all[span.start : span.start + s.size] = s
        Y[np.ix_(cols, np.arange(span.start, span.stop))] = (
            sla.solve_triangular(Lc.T, U, lower=False) if general else U
        )
        if links > nc + mc - 1:  # more coordinate–spring links than a tree has: a loop
            loops.append((Gc, span))
    # n_rigid says how many of those free loop-closed groups turn freely (the others are locked by a
    # loop of meshes whose ratios disagree): the ones with the relatively smallest σ_min
    candidates.sort()
    for _, column in candidates[: max(0, n_rigid - structural)]:
        is_rigid[column] = True
    lam_all = np.where(is_rigid, 0.0, s_all**2)
    order = np.lexsort((lam_all, ~is_rigid))  # rigid-body modes first, then ascending
    position = np.empty(n, dtype=int)
    position[order] = np.arange(n)
    doubtful = []
    for Gc, span in loops:
        columns = np.arange(span.start, span.stop)
        flexible = columns[~is_rigid[columns]]
        kappa = _loop_condition(Gc, flexible.size)
        if _EPS * kappa > ACCURACY:
            doubtful.append((kappa, np.sort(position[flexible])))
    return lam_all[order], d[:, None] * Y[:, order], doubtful


def _loop_condition(Gc: np.ndarray, n_flexible: int) -> float:
    """σ_max/σ_j of a loop-closed group's G after equilibrating its rows and columns, σ_j its smallest
    flexible singular value (the rigid-body one, if any, is left out).

    One-sided Jacobi with pivoting is accurate to about ε times this number whatever the diagonal
    scalings (Demmel et al. 1999), so it is the estimate reported for groups without the tree guarantee.
    """
    if n_flexible == 0:
        return 1.0
    C = np.abs(Gc)
    r = np.ones(C.shape[0])
    c = np.ones(C.shape[1])
    for _ in range(8):  # alternate row and column scaling to unit maximum
        r = 1.0 / np.max(C * c[None, :], axis=1)
        c = 1.0 / np.max(C * r[:, None], axis=0)
    sv = sla.svdvals(r[:, None] * Gc * c[None, :])
    return float(sv[0] / sv[n_flexible - 1]) if sv[n_flexible - 1] > 0 else math.inf


def _warn_estimate(norm: float, doubtful: np.ndarray, why: str) -> None:
    """Warn that the ``doubtful`` lowest flexible λ of the fast paths may miss :data:`ACCURACY`."""
    lowest = float(doubtful[0])
    if lowest > _EPS * norm:
        kappa = f"= {norm / lowest:.3g}"
        worst = min(_EPS * norm / (2.0 * lowest), 1.0)
    else:  # the lowest flexible λ is lost in the round-off: only a bound is known
        kappa = f"≥ {1.0 / _EPS:.3g}"
        worst = 1.0
    warnings.warn(
        f"ill-conditioned eigenproblem: condition estimate ‖M^-½ K M^-½‖/λ {kappa} for the lowest "
        f"flexible mode, and {why}; the {doubtful.size} lowest flexible natural frequencies may be off by "
        f"up to about {worst:.2g} (relative), not safely within the {ACCURACY:g} aimed at",
        ModelWarning,
        stacklevel=4,
    )


def _warn_loop(kappa: float, lam: np.ndarray) -> None:
    f = np.sqrt(np.clip(lam, 0.0, None)) / (2 * math.pi)
    warnings.warn(
        f"ill-conditioned eigenproblem: a branch closed by a loop of springs has the scaled condition "
        f"estimate {kappa:.3g}, so its {f.size} natural frequencies ({f.min():.4g} to {f.max():.4g} Hz) "
        f"may be wrong by up to {min(_EPS * kappa, 1.0):.2g} (relative), more than the {ACCURACY:g} "
        f"aimed at",
        ModelWarning,
        stacklevel=4,
    )
