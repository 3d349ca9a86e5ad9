"""Many variant models of one mechanism in one batched evaluation (:func:`variants`): the models'
differences in points, masses and inertias become the arrays of one compiled
:func:`~mechdyn.mechanism.dyads.cycle`; any other mechanism runs design by design on the general engine
(:class:`DesignBatch`, one :class:`~mechdyn.mechanism.DynamicsResult` per variant).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.mechanism.dyads import CycleBatch, NotDecomposable, cycle, plan
from mechdyn.mechanism.dynamics import inverse_dynamics
from mechdyn.mechanism.model import Mechanism
from mechdyn.mechanism.revolution import check_angles
from mechdyn.results import Result

__all__ = ["DesignBatch", "variants"]


@dataclass(frozen=True, repr=False)  # the short repr of Result
class DesignBatch(Result):
    """Variants run design by design on the general engine: one result per variant, with its status.

    Attributes
    ----------
    results : tuple of DynamicsResult or None
        None for a variant that could not be computed.
    status : tuple of str
        ``"ok"``, or the error that stopped the variant.
    """

    results: tuple[Any, ...]
    status: tuple[str, ...]

    @classmethod
    def run(cls, models: Sequence[Mechanism], n_angles: int, method: Any = "auto") -> DesignBatch:
        """Each model's :func:`~mechdyn.mechanism.inverse_dynamics` with the motion solver
        ``method``; an error is kept, not raised.

        Parameters
        ----------
        models : sequence of Mechanism
            Variants of one topology.
        n_angles : int
            Crank positions over one revolution, a whole number from 4 to 100 000.
        method : str or callable
            The motion solver (see :func:`~mechdyn.mechanism.inverse_dynamics`)."""
        n_angles = check_angles(n_angles)
        results: list[Any] = []
        status: list[str] = []
        for i, m in enumerate(models):
            try:
                results.append(inverse_dynamics(m, n_angles, method))
                status.append("ok")
            except ModelError as exc:
                results.append(None)
                status.append(f"variant {i}: {exc.detail}")
        return cls(tuple(results), tuple(status))

    @property
    def assembled(self) -> np.ndarray:
        """(V,) True for the variants that were computed."""
        return np.array([r is not None for r in self.results])

    def summary(self) -> dict[str, Any]:
        """Per variant (arrays over V, NaN for a failed one): the scalar figures of each design's
        :meth:`DynamicsResult.summary`, and the joint-force peaks."""
        rows = [r.summary() if r is not None else None for r in self.results]
        done = [row for row in rows if row is not None]
        if not done:
            return {}
        keys = [k for k, v in done[0].items() if isinstance(v, (int, float)) and not isinstance(v, bool)]
        out: dict[str, Any] = {
            k: np.array([row.get(k, np.nan) if row is not None else np.nan for row in rows], dtype=float)
            for k in keys
        }
        joints = list(done[0]["joint_force_peak_N"])
        out["joint_force_peak_N"] = {
            j: np.array([row["joint_force_peak_N"][j] if row is not None else np.nan for row in rows])
            for j in joints
        }
        return out

    def to_frame(self) -> Any:
        """One row per variant: its status and its figures."""
        import pandas as pd

        cols: dict[str, Any] = {"variant": np.arange(len(self.results)), "status": list(self.status)}
        for key, value in self.summary().items():
            if isinstance(value, dict):
                cols |= {f"joint_{name}_force_peak_N": v for name, v in value.items()}
            else:
                cols[key] = value
        return pd.DataFrame(cols)


def variants(
    models: Sequence[Mechanism], n_angles: int = 360, *, store_points: bool = True, method: Any = "auto"
) -> CycleBatch | DesignBatch:
    """Many variant models of one mechanism in one batched evaluation; variant i of the result is
    the single-design result of ``models[i]``.

    Parameters
    ----------
    models : sequence of Mechanism
        Variants of one topology: they may differ in their drawing's point coordinates, their bodies'
        masses and inertias (and their names), nothing else.
    n_angles : int
        Crank angles per revolution, a whole number from 4 to 100 000.
    store_points : bool
        Keep the motions (and with them every joint force); see :func:`~mechdyn.mechanism.cycle`.
    method : {"auto", "dyads", "newton"} or callable
        The motion solver, as for :func:`~mechdyn.mechanism.kinematics`: ``"auto"`` and ``"dyads"``
        run one compiled batch where the mechanism decomposes; ``"newton"`` or a callable
        ``(mechanism, n_angles) -> KinematicsResult`` run design by design.

    Returns
    -------
    CycleBatch or DesignBatch
        One variant per model, in order, each with its ``status`` (``"ok"`` or why it was not
        computed: the angle, the loop and the joint); the others are computed. A crank with RRR/RRP
        dyads runs as one compiled batch (:class:`CycleBatch`); any other mechanism (gear trains,
        sliders on moving guides) runs design by design on the general engine
        (:class:`DesignBatch`, with the same summary keys).

    Raises
    ------
    ModelError
        When a model differs from the first in more than points, masses and inertias (naming the
        variant and what differs).
    """
    if not models:
        raise ModelError("give at least one model", element="variants")
    n_angles = check_angles(n_angles)
    base = models[0]
    for i, m in enumerate(models[1:], start=1):
        _same_topology(base, m, i)
    if method not in ("auto", "dyads"):
        return DesignBatch.run(models, n_angles, method)
    try:
        plan(base)
    except NotDecomposable:
        if method == "dyads":
            raise
        return DesignBatch.run(models, n_angles)
    changed = [p for p in base.points if any(m.points[p] != base.points[p] for m in models)]
    points = {p: np.array([m.points[p] for m in models]) for p in changed}
    masses, inertias = {}, {}
    for k, b in enumerate(base.bodies):
        if any(m.bodies[k].mass != b.mass for m in models):
            masses[b.name] = np.array([m.bodies[k].mass for m in models])
        # each model's own inertia, also where only the mass changes (cycle() would scale it)
        if b.name in masses or any(m.bodies[k].inertia != b.inertia for m in models):
            inertias[b.name] = np.array([m.bodies[k].inertia for m in models])
    if len(models) > 1 and not (points or masses or inertias):  # identical variants: still one each
        points = {p: np.array([base.points[p]] * len(models)) for p in list(base.points)[:1]}
    return cycle(
        base,
        n_angles,
        points,
        masses,
        inertias=inertias,
        store_points=store_points,
        errors="nan",
    )


def _same_topology(base: Mechanism, m: Mechanism, i: int) -> None:
    """Refuse a variant that differs from the first in more than points, masses and inertias."""

    def differs(what: str) -> None:
        raise ModelError(
            f"variant {i} differs from variant 0 in its {what}; a batch holds variants of one "
            "topology that differ in points, masses and inertias; run the others one by one",
            element="variants",
        )

    if set(m.points) != set(base.points):
        differs("point names")
    if len(m.bodies) != len(base.bodies):
        differs("bodies")
    for a, b in zip(m.bodies, base.bodies, strict=True):
        if (a.name, a.points, a.center_of_mass) != (b.name, b.points, b.center_of_mass):
            differs(f"body {b.name!r} (its name, points or centre of mass)")
    for what in ("joints", "driver", "gravity", "process_forces", "output", "angle_datum"):
        if getattr(m, what) != getattr(base, what):
            differs(what.replace("_", " "))
