"""New values on a built drivetrain: the same disks and elements, other inertias, stiffnesses, damping.

A design study evaluates thousands of variants of one model. Rebuilding each (element objects checked one
by one, the model's names and topology, the element blocks, the assembly and its checks) costs many
times the eigen solve of a small model. The assembled matrices are linear in the element values
(a shaft's block is k [[1, −1], [−1, 1]], a disk's J), so the structure is worked out once per model
(:func:`value_layout`) and a variant's reduced M, K, C and load rows are one weighted sum each over it.
:meth:`Drivetrain.with_values` checks the new values (vectorised, with the elements' own bounds) and
builds the variant on the shared structure; its assembly needs no checks (positive values on the same
structure keep every block symmetric semi-definite and the rigid-body motions as they were).

Validation happens once, at this edge: plain numbers are checked together against the bounds each
element's constructor applies (finite, positive where they must be, within the magnitude limit of the
unit), and a bad one raises the element's own message naming the element, the field and the value; the
variant's analyses then trust its matrices (:func:`mechdyn.drivetrain.modal` does not check them again).
The variant's disk and element objects, which its analyses do not need, are made when first read
(:func:`variant_items`): a new variant of a 10-disk model costs about twice the bare eigen solve.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import Any, TypeVar

import numpy as np
import scipy.sparse as sp

from mechdyn.checks import magnitude_limit, smallest_positive
from mechdyn.drivetrain.arrays import trusted
from mechdyn.drivetrain.assembly import _DENSE_STIFFNESS, Assembly
from mechdyn.drivetrain.structure import DrivetrainLike
from mechdyn.errors import ModelError

__all__ = ["ValueLayout", "value_layout", "variant_items", "with_values"]

_LINEAR_TOL = 1e-12
#: The model a variant is made of, and made as (:class:`~mechdyn.drivetrain.Drivetrain`).
_Model = TypeVar("_Model", bound=DrivetrainLike)
#: What the variant shares with its base model: everything that does not depend on the values.
_STRUCTURE = (
    "disk_names",
    "disk_index",
    "dof_names",
    "dof_index",
    "_components",
    "_grounded_dofs",
    "_constraints",
    "_load_index",
)


@dataclass(frozen=True)
class _Linear:
    """data = bincount(position, coef · p[param]) over a fixed sparse structure."""

    position: np.ndarray
    param: np.ndarray
    coef: np.ndarray
    indices: np.ndarray
    indptr: np.ndarray
    shape: tuple[int, int]

    def data(self, p: np.ndarray) -> np.ndarray:
        return np.bincount(self.position, weights=self.coef * p[self.param], minlength=self.indices.size)

    @cached_property
    def rows(self) -> np.ndarray:
        """The row of each stored entry."""
        return np.repeat(np.arange(self.shape[0]), np.diff(self.indptr))

    def csr(self, p: np.ndarray) -> sp.csr_array:
        return sp.csr_array((self.data(p), self.indices, self.indptr), shape=self.shape)


def _linear(
    rows: np.ndarray, cols: np.ndarray, param: np.ndarray, coef: np.ndarray, shape: tuple[int, int]
) -> _Linear:
    keep = coef != 0
    rows, cols, param, coef = rows[keep], cols[keep], param[keep], coef[keep]
    key = rows.astype(np.int64) * shape[1] + cols
    keys = np.unique(key)
    r = keys // shape[1]
    indptr = np.concatenate([[0], np.cumsum(np.bincount(r, minlength=shape[0]))])
    return _Linear(np.searchsorted(keys, key), param, coef, (keys % shape[1]).astype(np.int32), indptr, shape)


@dataclass(frozen=True)
class ValueLayout:
    """How a drivetrain's reduced matrices and load rows follow its element values.

    Attributes
    ----------
    params : dict of (name, field) → int
        Position of each value in the parameter vector.
    units : tuple of (str, str)
        Each value's SI unit and sign rule ("positive", "nonnegative").
    base : ndarray
        The base model's values, SI.
    M, K, C, L, L_rate : _Linear
        The reduced mass, stiffness and damping matrices and the load rows as weighted sums of the
        values over a fixed sparse structure.
    asm : Assembly
        The base model's checked assembly (T, coordinates, rigid-body motions are shared).
    load_names, load_units : tuple of str
        The elements that carry a load and their units (:attr:`Drivetrain._load_table`).
    items : dict of str → int
        Position of each disk and element in ``(*disks, *elements)``, by name.
    names : tuple of (str, str)
        Each value's (element, field), in the parameter vector's order.
    low, high : ndarray
        The accepted range of each value, SI (the elements' own bounds).
    by_field : dict of str → dict of str → int
        Position of each value in the parameter vector by field, then by element name: the look-up
        :func:`with_values` makes per value given.
    item_of : tuple of int
        The position in ``(*disks, *elements)`` of each value's element, in the parameter vector's order.
    """

    params: dict[tuple[str, str], int]
    units: tuple[tuple[str, str], ...]
    base: np.ndarray
    M: _Linear
    K: _Linear
    C: _Linear
    L: _Linear
    L_rate: _Linear
    asm: Assembly
    load_names: tuple[str, ...]
    load_units: tuple[str, ...]
    items: dict[str, int]
    names: tuple[tuple[str, str], ...]
    low: np.ndarray
    high: np.ndarray
    by_field: dict[str, dict[str, int]]
    item_of: tuple[int, ...]


def value_layout(dt: DrivetrainLike) -> ValueLayout | None:
    """The layout of a built model, or None where some element's blocks are not linear in its values
    (no element today).

    Parameters
    ----------
    dt : Drivetrain
    """
    asm = dt.assembly
    T = asm.T
    g, a = T.indices[T.indptr[:-1]], T.data[T.indptr[:-1]]  # each degree of freedom's coordinate, factor
    n_red, n_dof = asm.n, len(dt.dof_names)
    idx = dt.dof_index
    load_row = dt._load_index
    params: dict[tuple[str, str], int] = {}
    units: list[tuple[str, str]] = []
    base: list[float] = []
    parts: dict[str, list[tuple[np.ndarray, np.ndarray, np.ndarray, str]]] = {
        k: [] for k in ("mass", "stiffness", "damping", "load_row", "load_rate_row")
    }
    for e, b0 in dt.element_blocks:
        dofs = np.array([idx[d] for d in b0.disks], dtype=np.intp)
        total: dict[str, Any] = {k: 0.0 for k in parts}
        for field, rule in type(e).VALUES.items():
            v = getattr(e, field)
            if v is None or v == 0:  # a value that is not there: changing it changes the structure
                continue
            b1 = trusted(type(e), **{**e.__dict__, field: 2.0 * v}).blocks()
            j = len(base)
            params[(e.name, field)] = j
            units.append(rule)  # (unit, sign rule)
            base.append(float(v))
            for k in parts:
                x0, x1 = getattr(b0, k), getattr(b1, k)
                if (x0 is None) != (x1 is None) or b1.disks != b0.disks:
                    return None
                if x0 is None:
                    continue
                U = (np.asarray(x1) - np.asarray(x0)) / v
                total[k] = total[k] + v * U
                parts[k].append((dofs, np.full(U.shape, j), U, e.name))
        for k in parts:
            x0 = getattr(b0, k)
            if x0 is not None and not np.allclose(total[k], x0, rtol=_LINEAR_TOL, atol=0.0):
                return None
    lin: dict[str, _Linear] = {}
    for k, which in (("mass", "M"), ("stiffness", "K"), ("damping", "C")):
        rows, cols, prm, coef = [], [], [], []
        for dofs, P, U, _ in parts[k]:
            i, jj = np.meshgrid(dofs, dofs, indexing="ij")
            rows.append(g[i].ravel())
            cols.append(g[jj].ravel())
            prm.append(P.ravel())
            coef.append((a[i] * a[jj] * U).ravel())
        lin[which] = _linear(*_cat(rows, cols, prm, coef), (n_red, n_red))
    for k, which in (("load_row", "L"), ("load_rate_row", "L_rate")):
        rows, cols, prm, coef = [], [], [], []
        for dofs, P, U, owner in parts[k]:
            rows.append(np.full(dofs.size, load_row[owner]))
            cols.append(dofs)
            prm.append(P)
            coef.append(U)
        lin[which] = _linear(*_cat(rows, cols, prm, coef), (len(load_row), n_dof))
    names, load_units, _, _ = dt._load_table
    by_field: dict[str, dict[str, int]] = {}
    for (name, field), j in params.items():
        by_field.setdefault(field, {})[name] = j
    items = {e.name: i for i, e in enumerate((*dt.disks, *dt.elements))}
    low = np.array([smallest_positive(u) if rule == "positive" else 0.0 for u, rule in units])
    high = np.array([magnitude_limit(u) for u, _ in units])
    return ValueLayout(
        params,
        tuple(units),
        np.array(base),
        lin["M"],
        lin["K"],
        lin["C"],
        lin["L"],
        lin["L_rate"],
        asm,
        names,
        load_units,
        items,
        tuple(params),
        low,
        high,
        by_field,
        tuple(items[name] for name, _ in params),
    )


def _cat(
    rows: list[np.ndarray], cols: list[np.ndarray], prm: list[np.ndarray], coef: list[np.ndarray]
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    whole = lambda x: np.concatenate(x).astype(np.intp) if x else np.zeros(0, dtype=np.intp)  # noqa: E731
    return whole(rows), whole(cols), whole(prm), np.concatenate(coef) if coef else np.zeros(0)


class _ValueAssembly(Assembly):
    """The assembly of a variant: the base's structure, its own values; M, K, C made when first read."""

    layout: ValueLayout
    values: np.ndarray

    @cached_property
    def M(self) -> sp.csr_array:
        return self.layout.M.csr(self.values)

    @cached_property
    def K(self) -> sp.csr_array:
        return self.layout.K.csr(self.values)

    @cached_property
    def C(self) -> sp.csr_array:
        return self.layout.C.csr(self.values)

    @cached_property
    def stiffness_operator(self) -> sp.csr_array | np.ndarray:
        if self.n > _DENSE_STIFFNESS:
            return self.K
        lin = self.layout.K
        out = np.zeros(lin.shape)
        out[lin.rows, lin.indices] = lin.data(self.values)
        return out

    @property
    def n(self) -> int:
        return self.layout.K.shape[0]


def variant_assembly(dt: DrivetrainLike, layout: ValueLayout, values: np.ndarray) -> Assembly:
    """The assembly of a variant made by :func:`with_values`, on its base's structure (no checks: see
    the module's notes).

    Parameters
    ----------
    dt : Drivetrain
        The variant.
    layout : ValueLayout
        Its base's layout.
    values : ndarray
        Its values, SI, in the layout's order.
    """
    base = layout.asm
    diagonal = None
    if base.mass_diagonal is not None:  # one entry per row of T: TᵀMT stays diagonal
        lin = layout.M
        diagonal = np.zeros(lin.shape[0])
        diagonal[lin.rows] = lin.data(values)
    asm = trusted(
        _ValueAssembly,
        drivetrain=dt,
        T=base.T,
        coordinate_names=base.coordinate_names,
        rigid_body_vectors=base.rigid_body_vectors,
        mass_diagonal=diagonal,
        layout=layout,
        values=values,
    )
    asm.__dict__["rigid_body_unit_shapes"] = base.rigid_body_unit_shapes
    return asm


def variant_loads(layout: ValueLayout, values: np.ndarray) -> Any:
    """The load table (:attr:`Drivetrain._load_table`) of a variant, from its base's layout."""
    L_rate = layout.L_rate.csr(values)
    L_rate.eliminate_zeros()
    return layout.load_names, layout.load_units, layout.L.csr(values), L_rate


def _checked(name: str, field: str, value: Any, unit: str, rule: str) -> float:
    from mechdyn.units import si_field

    return si_field(name, field, value, unit, positive=rule == "positive", nonnegative=rule == "nonnegative")


#: The types taken as plain SI numbers on the fast path (anything else is converted one by one).
_PLAIN = frozenset({float, int, np.float64})


def _on_structure(dt: _Model, layout: ValueLayout, changes: Mapping[str, Any]) -> _Model | None:
    """The variant on ``dt``'s structure when every value given is a plain positive number of a value
    the layout holds; None otherwise (then :func:`with_values` takes the general path, which also
    words the errors). The numbers are checked here, vectorised, against the elements' bounds."""
    at: list[int] = []
    given: list[Any] = []
    for field, values in changes.items():
        positions = layout.by_field.get(field)
        if positions is None or not isinstance(values, dict):
            return None
        try:
            at += [positions[name] for name in values]
        except (KeyError, TypeError):  # not a value of the layout (or a name that is no text)
            return None
        given += values.values()
    if not all(type(v) in _PLAIN for v in given):
        return None
    old = dt.__dict__.get("_values")
    p = (layout.base if old is None else old).copy()
    js = np.array(at, dtype=np.intp)
    vs = np.array(given, dtype=float)
    if not vs.all():
        return None  # a value that vanishes changes the blocks' shape (or is refused): the general path
    ok = (vs >= layout.low[js]) & (vs <= layout.high[js])  # NaN fails both
    if not ok.all():
        i = int(np.argmin(ok))
        (name, field), (unit, rule) = layout.names[js[i]], layout.units[js[i]]
        _checked(name, field, float(vs[i]), unit, rule)  # raises, naming the element, field and range
        raise ModelError(  # pragma: no cover - the elements' bounds and _checked agree
            f"{vs[i]!r} is outside the accepted range", element=name, field=field
        )
    p[js] = vs
    # the disk and element objects are built when first read (Drivetrain.__getattr__, variant_items):
    # the variant's analyses need its structure and values alone
    variant = trusted(
        type(dt),
        name=dt.name,
        provenance=_provenance(dt, _changed_items(layout, at)) if dt.provenance else dt.provenance,
    )
    d = variant.__dict__
    base = dt.__dict__
    for key in _STRUCTURE:
        if key in base:
            d[key] = base[key]
    d["_value_layout"] = layout
    d["_values"] = p
    return variant


def _changed_items(layout: ValueLayout, at: list[int]) -> dict[int, set[str]]:
    """The fields changed per element (by position in ``(*disks, *elements)``), from the values' positions."""
    out: dict[int, set[str]] = {}
    for j in at:
        out.setdefault(layout.item_of[j], set()).add(layout.names[j][1])
    return out


def variant_items(layout: ValueLayout, values: np.ndarray) -> tuple[tuple[Any, ...], tuple[Any, ...]]:
    """The disks and elements of a variant made on ``layout``'s structure: its base model's objects,
    those whose values differ copied with the new values (checked already).

    Parameters
    ----------
    layout : ValueLayout
        The layout of the model the variant's structure comes from.
    values : ndarray
        The variant's values, SI, in the layout's order.

    Returns
    -------
    disks, elements : tuple
        As :attr:`Drivetrain.disks` and :attr:`Drivetrain.elements`.
    """
    root = layout.asm.drivetrain
    items: list[Any] = [*root.disks, *root.elements]
    new: dict[int, dict[str, float]] = {}
    for j in np.flatnonzero(values != layout.base).tolist():
        new.setdefault(layout.item_of[j], {})[layout.names[j][1]] = float(values[j])
    for i, fields in new.items():
        e = items[i]
        copy = object.__new__(type(e))
        d = copy.__dict__
        d.update(e.__dict__)
        d.update(fields)
        items[i] = copy
    n_disks = len(root.disks)
    return tuple(items[:n_disks]), tuple(items[n_disks:])


def _provenance(dt: DrivetrainLike, new: Mapping[int, Any]) -> dict[str, str]:
    """``dt``'s provenance less the entries of the values changed (where they came from no longer holds)."""
    stale = set()
    n_disks = len(dt.disks)
    items = (*dt.disks, *dt.elements)
    for i, fields in new.items():
        name = items[i].name
        if "stiffness" in fields or (i < n_disks and "inertia" in fields):
            stale.add(name)
        if i >= n_disks and "inertia" in fields:
            stale.add(f"{name} (inertia)")
    return {k: v for k, v in dt.provenance.items() if k not in stale}


def with_values(dt: _Model, changes: Mapping[str, Mapping[str, Any]]) -> _Model:
    """The variant of ``dt`` with new values (see :meth:`Drivetrain.with_values`).

    Plain numbers for values the model has go the fast way (:func:`_on_structure`: one vectorised
    check, the structure shared); quantities, a value that appears or vanishes, and every error go
    the general way below, value by value.
    """
    layout: ValueLayout | None = dt._value_layout
    if layout is not None:
        fast_variant = _on_structure(dt, layout, changes)
        if fast_variant is not None:
            return fast_variant
    items: list[Any] = [*dt.disks, *dt.elements]
    index = layout.items if layout is not None else {e.name: i for i, e in enumerate(items)}
    p = dt.__dict__.get("_values", layout.base if layout is not None else None)
    p = None if p is None else p.copy()
    fast = layout is not None
    new: dict[int, dict[str, float]] = {}
    at: list[int] = []  # the layout's positions of the plain numbers given, checked below at once
    for field, values in changes.items():
        if not isinstance(values, Mapping):
            raise ModelError(
                f"give the new {field} values as a mapping of element name → value",
                element=dt.name,
                field=field,
            )
        for name, value in values.items():
            i = index.get(name)
            if i is None:
                raise ModelError(
                    f"with_values names {name!r}, which is not a disk or element of the model",
                    element=dt.name,
                    field="name",
                )
            e = items[i]
            unit_rule = type(e).VALUES.get(field)
            if unit_rule is None:
                own = ", ".join(type(e).VALUES) or "none"
                raise ModelError(
                    f"{type(e).__name__} {name!r} has no value {field!r}; it has: {own}",
                    element=name,
                    field=field,
                )
            j = layout.params.get((name, field)) if layout is not None else None
            if j is not None and isinstance(value, float | int) and not isinstance(value, bool):
                v = float(value)
                at.append(j)
            else:
                v = _checked(name, field, value, *unit_rule)
            if j is None or v == 0:
                fast = False  # a value appears or vanishes: the blocks change shape
            elif p is not None:
                p[j] = v
            new.setdefault(i, {})[field] = v
    if at and p is not None and layout is not None:
        js = np.array(at)
        vs = p[js]
        bad = ~((vs >= layout.low[js]) & (vs <= layout.high[js]))  # NaN fails both
        if bad.any():
            j = int(js[np.argmax(bad)])
            (name, field), (unit, rule) = layout.names[j], layout.units[j]
            _checked(name, field, float(vs[np.argmax(bad)]), unit, rule)  # raises, naming what is accepted
    for i, fields in new.items():
        # on the shared structure the values are checked already; otherwise the element checks itself
        # (a rigid mesh given a stiffness needs its base radii, a divided shaft its inertia)
        e = items[i]
        if fast:
            copy = object.__new__(type(e))
            copy.__dict__.update(e.__dict__)
            copy.__dict__.update(fields)
            items[i] = copy
        else:
            items[i] = dataclasses.replace(e, **fields)
    provenance = _provenance(dt, new) if dt.provenance else dt.provenance
    n_disks = len(dt.disks)
    disks, elements = tuple(items[:n_disks]), tuple(items[n_disks:])
    if not fast:
        return dataclasses.replace(dt, disks=disks, elements=elements, provenance=provenance)
    variant = trusted(type(dt), disks=disks, elements=elements, name=dt.name, provenance=provenance)
    d = variant.__dict__
    for key in _STRUCTURE:
        if key in dt.__dict__:
            d[key] = dt.__dict__[key]
    d["_value_layout"] = layout
    d["_values"] = p
    return variant
