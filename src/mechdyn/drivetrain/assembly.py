"""Assembly of the drivetrain matrices from the model, with the checks that guard them.

The matrices are never typed by hand: every element contributes its blocks through
:meth:`~mechdyn.drivetrain.elements.Element.blocks`, rigid meshes become a transformation
θ = T q to independent coordinates q, and the reduced matrices are Tᵀ M T, Tᵀ K T, Tᵀ C T.

M holds the disks' inertias and the mass blocks of shafts with their own inertia. While every mass
block is diagonal (disks, lumped shafts), so is Tᵀ M T (T has one entry per row) and the assembly keeps
its diagonal, :attr:`Assembly.mass`, for the fast paths; a consistent shaft makes M a band matrix,
:attr:`Assembly.M`, which is always there.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Generic, TypeVar

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.csgraph as csgraph

from mechdyn.drivetrain.structure import DrivetrainLike
from mechdyn.errors import ModelCheckError, ModelError

__all__ = ["Assembly", "assemble"]

_TOL = 1e-10

#: The model an assembly was made from (:class:`~mechdyn.drivetrain.Drivetrain`).
_Model = TypeVar("_Model", bound=DrivetrainLike)


@dataclass(frozen=True)
class Assembly(Generic[_Model]):
    """The assembled drivetrain.

    Attributes
    ----------
    drivetrain : Drivetrain
        The model it was assembled from.
    T : scipy.sparse.csr_array
        (n_dofs, n_coordinates) transformation θ = T q over the degrees of freedom
        (:attr:`Drivetrain.dof_names`: the disks, then the nodes inside divided shafts); one entry per
        row (each disk follows one independent coordinate through rigid meshes).
    coordinate_names : tuple of str
        The disk (or shaft node) that each independent coordinate is (the first disk of its rigidly
        geared group).
    M, K, C : scipy.sparse.csr_array
        Reduced mass (kg·m²), stiffness (N·m/rad) and damping (N·m·s/rad) matrices, Tᵀ A T.
    rigid_body_vectors : ndarray
        (n_dofs, n_free) exact rigid-body motions, one per free branch, rad per unit motion.
    mass_diagonal : ndarray or None
        The diagonal of M, kg·m², where M is diagonal (no consistent shaft inertia); else None.
    """

    drivetrain: _Model
    T: sp.csr_array
    coordinate_names: tuple[str, ...]
    M: sp.csr_array
    K: sp.csr_array
    C: sp.csr_array
    rigid_body_vectors: np.ndarray
    mass_diagonal: np.ndarray | None = None

    @property
    def diagonal_mass(self) -> bool:
        """True when the reduced mass matrix is diagonal (every mass block diagonal)."""
        return self.mass_diagonal is not None

    @property
    def mass(self) -> np.ndarray:
        """Reduced inertias, kg·m², the diagonal of a diagonal M (the fast paths).

        Raises
        ------
        ModelError
            Where M is not diagonal (a shaft with consistent inertia): use :attr:`M`.
        """
        if self.mass_diagonal is None:
            raise ModelError(
                "the mass matrix is not diagonal (a shaft carries consistent inertia); use Assembly.M, "
                "or mass_model = 'lumped' for a diagonal one",
                element=self.drivetrain.name,
                field="mass",
            )
        return self.mass_diagonal

    def mass_times(self, X: np.ndarray) -> np.ndarray:
        """M X on the reduced coordinates, kg·m² times the unit of X (diagonal M: a scaling of rows).

        Parameters
        ----------
        X : ndarray
            (n,) or (n, m) reduced coordinates, e.g. mode shapes in rad.
        """
        if self.mass_diagonal is not None:
            d = self.mass_diagonal
            return d * X if X.ndim == 1 else d[:, None] * X
        return np.asarray(self.M @ X)

    def mass_operator(self) -> sp.sparray:
        """M as a sparse matrix for the solvers, kg·m² (``diags_array`` of :attr:`mass` when diagonal)."""
        if self.mass_diagonal is not None:
            return sp.diags_array(self.mass_diagonal)
        return self.M

    @property
    def n(self) -> int:
        """Number of independent coordinates."""
        return self.K.shape[0]

    @property
    def n_rigid_body(self) -> int:
        """Number of rigid-body modes (free branches)."""
        return self.rigid_body_vectors.shape[1]

    @cached_property
    def stiffness_operator(self) -> sp.csr_array | np.ndarray:
        """K for the eigen solvers, N·m/rad: dense where the model is small (up to
        ``_DENSE_STIFFNESS`` coordinates, solved densely: no conversion per solve), else :attr:`K`."""
        return self.K.toarray() if self.n <= _DENSE_STIFFNESS else self.K

    @cached_property
    def rigid_body_unit_shapes(self) -> np.ndarray:
        """:attr:`rigid_body_vectors` scaled to a largest magnitude of 1 (rad), built once."""
        return _unit_shapes(self.rigid_body_vectors)

    @cached_property
    def M_full(self) -> sp.csr_array:
        """Mass over all degrees of freedom before the rigid-mesh reduction, kg·m²."""
        return _scatter(self.drivetrain, "mass")

    @cached_property
    def K_full(self) -> sp.csr_array:
        """Stiffness over all degrees of freedom before the rigid-mesh reduction, N·m/rad."""
        return _scatter(self.drivetrain, "stiffness")

    @cached_property
    def C_full(self) -> sp.csr_array:
        """Damping over all degrees of freedom before the rigid-mesh reduction, N·m·s/rad."""
        return _scatter(self.drivetrain, "damping")


#: Largest model (coordinates) whose stiffness the eigen solvers get dense (they solve it densely).
_DENSE_STIFFNESS = 150


def _unit_shapes(shapes: np.ndarray) -> np.ndarray:
    """Scale each column to a largest magnitude of 1, that entry positive."""
    if shapes.size == 0:
        return shapes.copy()
    i = np.argmax(np.abs(shapes), axis=0)
    peak = shapes[i, np.arange(shapes.shape[1])]
    return shapes / np.where(peak == 0, 1.0, peak)


def _csr(rows: np.ndarray, cols: np.ndarray, vals: np.ndarray, shape: tuple[int, int]) -> sp.csr_array:
    """The sparse matrix of the triplets, duplicates summed, indices sorted: as COO → CSR gives it,
    built in NumPy (scipy's conversions cost more than the sums on the small models of a study)."""
    n_rows, n_cols = shape
    key = rows.astype(np.int64) * n_cols + cols
    order = np.argsort(key, kind="stable")
    key, vals = key[order], np.asarray(vals, dtype=float)[order]
    if key.size:
        starts = np.flatnonzero(np.concatenate(([True], key[1:] != key[:-1])))
        data, key = np.add.reduceat(vals, starts), key[starts]
    else:
        data = vals
    indptr = np.zeros(n_rows + 1, dtype=np.int32)
    np.cumsum(np.bincount(key // n_cols, minlength=n_rows), out=indptr[1:])
    return sp.csr_array((data, (key % n_cols).astype(np.int32), indptr), shape=shape)


def _diagonal(values: np.ndarray) -> sp.csr_array:
    """The diagonal matrix of ``values`` as CSR (built directly)."""
    n = values.size
    at = np.arange(n + 1, dtype=np.int32)
    return sp.csr_array((np.asarray(values, dtype=float), at[:-1], at), shape=(n, n))


def _scatter(drivetrain: DrivetrainLike, which: str) -> sp.csr_array:
    n = len(drivetrain.dof_names)
    rows, cols, vals = [], [], []
    for g in drivetrain.block_groups(which):
        k = g.dofs.shape[1]
        rows.append(np.repeat(g.dofs, k, axis=1).ravel())
        cols.append(np.tile(g.dofs, (1, k)).ravel())
        vals.append(g.blocks.ravel())
    if not rows:
        return sp.csr_array((n, n))
    return _csr(np.concatenate(rows), np.concatenate(cols), np.concatenate(vals), (n, n))


def _reduction(drivetrain: DrivetrainLike) -> tuple[sp.csr_array, tuple[str, ...]]:
    """θ = T q for the rigid-mesh constraints; each disk follows its group's first disk."""
    n = len(drivetrain.dof_names)
    links = []
    for a, b, ratio, e, count in drivetrain._constraints:
        if count != 2:  # pragma: no cover - no such element yet
            raise ModelCheckError("only two-disk constraints can be reduced", element=e.name)
        links.append((a, b, ratio, e))
    if not links:
        return _diagonal(np.ones(n)), drivetrain.dof_names
    group, amp, locked = drivetrain._propagate(links)
    for bad in locked:
        if bad is not None:
            raise ModelCheckError(
                "closes a loop of rigid gear meshes whose ratios disagree, so the train cannot turn; "
                "make one mesh of the loop flexible or correct the ratios",
                element=bad.name,
            )
    n_groups = int(group.max()) + 1
    T = sp.csr_array((amp, (np.arange(n), group)), shape=(n, n_groups))
    first = [int(np.flatnonzero(group == g)[0]) for g in range(n_groups)]
    return T, tuple(drivetrain.dof_names[i] for i in first)


def _reduce(T: sp.csr_array, A: sp.csr_array, reduced: bool) -> sp.csr_array:
    """Tᵀ A T (A itself when no rigid mesh removed a coordinate, T being the identity)."""
    return sp.csr_array(T.T @ A @ T) if reduced else A


def assemble(drivetrain: _Model, *, check: bool = True) -> Assembly[_Model]:
    """Assemble the reduced mass, stiffness and damping matrices of a drivetrain.

    Parameters
    ----------
    drivetrain : Drivetrain
    check : bool
        Run the element and rigid-body checks (default). See Notes.

    Returns
    -------
    Assembly

    Raises
    ------
    ModelCheckError
        Naming the element whose block is not symmetric or not positive semi-definite, or which
        resists the rigid-body rotation of a free branch (a stiffness that grounds a free drivetrain),
        or a loop of rigid meshes that locks the train.

    Notes
    -----
    Checks: every element block symmetric and positive semi-definite; the assembled K annihilates
    the exact rigid-body motion of each free branch (so the number of zero modes equals the number
    of free branches). Together they make K symmetric semi-definite with the right null space. The
    reduced M must be positive definite: every coordinate carries inertia, and a non-diagonal M
    has a Cholesky factor.

    The checked assembly is built once per model and kept with it (:attr:`Drivetrain.assembly`).
    """
    return drivetrain.assembly if check else _assemble(drivetrain, check=False)


def _mass_diagonal(drivetrain: DrivetrainLike) -> np.ndarray | None:
    """The diagonal of the full mass matrix where every mass block is diagonal, else None.

    Disks only: their inertias, exactly (the fast path every model without shaft inertia takes).
    """
    n = len(drivetrain.dof_names)
    J = np.zeros(n)
    for g in drivetrain.block_groups("mass"):
        B = g.blocks
        k = B.shape[1]
        if k > 1 and np.any(B[:, ~np.eye(k, dtype=bool)]):
            return None
        np.add.at(J, g.dofs, np.diagonal(B, axis1=1, axis2=2))
    return J


def _assemble(drivetrain: _Model, *, check: bool) -> Assembly[_Model]:
    T, names = _reduction(drivetrain)
    reduced = T.shape[0] != T.shape[1]
    J = _mass_diagonal(drivetrain)
    if J is not None:
        mass = np.asarray(T.multiply(T).T @ J) if reduced else J  # one entry per row of T: TᵀMT diagonal
        M = _diagonal(mass)
    else:
        mass = None
        M = _reduce(T, _scatter(drivetrain, "mass"), reduced)
    rigid = drivetrain.free_branches()
    R = np.column_stack(rigid) if rigid else np.zeros((T.shape[0], 0))
    asm = Assembly(
        drivetrain=drivetrain,
        T=T,
        coordinate_names=names,
        M=M,
        K=_reduce(T, _scatter(drivetrain, "stiffness"), reduced),
        C=_reduce(T, _scatter(drivetrain, "damping"), reduced),
        rigid_body_vectors=R,
        mass_diagonal=mass,
    )
    if check:
        _check_elements(drivetrain)
        _check_mass(asm)
        _check_rigid_body(asm)
    return asm


#: Largest non-diagonal reduced M of wide band whose definiteness is checked by a dense Cholesky factor.
_CHOLESKY_LIMIT = 3000


def _check_mass(asm: Assembly) -> None:
    """The reduced M symmetric positive definite: every coordinate has inertia, and M = L Lᵀ.

    A non-diagonal M is factored in the reverse Cuthill–McKee order, as a band (a chain of shaft
    elements has band 1), densely where the band is wide; beyond ``_CHOLESKY_LIMIT`` coordinates of
    wide band the positive diagonal and the elements' positive semi-definite blocks are the check.
    """
    diagonal = asm.M.diagonal()
    empty = np.flatnonzero(~(diagonal > 0))
    if empty.size:
        raise ModelCheckError(
            f"coordinate {asm.coordinate_names[int(empty[0])]!r} has no inertia (mass matrix entry "
            f"{diagonal[empty[0]]:g} kg·m²); give it a disk or a shaft with inertia",
            element=asm.drivetrain.name,
        )
    if asm.diagonal_mass:
        return
    M = asm.M
    if abs(M - M.T).max() > _TOL * abs(M).max():
        raise ModelCheckError("the assembled mass matrix is not symmetric", element=asm.drivetrain.name)
    perm = csgraph.reverse_cuthill_mckee(M, symmetric_mode=True)
    Mp = sp.csr_array(M[perm][:, perm]).tocoo()
    band = int(np.abs(Mp.row - Mp.col).max())
    try:
        if band <= 64:
            n = M.shape[0]
            upper = np.zeros((band + 1, n))
            keep = Mp.col >= Mp.row
            upper[band + Mp.row[keep] - Mp.col[keep], Mp.col[keep]] = Mp.data[keep]
            sla.cholesky_banded(upper, lower=False)
        elif M.shape[0] <= _CHOLESKY_LIMIT:
            np.linalg.cholesky(M.toarray())
    except np.linalg.LinAlgError:
        raise ModelCheckError(
            "the assembled mass matrix is not positive definite; check the shafts' inertias",
            element=asm.drivetrain.name,
        ) from None


def _element_name(drivetrain: DrivetrainLike, position: int) -> str:
    return drivetrain.element_blocks[position][0].name


def _check_elements(drivetrain: DrivetrainLike) -> None:
    for which in ("mass", "stiffness", "damping"):
        for g in drivetrain.block_groups(which):
            B = g.blocks
            scale = np.maximum(np.abs(B).max(axis=(1, 2)), np.finfo(float).tiny)
            asym = np.abs(B - B.transpose(0, 2, 1)).max(axis=(1, 2)) > _TOL * scale
            if asym.any():
                i = int(np.argmax(asym))
                raise ModelCheckError(
                    f"its {which} block is not symmetric: {B[i].tolist()}",
                    element=_element_name(drivetrain, g.elements[i]),
                )
            lowest = np.linalg.eigvalsh(B).min(axis=1)
            bad = lowest < -_TOL * scale
            if bad.any():
                i = int(np.argmax(bad))
                raise ModelCheckError(
                    f"its {which} block is not positive semi-definite (eigenvalue {lowest[i]:.4g})",
                    element=_element_name(drivetrain, g.elements[i]),
                )


def _check_rigid_body(asm: Assembly) -> None:
    dt = asm.drivetrain
    for r in asm.rigid_body_vectors.T:
        for g in dt.block_groups("stiffness"):
            re = r[g.dofs]  # (m, k)
            resid = np.abs(np.einsum("mij,mj->mi", g.blocks, re)).max(axis=1)
            scale = np.abs(g.blocks).max(axis=(1, 2)) * np.abs(re).max(axis=1)
            bad = resid > 1e-9 * scale
            if bad.any():
                i = int(np.argmax(bad))
                raise ModelCheckError(
                    "its stiffness resists the rigid-body rotation of a free branch (it grounds a "
                    "free drivetrain); check its ratio or radii against the meshes of that branch",
                    element=_element_name(dt, g.elements[i]),
                )
