"""What the drivetrain's computations read from a model: its element blocks stacked by size, and its type.

:class:`~mechdyn.drivetrain.Drivetrain` holds the model; the modules that compute from it (the
assembly, the variants made by :meth:`~mechdyn.drivetrain.Drivetrain.with_values`, the chain built from
arrays, the model table) are called by its methods, so they do not import it: they read a model through
:class:`DrivetrainLike`, the structural type that names what they use (a ``Drivetrain`` is one), and
build the :class:`BlockGroup` stacks a model hands out.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import numpy as np

from mechdyn.drivetrain.elements import Disk, Element, ElementBlocks

__all__ = ["BlockGroup", "DrivetrainLike"]


@dataclass(frozen=True)
class BlockGroup:
    """Blocks of equal size from several elements, stacked for vectorised work.

    Attributes
    ----------
    elements : ndarray
        (m,) positions in :attr:`Drivetrain.element_blocks`.
    dofs : ndarray
        (m, k) degree-of-freedom indices (:attr:`Drivetrain.dof_names`) of each block.
    blocks : ndarray
        (m, k, k) the blocks.
    """

    elements: np.ndarray
    dofs: np.ndarray
    blocks: np.ndarray


class DrivetrainLike(Protocol):
    """A drivetrain model as the assembly, the variants and the model table read it: what
    :class:`~mechdyn.drivetrain.Drivetrain` offers (see there for each member; angles in rad,
    inertias kg·m², stiffnesses N·m/rad)."""

    __dataclass_fields__: ClassVar[dict[str, Any]]

    @property
    def name(self) -> str: ...

    @property
    def disks(self) -> tuple[Disk, ...]: ...

    @property
    def elements(self) -> tuple[Element, ...]: ...

    @property
    def provenance(self) -> Mapping[str, str]: ...

    @property
    def dof_names(self) -> tuple[str, ...]: ...

    @property
    def dof_index(self) -> dict[str, int]: ...

    @property
    def element_blocks(self) -> tuple[tuple[Element | Disk, ElementBlocks], ...]: ...

    @property
    def assembly(self) -> Any: ...

    @property
    def _constraints(self) -> tuple[tuple[int, int, float, Element, int], ...]: ...

    @property
    def _load_table(self) -> tuple[tuple[str, ...], tuple[str, ...], Any, Any]: ...

    @property
    def _load_index(self) -> dict[str, int]: ...

    @property
    def _value_layout(self) -> Any: ...

    def block_groups(self, which: str) -> tuple[BlockGroup, ...]: ...

    def free_branches(self) -> list[np.ndarray]: ...

    def _propagate(
        self, links: Sequence[tuple[int, int, float, Element]]
    ) -> tuple[np.ndarray, np.ndarray, list[Element | None]]: ...
