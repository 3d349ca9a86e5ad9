"""Drivetrains built from arrays: a long chain without a Python step per element.

:meth:`Drivetrain.chain` takes the inertias, stiffnesses and damping as arrays (plain SI numbers, a
pint quantity array, or quantities one by one), converts and checks them once, vectorised, and
builds the model's disks and shafts and everything the analyses derive from them (names and indices,
the element blocks stacked by size, the rigid-body branch, the load rows) as arrays, with no walk over
the elements. The result is the same :class:`~mechdyn.drivetrain.Drivetrain` the element lists give,
equal to it and analysed the same way.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any, TypeVar

import numpy as np

from mechdyn.checks import check_array
from mechdyn.drivetrain.structure import BlockGroup
from mechdyn.errors import ModelError

__all__ = ["chain", "si_array", "trusted"]


def si_array(
    owner: str,
    field: str,
    values: Any,
    unit: str,
    *,
    size: int | None = None,
    positive: bool = False,
    nonnegative: bool = False,
) -> np.ndarray:
    """A 1-D array of quantities in ``unit`` (SI), converted once and checked entry by entry.

    Parameters
    ----------
    owner : str
        The model or element, for messages.
    field : str
        The parameter's name, for messages.
    values : array_like, pint.Quantity or sequence of quantities
        Plain numbers (taken as SI, the Python API's contract), a pint quantity array of any unit of
        the right dimension, or quantities one by one (``"4e-3 kg*m^2"``).
    unit : str
        The SI unit wanted, e.g. ``"kg*m^2"``.
    size : int, optional
        The number of entries required.
    positive, nonnegative : bool
        Every entry positive (and at least the smallest positive magnitude of the unit) / not negative.

    Returns
    -------
    ndarray
        (size,) float, in ``unit``; finite and within the magnitude limit of the unit
        (:data:`mechdyn.checks.MAGNITUDE_LIMITS`).

    Raises
    ------
    mechdyn.errors.ModelError
        Naming the parameter, the first bad entry and what is accepted.
    """
    from mechdyn.units import UnitError, registry, to_si

    quantity = lambda v: hasattr(v, "units") and hasattr(v, "magnitude")  # noqa: E731 - pint, unimported
    if quantity(values):
        import pint

        try:
            q = registry().Quantity(np.asarray(values.magnitude, dtype=float), str(values.units))
            values = np.asarray(q.to(unit).magnitude, dtype=float)
        except (pint.errors.PintError, ValueError, TypeError) as exc:
            raise ModelError(f"{field}: {exc}; give {unit}", element=owner, field=field) from None
    elif not isinstance(values, np.ndarray) and any(
        isinstance(v, str) or quantity(v) for v in np.asarray(values, dtype=object).ravel()
    ):
        try:
            values = [to_si(v, unit, plain_is_si=True) for v in values]
        except UnitError as exc:
            raise ModelError(str(exc), element=owner, field=field) from None
    a = check_array(owner, field, values, unit, positive=positive, nonnegative=nonnegative)
    if a.ndim != 1 or (size is not None and a.size != size):
        want = f"{size} values" if size is not None else "a 1-D list of values"
        raise ModelError(f"{field} has shape {a.shape}; give {want}", element=owner, field=field)
    return a


def trusted(cls: type, **fields: Any) -> Any:
    """An instance of the frozen dataclass ``cls`` with these fields, its checks skipped: for values
    checked already, vectorised (every field must be given)."""
    obj: Any = object.__new__(cls)
    obj.__dict__.update(fields)
    return obj


def _names(owner: str, field: str, given: Sequence[str] | None, prefix: str, count: int) -> list[str]:
    if given is None:
        return [f"{prefix}{i}" for i in range(count)]
    if isinstance(given, str) or len(given) != count:
        raise ModelError(f"give {count} names", element=owner, field=field)
    out = []
    for name in given:
        if not isinstance(name, str) or not name.strip():
            raise ModelError(f"name {name!r} must be a non-empty text", element=owner, field=field)
        out.append(name.strip())
    return out


_Model = TypeVar("_Model")


def chain(
    model: type[_Model],
    inertias: Any,
    stiffnesses: Any,
    *,
    damping: Any = None,
    name: str = "drivetrain",
    disk_names: Sequence[str] | None = None,
    shaft_names: Sequence[str] | None = None,
) -> _Model:
    """A chain of disks joined by shafts, built from arrays (see :meth:`Drivetrain.chain`).

    Parameters
    ----------
    model : type
        The model class to build, :class:`~mechdyn.drivetrain.Drivetrain` (its checks skipped: the
        values are checked here, vectorised).
    inertias, stiffnesses, damping, name, disk_names, shaft_names
        As :meth:`Drivetrain.chain` takes them (kg·m², N·m/rad, N·m·s/rad).

    Returns
    -------
    Drivetrain
        The chain, with what the analyses derive from its elements made as arrays.
    """
    from mechdyn.drivetrain.elements import Disk, Shaft

    J = si_array(name, "inertias", inertias, "kg*m^2", positive=True)
    n = J.size
    if n == 0:
        raise ModelError("a drivetrain needs at least one disk", element=name, field="inertias")
    k = si_array(name, "stiffnesses", stiffnesses, "N*m/rad", size=n - 1, positive=True)
    c = (
        np.zeros(n - 1)
        if damping is None
        else si_array(name, "damping", damping, "N*m*s/rad", size=n - 1, nonnegative=True)
    )
    disk_list = _names(name, "disk_names", disk_names, "d", n)
    shaft_list = _names(name, "shaft_names", shaft_names, "s", n - 1)
    if len(set(disk_list).union(shaft_list)) != 2 * n - 1:
        seen: set[str] = set()
        for x in (*disk_list, *shaft_list):
            if x in seen:
                raise ModelError(
                    "the name is used twice; give every disk and element its own name",
                    element=x,
                    field="name",
                )
            seen.add(x)
    Jl, kl, cl = J.tolist(), k.tolist(), c.tolist()
    disks = tuple(trusted(Disk, name=d, inertia=j) for d, j in zip(disk_list, Jl, strict=True))
    ends = list(itertools.pairwise(disk_list))
    shafts = tuple(
        trusted(
            Shaft,
            name=s,
            disks=ab,
            stiffness=kk,
            damping=cc,
            inertia=0.0,
            mass_model="consistent",
            elements=1,
        )
        for s, ab, kk, cc in zip(shaft_list, ends, kl, cl, strict=True)
    )
    dt = trusted(model, disks=disks, elements=shafts, name=name, provenance={})
    # what the analyses derive from the elements, as arrays: the same values the element walk gives
    index = {d: i for i, d in enumerate(disk_list)}
    at = np.arange(n, dtype=np.intp)
    pairs = np.column_stack([at[:-1], at[1:]])
    unit = np.array([[1.0, -1.0], [-1.0, 1.0]])
    damped = np.flatnonzero(c)
    groups = {
        "mass": (BlockGroup(at.copy(), at[:, None].copy(), J[:, None, None].copy()),),
        "stiffness": (BlockGroup(n + at[:-1], pairs, k[:, None, None] * unit),) if n > 1 else (),
        "damping": (BlockGroup(n + damped, pairs[damped], c[damped, None, None] * unit),)
        if damped.size
        else (),
    }
    import scipy.sparse as sp

    rows = np.repeat(np.arange(n - 1), 2)
    cols = pairs.ravel()
    L = sp.csr_array((np.column_stack([-k, k]).ravel(), (rows, cols)), shape=(n - 1, n))
    L_rate = sp.csr_array((np.column_stack([-c, c]).ravel(), (rows, cols)), shape=(n - 1, n))
    L_rate.eliminate_zeros()
    dt.__dict__.update(
        disk_names=tuple(disk_list),
        disk_index=index,
        dof_names=tuple(disk_list),
        dof_index=index,
        _block_groups=groups,
        _components=(np.zeros(n, dtype=np.int64), np.ones(n), [None]),
        _grounded_dofs=np.zeros(0, dtype=np.intp),
        _constraints=(),
        _load_table=(tuple(shaft_list), ("N*m",) * (n - 1), L, L_rate),
    )
    return dt
