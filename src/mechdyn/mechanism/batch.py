"""Design studies' batch evaluation of a mechanism: variants given as columns of model-file values.

A design study names model values by their place in the file (:mod:`mechdyn.studies.paths`); those
that the batched engine varies directly — a point's coordinates (``points.C``), a body's mass or
inertia (``bodies.slide.mass``) — go into one :func:`mechdyn.mechanism.cycle` call for all variants.
Any other value (a driver speed, a centre of mass written as coordinates) is not batched:
:class:`~mechdyn.registry.NotBatchable` sends the study to the one-by-one path, which gives the same
numbers.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from mechdyn.registry import NotBatchable, summary_columns  # noqa: F401 - where callers find it

__all__ = ["cycle_columns"]


def cycle_columns(
    mechanism: Any,
    columns: Mapping[tuple[str | int, ...], np.ndarray],
    n_angles: int,
    n_variants: int | None = None,
    *,
    summary_only: bool = False,
) -> Any:
    """One :func:`~mechdyn.mechanism.cycle` over the variants that ``columns`` describe.

    Parameters
    ----------
    mechanism : Mechanism
        The base model (as its file builds it).
    columns : mapping of keys → ndarray (V,)
        Keys into the mechanism file (``("points", "C", 0)``, ``("bodies", 4, "mass")``) and the
        SI value of each variant.
    n_angles : int
        Crank angles per revolution.
    n_variants : int, optional
        V (default: the length of the columns); the base design V times when no column is given.
    summary_only : bool
        Keep each variant's scalar figures alone (:func:`~mechdyn.mechanism.dyads.cycle_summary`:
        chunks of variants through reused work buffers, a few hundred bytes per variant), not its
        curves; the figures are the same.

    Returns
    -------
    CycleBatch or CycleSummary
        Motions not kept (``store_points=False``), or the figures alone (``summary_only``); a
        variant that cannot be assembled is NaN with its reason in ``failures``.

    Raises
    ------
    NotBatchable
        For a value the batch does not vary, or a mechanism the compiled batch does not run.
    """
    from mechdyn.mechanism.dyads import NotDecomposable, cycle, cycle_summary, plan

    try:
        plan(mechanism)
    except NotDecomposable as exc:
        raise NotBatchable(str(exc)) from None
    V = n_variants or max((np.asarray(v).size for v in columns.values()), default=1)
    points: dict[str, np.ndarray] = {}
    masses: dict[str, np.ndarray] = {}
    inertias: dict[str, np.ndarray] = {}
    bodies = mechanism.bodies
    for keys, values in columns.items():
        v = np.broadcast_to(np.asarray(values, dtype=float), (V,))
        match keys:
            case ("points", str(name), int(i)) if name in mechanism.points and i in (0, 1):
                xy = points.setdefault(name, np.tile(np.asarray(mechanism.points[name], float), (V, 1)))
                xy[:, i] = v
            case ("bodies", int(k), "mass") if 0 <= k < len(bodies):
                masses[bodies[k].name] = v
            case ("bodies", int(k), "inertia") if 0 <= k < len(bodies):
                inertias[bodies[k].name] = v
            case _:
                raise NotBatchable(f"the batch does not vary {'.'.join(map(str, keys))}")
    for name in masses:  # a mass given alone scales the inertia in cycle(); the file keeps it
        k = mechanism.body_index[name]
        inertias.setdefault(name, np.full(V, bodies[k].inertia))
    if not (points or masses or inertias):
        first = next(iter(mechanism.points))
        points[first] = np.tile(np.asarray(mechanism.points[first], float), (V, 1))
    if summary_only:
        return cycle_summary(mechanism, n_angles, points, masses, inertias=inertias)
    return cycle(mechanism, n_angles, points, masses, inertias=inertias, store_points=False, errors="nan")
