"""The assembly checks, and the hand-typed matrix errors of the published turret study."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from mechdyn.drivetrain import (
    Disk,
    Drivetrain,
    GearMesh,
    Shaft,
    assemble,
    check_matrices,
)
from mechdyn.drivetrain.elements import Element, ElementBlocks
from mechdyn.errors import ModelCheckError


def _full(turret):
    asm = assemble(turret)
    return np.diag(turret.inertias), asm.K_full.toarray(), asm


def _check(turret, M, K, asm):
    check_matrices(
        M,
        K,
        expected_rigid_body_modes=1,
        dof_names=turret.disk_names,
        rigid_body_vectors=asm.rigid_body_vectors,
    )


def test_assembled_turret_passes(turret_b, turret_c):
    for dt in (turret_b, turret_c):
        M, K, asm = _full(dt)
        _check(dt, M, K, asm)


def test_stray_grounding_term_is_flagged(turret_b):
    # published error 1: a stray diagonal term grounds the free drivetrain (first frequency not 0)
    M, K, asm = _full(turret_b)
    K[2, 2] += 1e5
    with pytest.raises(ModelCheckError, match=r"0 zero \(rigid-body\) mode\(s\); expected 1.*resist.*: 3$"):
        _check(turret_b, M, K, asm)


def test_mesh_term_on_the_wrong_gear_is_flagged(turret_b):
    # published error 2: mesh 2's r4² k_c term typed on disk 3's diagonal instead of disk 4's
    M, K, asm = _full(turret_b)
    mesh2 = turret_b.element("mesh 2")
    term = mesh2.stiffness * mesh2.base_radii[0] ** 2
    K[3, 3] -= term
    K[2, 2] += term
    with pytest.raises(
        ModelCheckError, match=r"(not positive semi-definite|zero \(rigid-body\) mode)"
    ) as info:
        _check(turret_b, M, K, asm)
    assert str(info.value).endswith("rows of K that resist the rigid-body motion: 3, 4")


def test_asymmetric_matrix_names_the_entry():
    K = np.array([[1.0, -1.0], [-0.9, 1.0]])
    with pytest.raises(ModelCheckError, match=r"K\[a, b\] = -1 but K\[b, a\] = -0.9"):
        check_matrices(np.eye(2), K, expected_rigid_body_modes=1, dof_names=["a", "b"])


def test_rigid_loop_with_inconsistent_ratios_is_named():
    dt = Drivetrain(
        [Disk("a", 1.0), Disk("b", 1.0), Disk("c", 1.0)],
        [
            GearMesh("ab", ("a", "b"), ratio=2.0),
            GearMesh("bc", ("b", "c"), ratio=3.0),
            GearMesh("ca", ("c", "a"), ratio=5.0),
        ],
    )
    with pytest.raises(ModelCheckError, match=r"element '(ab|bc|ca)'.*loop of rigid gear meshes"):
        assemble(dt)


def test_flexible_loop_with_inconsistent_ratios_locks_the_branch():
    dt = Drivetrain(
        [Disk("a", 1.0), Disk("b", 1.0)],
        [Shaft("s", ("a", "b"), 1e4), GearMesh("g", ("a", "b"), base_radii=(0.05, 0.1), stiffness=1e8)],
    )
    r = assemble(dt)
    assert r.n_rigid_body == 0
    assert np.linalg.eigvalsh(r.K.toarray()).min() > 0


@dataclass(frozen=True)
class _Lopsided(Element):
    """A user-written element with a faulty block, to prove the checks name it."""

    name: str
    block: tuple

    def blocks(self) -> ElementBlocks:
        return ElementBlocks(("a", "b"), stiffness=np.array(self.block))

    def transmission(self) -> float:
        return 1.0


@pytest.mark.parametrize(
    ("block", "message"),
    [
        (((1.0, -1.0), (-0.5, 1.0)), "not symmetric"),
        (((1.0, -2.0), (-2.0, 1.0)), "not positive semi-definite"),
        (((2.0, -1.0), (-1.0, 1.0)), "grounds a free drivetrain"),
    ],
)
def test_faulty_element_blocks_are_reported_with_the_element(block, message):
    dt = Drivetrain([Disk("a", 1.0), Disk("b", 1.0)], [_Lopsided("custom", block)])
    with pytest.raises(ModelCheckError, match=f"element 'custom'.*{message}"):
        assemble(dt)
