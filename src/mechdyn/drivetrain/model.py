"""The drivetrain model: disks and the elements that connect them, as one immutable object."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np

from mechdyn.drivetrain.elements import Disk, Element, ElementBlocks, Shaft
from mechdyn.drivetrain.gear_mesh import GearMesh
from mechdyn.drivetrain.structure import BlockGroup
from mechdyn.errors import ModelError

__all__ = ["BlockGroup", "Drivetrain"]


@dataclass(frozen=True)
class Drivetrain:
    """A torsional drivetrain: disks (degrees of freedom) and connecting/grounding elements.

    Parameters
    ----------
    disks : sequence of Disk
        One torsional degree of freedom each, in the order used for mode shapes.
    elements : sequence of Element
        Shafts, gear meshes, grounded springs and dampers; each refers to disks by name.
    name : str
        A title for tables, plots and the results store.
    provenance : mapping of str → str, optional
        Where a disk's inertia or an element's stiffness came from, by name, where it was not given as
        a number (``"from geometry: l = 120 mm, d = 30 mm, G = 80 GPa"``), a shaft's own inertia under
        ``"<shaft> (inertia)"``; shown by :func:`mechdyn.drivetrain.model_table`. Not part of the
        model's identity (equality).

    Notes
    -----
    The model is immutable; variants are new objects (:meth:`with_rigid_gears`,
    :func:`dataclasses.replace`).

    Its degrees of freedom (:attr:`dof_names`) are the disks, in order, then the nodes that elements
    create inside themselves (a shaft divided into elements, ``"shaft[1]"``, …), element by element.
    Without such elements they are the disks alone.
    """

    disks: tuple[Disk, ...]
    # a factory rather than a class-level default: a variant made by with_values builds its element
    # objects when first read (__getattr__), which a class attribute ``elements`` would shadow
    elements: tuple[Element, ...] = field(default_factory=tuple)
    name: str = "drivetrain"
    provenance: Mapping[str, str] = field(default_factory=dict, compare=False)

    def __getattr__(self, name: str) -> Any:
        # only for attributes not set: the disks and elements of a variant made by with_values, built
        # from its values when first read (its analyses do not need them)
        if name in ("disks", "elements") and "_values" in self.__dict__:
            from mechdyn.drivetrain.variants import variant_items

            disks, elements = variant_items(self.__dict__["_value_layout"], self.__dict__["_values"])
            self.__dict__.update(disks=disks, elements=elements)
            return self.__dict__[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __post_init__(self) -> None:
        object.__setattr__(self, "disks", tuple(self.disks))
        object.__setattr__(self, "elements", tuple(self.elements))
        if not self.disks:
            raise ModelError("a drivetrain needs at least one disk")
        seen: set[str] = set()
        for item in (*self.disks, *self.elements):
            if item.name in seen:
                raise ModelError(
                    "the name is used twice; give every disk and element its own name",
                    element=item.name,
                    field="name",
                )
            seen.add(item.name)
        for d in self.disks:
            if not isinstance(d, Disk):
                raise ModelError(f"{type(d).__name__} is not a Disk", element=getattr(d, "name", None))
        known = set(self.disk_names)
        for e in self.elements:
            if isinstance(e, Disk):
                raise ModelError("a disk belongs in `disks`, not `elements`", element=e.name)
        for e, b in self.element_blocks:
            for node in b.internal:
                if node in seen:
                    raise ModelError(
                        f"the node {node!r} inside it has the name of another disk, element or node; "
                        "rename one of them",
                        element=e.name,
                        field="name",
                    )
                seen.add(node)
            for disk_name in b.disks:
                if disk_name not in known and disk_name not in b.internal:
                    raise ModelError(
                        f"refers to disk {disk_name!r}, which is not defined; "
                        f"defined disks: {', '.join(self.disk_names)}",
                        element=e.name,
                        field="disks",
                    )

    @classmethod
    def chain(
        cls,
        inertias: Any,
        stiffnesses: Any,
        *,
        damping: Any = None,
        name: str = "drivetrain",
        disk_names: Sequence[str] | None = None,
        shaft_names: Sequence[str] | None = None,
    ) -> Drivetrain:
        """A chain of n disks joined by n − 1 shafts, built from arrays: for long chains.

        Parameters
        ----------
        inertias : array_like or pint.Quantity
            (n,) disk inertias J, kg·m² (plain numbers are SI; a quantity array may be in any unit
            of inertia), each from 1e-18 to 1e10 kg·m².
        stiffnesses : array_like or pint.Quantity
            (n − 1,) shaft stiffnesses, N·m/rad, shaft i joining disks i and i + 1, each from 1e-9 to
            1e14 N·m/rad.
        damping : array_like or pint.Quantity, optional
            (n − 1,) shaft damping, N·m·s/rad, from 0 to 1e15 N·m·s/rad (default: none).
        name : str
            The model's name.
        disk_names, shaft_names : sequence of str, optional
            Default ``"d0"``, ``"d1"``, … and ``"s0"``, ``"s1"``, …; all distinct.

        Returns
        -------
        Drivetrain
            Equal to ``Drivetrain([Disk(...), ...], [Shaft(...), ...])`` with the same values, and
            analysed the same way; built in arrays (the values converted and checked once,
            vectorised; the element blocks, names, rigid-body branch and load rows made as arrays, no
            walk over the elements), so a chain of 10⁵ disks builds in a fraction of a second.
        """
        from mechdyn.drivetrain.arrays import chain

        return chain(
            cls,
            inertias,
            stiffnesses,
            damping=damping,
            name=name,
            disk_names=disk_names,
            shaft_names=shaft_names,
        )

    def to_frame(self) -> Any:
        """The model as assembled, one row per disk and element: name, kind, disks, value (SI), unit
        and where it came from (:func:`mechdyn.drivetrain.model_frame`)."""
        from mechdyn.drivetrain.summary import model_frame

        return model_frame(self)

    # -- naming -------------------------------------------------------------------------------
    @cached_property
    def disk_names(self) -> tuple[str, ...]:
        return tuple(d.name for d in self.disks)

    @cached_property
    def disk_index(self) -> dict[str, int]:
        """Position of each disk among the degrees of freedom (the disks come first, in order)."""
        return {n: i for i, n in enumerate(self.disk_names)}

    @cached_property
    def dof_names(self) -> tuple[str, ...]:
        """The degrees of freedom: the disks, then the nodes inside divided shafts (``"shaft[1]"``, …)."""
        inside = tuple(node for _, b in self.element_blocks for node in b.internal)
        return (*self.disk_names, *inside) if inside else self.disk_names

    @cached_property
    def dof_index(self) -> dict[str, int]:
        """Position of each degree of freedom (disk or node inside an element) by name."""
        return {n: i for i, n in enumerate(self.dof_names)}

    @property
    def total_inertia(self) -> float:
        """Σ J of the disks plus the shafts' own inertias, kg·m² (what turns, meshes' ratios aside)."""
        shafts = sum(getattr(e, "inertia", 0.0) for e in self.elements)
        return float(sum(d.inertia for d in self.disks) + shafts)

    @property
    def inertias(self) -> np.ndarray:
        """Disk inertias J, kg·m², in disk order."""
        return np.array([d.inertia for d in self.disks])

    def element(self, name: str) -> Element | Disk:
        """The disk or element called ``name``.

        Parameters
        ----------
        name : str
            A disk's or an element's name.
        """
        for item in (*self.disks, *self.elements):
            if item.name == name:
                return item
        raise KeyError(name)

    @property
    def meshes(self) -> tuple[GearMesh, ...]:
        return tuple(e for e in self.elements if isinstance(e, GearMesh))

    @cached_property
    def element_blocks(self) -> tuple[tuple[Element | Disk, ElementBlocks], ...]:
        """Every disk and element with its blocks, computed once."""
        return tuple((e, e.blocks()) for e in (*self.disks, *self.elements))

    def block_groups(self, which: str) -> tuple[BlockGroup, ...]:
        """The elements' ``which`` blocks ("mass", "stiffness", "damping"), stacked by block size, their
        rows and columns the degrees of freedom :attr:`dof_names`.

        Parameters
        ----------
        which : {"mass", "stiffness", "damping"}
            The matrix whose blocks are wanted (kg·m², N·m/rad or N·m·s/rad).
        """
        return self._block_groups[which]

    @cached_property
    def _block_groups(self) -> dict[str, tuple[BlockGroup, ...]]:
        idx = self.dof_index
        kinds = ("mass", "stiffness", "damping")
        # one walk over the elements for the three matrices: (which, block size) → positions, dofs, blocks
        by_size: dict[tuple[str, int], tuple[list[int], list[list[int]], list[np.ndarray]]] = {}
        for i, (_, b) in enumerate(self.element_blocks):
            dofs = [idx[d] for d in b.disks]
            for which, block in zip(kinds, (b.mass, b.stiffness, b.damping), strict=True):
                if block is None:
                    continue
                e_list, d_list, b_list = by_size.setdefault((which, len(dofs)), ([], [], []))
                e_list.append(i)
                d_list.append(dofs)
                b_list.append(block)
        out: dict[str, tuple[BlockGroup, ...]] = {which: () for which in kinds}
        for (which, _), (e, d, bl) in by_size.items():
            group = BlockGroup(np.array(e), np.array(d, dtype=np.intp), np.array(bl, dtype=float))
            out[which] = (*out[which], group)
        return out

    @cached_property
    def _load_table(self) -> tuple[tuple[str, ...], tuple[str, ...], Any, Any]:
        """The elements that carry a load, their units, and the sparse rows giving each load from the
        degrees of freedom's angles (N·m/rad or N/rad) and from their rates (N·m·s/rad or N·s/rad)."""
        import scipy.sparse as sp

        if "_values" in self.__dict__:  # a variant made by with_values: its base's structure
            from mechdyn.drivetrain.variants import variant_loads

            return variant_loads(self._value_layout, self.__dict__["_values"])

        idx = self.dof_index
        names: list[str] = []
        units: list[str] = []
        rows: list[int] = []
        cols: list[int] = []
        vals: list[np.ndarray] = []
        rate_vals: list[np.ndarray] = []
        for e, b in self.element_blocks:
            if b.load_row is None:
                continue
            i = len(names)
            names.append(e.name)
            units.append(b.load_unit)
            rows += [i] * len(b.disks)
            cols += [idx[d] for d in b.disks]
            vals.append(b.load_row)
            rate_vals.append(b.load_rate_row if b.load_rate_row is not None else np.zeros(len(b.disks)))
        shape = (len(names), len(self.dof_names))
        if not names:
            return (), (), sp.csr_array(shape), sp.csr_array(shape)
        L = sp.csr_array((np.concatenate(vals), (rows, cols)), shape=shape)
        L_rate = sp.csr_array((np.concatenate(rate_vals), (rows, cols)), shape=shape)
        L_rate.eliminate_zeros()
        return tuple(names), tuple(units), L, L_rate

    @cached_property
    def _load_index(self) -> dict[str, int]:
        """Row of each load-carrying element in :attr:`_load_table`, by name."""
        return {n: i for i, n in enumerate(self._load_table[0])}

    @cached_property
    def assembly(self) -> Any:
        """The checked :class:`~mechdyn.drivetrain.Assembly` of this model, built once.

        The model is immutable, so its matrices are too: every analysis of the same model shares
        them (a study's repeated analyses of one variant pay for the assembly once).
        """
        if "_values" in self.__dict__:  # a variant made by with_values: its base's structure
            from mechdyn.drivetrain.variants import variant_assembly

            return variant_assembly(self, self._value_layout, self.__dict__["_values"])
        from mechdyn.drivetrain.assembly import _assemble

        return _assemble(self, check=True)

    @cached_property
    def _value_layout(self) -> Any:
        """How the assembled matrices follow the element values
        (:func:`mechdyn.drivetrain.variants.value_layout`), shared by every variant :meth:`with_values`
        makes."""
        from mechdyn.drivetrain.variants import value_layout

        return value_layout(self)

    def with_values(self, **values: Mapping[str, Any]) -> Drivetrain:
        """A variant with new inertias, stiffnesses or damping: the same disks, elements and geometry.

        Parameters
        ----------
        **values : mapping of name → value
            By value field, the new values of the disks and elements named: ``inertia`` (a disk's or
            a shaft's, kg·m²), ``stiffness`` (a shaft's or grounded spring's N·m/rad, a flexible
            mesh's N/m), ``damping`` (N·m·s/rad, a mesh's N·s/m); plain numbers are SI, quantities
            are converted. Each is checked with its element's bounds (``Element.VALUES``).

        Returns
        -------
        Drivetrain
            Equal to the model rebuilt with ``dataclasses.replace`` on those elements (and to the
            model built from element lists with the new values); its matrices, though, are made from
            this model's structure (:mod:`mechdyn.drivetrain.variants`): the values enter a weighted
            sum per matrix, no element is re-checked nor the assembly with its checks redone, and its
            disk and element objects are made only when read, so a variant of a small model costs
            about twice its bare eigen solve (``benchmarks/modal_chain.py``). A value that appears or
            vanishes (a damping from or to 0, a shaft's inertia) changes the structure: that variant
            is rebuilt in full. Provenance entries of the changed values are dropped.

        Raises
        ------
        mechdyn.errors.ModelError
            Naming the element, the field and the value, for a value that is not finite, not
            positive where it must be, beyond the element's bounds, or of the wrong unit; a name that
            is not a disk or element of the model; a field the element does not have. The new values
            are checked here, once (plain numbers together, vectorised); the analyses of the variant
            do not check its matrices again.

        Examples
        --------
        >>> from mechdyn.drivetrain import Disk, Drivetrain, Shaft, modal
        >>> pair = Drivetrain([Disk("a", 1.0), Disk("b", 2.0)], [Shaft("s", ("a", "b"), 1000.0)])
        >>> stiffer = pair.with_values(stiffness={"s": 4000.0})
        >>> round(float(modal(stiffer).frequencies_hz[0] / modal(pair).frequencies_hz[0]), 12)
        2.0
        """
        from mechdyn.drivetrain.variants import with_values

        return with_values(self, values)

    # -- variants -----------------------------------------------------------------------------
    def with_rigid_gears(self) -> Drivetrain:
        """The same drivetrain with every gear mesh a rigid kinematic constraint (built once)."""
        return self._rigid_gears

    @cached_property
    def _rigid_gears(self) -> Drivetrain:
        elements = tuple(e.as_rigid() if isinstance(e, GearMesh) else e for e in self.elements)
        return replace(self, elements=elements, name=self.name)

    # -- topology -----------------------------------------------------------------------------
    def _links(self, only: type | None = None) -> list[tuple[int, int, float, Element]]:
        idx = self.dof_index
        out = []
        for e, b in self.element_blocks:
            t = e.transmission()
            if t is None or len(b.disks) < 2 or (only is not None and not isinstance(e, only)):
                continue
            # an element with nodes inside is a chain from its first to its last degree of freedom: the
            # nodes follow one another at 1, the last link carries the element's transmission
            chain = [idx[d] for d in b.disks]
            for a, z in itertools.pairwise(chain[:-1]):
                out.append((a, z, 1.0, e))
            out.append((chain[-2], chain[-1], t, e))
        return out

    def _propagate(
        self, links: Sequence[tuple[int, int, float, Element]]
    ) -> tuple[np.ndarray, np.ndarray, list[Element | None]]:
        """Label connected groups and the rigid-motion amplitude of each disk within its group.

        Returns the group label per disk, the amplitude per disk (1 at the group's first disk), and
        per group the first element that closes a loop with inconsistent ratios (None if none).
        """
        n = len(self.dof_names)
        adj: list[list[tuple[int, float, Element]]] = [[] for _ in range(n)]
        for a, b, t, e in links:
            adj[a].append((b, t, e))
            adj[b].append((a, 1.0 / t, e))
        group = np.full(n, -1)
        amp = np.zeros(n)
        locked: list[Element | None] = []
        for start in range(n):
            if group[start] >= 0:
                continue
            g = len(locked)
            locked.append(None)
            group[start] = g
            amp[start] = 1.0
            stack = [start]
            while stack:
                i = stack.pop()
                for j, t, e in adj[i]:
                    if group[j] < 0:
                        group[j] = g
                        amp[j] = amp[i] * t
                        stack.append(j)
                    elif locked[g] is None and not math.isclose(amp[j], amp[i] * t, rel_tol=1e-9):
                        locked[g] = e
        return group, amp, locked

    @cached_property
    def _components(self) -> tuple[np.ndarray, np.ndarray, list[Element | None]]:
        return self._propagate(self._links())

    @property
    def component_of_disk(self) -> np.ndarray:
        """Label of the connected branch (through shafts and meshes) of each degree of freedom."""
        return self._components[0]

    @cached_property
    def _grounded_dofs(self) -> np.ndarray:
        """The degrees of freedom that an element ties to the frame through a stiffness."""
        idx = self.dof_index
        return np.array(
            sorted({idx[d] for _, b in self.element_blocks if b.grounds for d in b.disks}), dtype=np.intp
        )

    @cached_property
    def _constraints(self) -> tuple[tuple[int, int, float, Element, int], ...]:
        """The rigid constraints: (first dof, second dof, θ_second/θ_first, element, disks in the
        constraint), from the elements' constraint rows."""
        idx = self.dof_index
        out = []
        for e, b in self.element_blocks:
            if b.constraint is None:
                continue
            ca, cb = b.constraint[0], b.constraint[-1]
            out.append((idx[b.disks[0]], idx[b.disks[-1]], -ca / cb, e, len(b.disks)))
        return tuple(out)

    def free_branches(self) -> list[np.ndarray]:
        """Rigid-body motions of the branches that can turn freely, one full-length vector each.

        A branch is a set of disks connected through shafts and meshes. It turns freely (one
        rigid-body mode) unless a grounded spring holds it or a loop of meshes with inconsistent
        ratios locks it. The vector gives each degree of freedom's angle (:attr:`dof_names`) for a
        unit angle of the branch's first disk, following shaft (1) and mesh (∓ratio) transmissions.
        """
        group, amp, locked = self._components
        grounded = set(np.unique(group[self._grounded_dofs]).tolist())
        vectors = []
        for g in range(len(locked)):
            if g in grounded or locked[g] is not None:
                continue
            v = np.where(group == g, amp, 0.0)
            vectors.append(v)
        return vectors

    def shaft_lines(self) -> list[tuple[str, ...]]:
        """Groups of disks joined by shafts alone (each group turns at one mean speed)."""
        group, _, _ = self._propagate(self._links(only=Shaft))
        lines: dict[int, list[str]] = {}
        for name, g in zip(self.disk_names, group[: len(self.disks)], strict=True):
            lines.setdefault(int(g), []).append(name)
        return [tuple(v) for v in lines.values()]

    def speed_ratios(self, reference: str) -> np.ndarray:
        """``|ω_disk / ω_reference|`` for every disk, from shafts (1) and mesh ratios (teeth first).

        Disks not connected to ``reference`` get NaN.

        Parameters
        ----------
        reference : str
            The disk whose speed is 1.

        """
        if reference not in self.disk_index:
            raise ModelError(
                f"reference disk {reference!r} is not defined; defined disks: {', '.join(self.disk_names)}"
            )
        links = [
            (a, b, -1.0 / e.speed_ratio if isinstance(e, GearMesh) else t, e) for a, b, t, e in self._links()
        ]
        group, amp, _ = self._propagate(links)
        r = self.disk_index[reference]
        out = np.abs(amp / amp[r])
        out[group != group[r]] = np.nan
        return out[: len(self.disks)]
