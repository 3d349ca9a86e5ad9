"""Assembly of the drivetrain matrices from the model, with the checks that guard them.

The matrices are never typed by hand: every element contributes its blocks through
:meth:`~mechdyn.drivetrain.elements.Element.blocks`, rigid meshes become a transformation
θ = T q to independent coordinates q, and the reduced matrices are Tᵀ M T, Tᵀ K T, Tᵀ C T.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import ModelCheckError

__all__ = ["Assembly", "assemble"]

_TOL = 1e-10


@dataclass(frozen=True)
class Assembly:
    """The assembled drivetrain.

    Attributes
    ----------
    drivetrain : Drivetrain
        The model it was assembled from.
    T : scipy.sparse.csr_array
        (n_disks, n_coordinates) transformation θ = T q; one entry per row (each disk follows one
        independent coordinate through rigid meshes).
    coordinate_names : tuple of str
        The disk that each independent coordinate is (the first disk of its rigidly geared group).
    mass : ndarray
        Reduced inertias (the reduced mass matrix is diagonal), kg·m².
    K, C : scipy.sparse.csr_array
        Reduced stiffness (N·m/rad) and damping (N·m·s/rad) matrices.
    rigid_body_vectors : ndarray
        (n_disks, n_free) exact rigid-body motions, one per free branch, rad per unit motion.
    """

    drivetrain: Drivetrain
    T: sp.csr_array
    coordinate_names: tuple[str, ...]
    mass: np.ndarray
    K: sp.csr_array
    C: sp.csr_array
    rigid_body_vectors: np.ndarray

    @property
    def n(self) -> int:
        """Number of independent coordinates."""
        return self.mass.size

    @property
    def n_rigid_body(self) -> int:
        """Number of rigid-body modes (free branches)."""
        return self.rigid_body_vectors.shape[1]

    @cached_property
    def K_full(self) -> sp.csr_array:
        """Stiffness over all disks before the rigid-mesh reduction, N·m/rad."""
        return _scatter(self.drivetrain, "stiffness")

    @cached_property
    def C_full(self) -> sp.csr_array:
        """Damping over all disks before the rigid-mesh reduction, N·m·s/rad."""
        return _scatter(self.drivetrain, "damping")


def _scatter(drivetrain: Drivetrain, which: str) -> sp.csr_array:
    n = len(drivetrain.disks)
    rows, cols, vals = [], [], []
    for g in drivetrain.block_groups(which):
        k = g.dofs.shape[1]
        rows.append(np.repeat(g.dofs, k, axis=1).ravel())
        cols.append(np.tile(g.dofs, (1, k)).ravel())
        vals.append(g.blocks.ravel())
    if not rows:
        return sp.csr_array((n, n))
    return sp.coo_array(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    ).tocsr()


def _reduction(drivetrain: Drivetrain) -> tuple[sp.csr_array, tuple[str, ...]]:
    """θ = T q for the rigid-mesh constraints; each disk follows its group's first disk."""
    idx = drivetrain.disk_index
    n = len(drivetrain.disks)
    links = []
    for e, b in drivetrain.element_blocks:
        if b.constraint is None:
            continue
        if len(b.disks) != 2:  # pragma: no cover - no such element yet
            raise ModelCheckError("only two-disk constraints can be reduced", element=e.name)
        ca, cb = b.constraint
        links.append((idx[b.disks[0]], idx[b.disks[1]], -ca / cb, e))
    if not links:
        return sp.csr_array(sp.identity(n, format="csr")), drivetrain.disk_names
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
    return T, tuple(drivetrain.disk_names[i] for i in first)


def _reduce(T: sp.csr_array, A: sp.csr_array, reduced: bool) -> sp.csr_array:
    """Tᵀ A T (A itself when no rigid mesh removed a coordinate, T being the identity)."""
    return sp.csr_array(T.T @ A @ T) if reduced else A


def assemble(drivetrain: Drivetrain, *, check: bool = True) -> Assembly:
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
    of free branches). Together they make K symmetric semi-definite with the right null space.

    The checked assembly is built once per model and kept with it (:attr:`Drivetrain.assembly`).
    """
    return drivetrain.assembly if check else _assemble(drivetrain, check=False)


def _assemble(drivetrain: Drivetrain, *, check: bool) -> Assembly:
    T, names = _reduction(drivetrain)
    reduced = T.shape[0] != T.shape[1]
    J = drivetrain.inertias
    mass = np.asarray(T.multiply(T).T @ J) if reduced else J  # one entry per row of T: TᵀMT diagonal
    rigid = drivetrain.free_branches()
    R = np.column_stack(rigid) if rigid else np.zeros((len(J), 0))
    asm = Assembly(
        drivetrain=drivetrain,
        T=T,
        coordinate_names=names,
        mass=mass,
        K=_reduce(T, _scatter(drivetrain, "stiffness"), reduced),
        C=_reduce(T, _scatter(drivetrain, "damping"), reduced),
        rigid_body_vectors=R,
    )
    if check:
        _check_elements(drivetrain)
        _check_rigid_body(asm)
    return asm


def _element_name(drivetrain: Drivetrain, position: int) -> str:
    return drivetrain.element_blocks[position][0].name


def _check_elements(drivetrain: Drivetrain) -> None:
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
