"""The local stage of an optimization: a constrained polish of the best designs, and its proof.

A sampler (Optuna's TPE) finds the region of the optimum; it does not reach the optimum itself,
least of all against an equality held to a tolerance (a stroke to ±1 mm). From the best designs it
found, :func:`polish` runs SciPy's SLSQP (sequential least squares quadratic programming: Kraft,
"A software package for sequential quadratic programming", DFVLR-FB 88-28, 1988) with the study's
constraints as constraints (``equals`` ± ``tolerance`` as two inequalities) and the parameter
ranges as bounds. A synthesis first runs :func:`fit`, a least-squares method for its residuals
(y − target)/tolerance, which gets near the targets in far fewer steps than SLSQP on their sum of
squares.

Gradients are central differences with a step of :data:`STEP` times each parameter's range
(one-sided at a bound): all 2n + 1 variants of one point go to the evaluator as one block, so a
batched analysis (a mechanism's compiled cycle) computes a gradient for about the cost of one
design, and every variant is stored like any other. The analyses are smooth in their parameters and
exact to round-off (~1e-15), so the difference error, O(h²) ≈ 1e-12 relative, is far below what
matters; SciPy's own two-point differences would ask for the points one at a time.

:func:`optimality` proves the answer from the stored variants alone (a run and a stored study give
the same): at the optimum's stencil it finds the active constraints and bounds, solves the
Karush–Kuhn–Tucker conditions ∇F = Σ λⱼ ∇gⱼ (λ ≥ 0) by non-negative least squares (Nocedal &
Wright, *Numerical Optimization*, 2nd ed., 2006, §12.3) and reports the residual as the first-order
optimality measure and each multiplier in the user's units: how much the objective improves per
unit that a limit is relaxed ("1 mm more stroke tolerance is worth 0.8 tonf").

Every answer carries a verdict on that measure (:func:`verdict`): ``"converged"`` where the residual
is at most :data:`FIRST_ORDER` at a design that keeps every constraint, ``"stopped at an iteration
limit"`` where SLSQP ran out of iterations short of it, ``"not converged"`` otherwise. A converged
start is a local optimum only: starts that converge to different values show that the objective has
several, which only the global stage before the polish can tell apart.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from mechdyn.studies.outputs import HOLD_TOLERANCE
from mechdyn.studies.storage import StoredVariant, variant_key

__all__ = [
    "CONVERGED",
    "FIRST_ORDER",
    "ITERATION_LIMIT",
    "MAX_ITERATIONS",
    "NOT_CONVERGED",
    "STEP",
    "fit",
    "optimality",
    "polish",
    "stencil",
    "target_cost",
    "verdict",
]

STEP = 1e-6
"""Finite-difference step, as a fraction of each parameter's range."""

FIRST_ORDER = 1e-4
"""The tolerance on the first-order optimality measure (the relative KKT residual of
:func:`optimality`; the conditions: Nocedal & Wright, 2006, §12.3): at or below it a feasible design
is a first-order point and the search has converged there: what the active limits leave of the
objective's gradient would change it by at most 0.01 % across a whole parameter range. The
gradients are exact to about 1e-9 of F at the finite-difference step (see above), a polish that
converges gets far below (the shipped relocation study: ~1e-16), and a sampler's best design is of
order 0.01 to 1: the tolerance sits well between."""

MAX_ITERATIONS = 100
"""SLSQP iterations per polish start."""

CONVERGED = "converged"
"""The verdict on a design whose first-order measure is at most :data:`FIRST_ORDER`."""
ITERATION_LIMIT = "stopped at an iteration limit"
"""The verdict on a polish start that ran out of iterations short of a first-order point."""
NOT_CONVERGED = "not converged"
"""The verdict on any other design: the measure above :data:`FIRST_ORDER`, not shown (no gradient
stored there), or a design that breaks a constraint."""

_ACTIVE = 1e-6  # a constraint within this fraction of its scale, or a bound within it of the range, is active
_MAX_STARTS = 3


def stencil(x: np.ndarray, low: np.ndarray, high: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The 2n + 1 rows of a central difference at ``x`` (SI): x, then x + hᵢeᵢ, then x − hᵢeᵢ, each
    kept in [low, high] (one-sided at a bound), and the step between each pair.

    Parameters
    ----------
    x, low, high : ndarray
        (n,) the point and the parameter ranges, SI.

    Returns
    -------
    rows : ndarray
        (2n + 1, n).
    width : ndarray
        (n,) the distance between the pair of rows of each parameter.
    """
    h = STEP * (high - low)
    up = np.minimum(x + h, high)
    dn = np.maximum(x - h, low)
    n = x.size
    rows = np.repeat(x[None, :], 2 * n + 1, axis=0)
    rows[1 + np.arange(n), np.arange(n)] = up
    rows[1 + n + np.arange(n), np.arange(n)] = dn
    return rows, up - dn


def _limits(study: Any) -> list[tuple[Any, str, float, float]]:
    """Each constraint side as (constraint, side, limit, scale), side ``"max"`` or ``"min"``
    (:meth:`~mechdyn.studies.outputs.Constraint.sides`): the constraint function is g = limit − y
    (max) or y − limit (min), ≥ 0 where it holds."""
    return [(c, side, limit, scale) for c in study.constraints for side, limit, scale in c.sides()]


def target_cost(study: Any, outputs: Mapping[str, Any]) -> float:
    """A synthesis' cost: Σ ((y − target) / tolerance)² over its targets (inf where one is missing).

    Parameters
    ----------
    study : Study
        Its ``targets`` (``equals`` within ``tolerance``, SI).
    outputs : mapping
        A variant's outputs, SI.
    """
    total = 0.0
    for t in study.targets:
        y = outputs.get(t.output.key)
        if y is None or not math.isfinite(y):
            return math.inf
        total += ((y - t.equals) / t.tolerance) ** 2
    return total


def _values(study: Any, v: StoredVariant) -> tuple[float, np.ndarray]:
    """F (minimised: sign · objective, or a synthesis' target cost) and every g (≥ 0 where the
    constraint holds), SI; NaN where the variant failed."""
    if study.objectives:
        o = study.objectives[0]
        y = v.outputs.get(o.output.key) if v.status == "ok" else None
        f = o.sign * float(y) if y is not None else math.nan
    else:
        f = target_cost(study, v.outputs) if v.status == "ok" else math.nan
        f = f if math.isfinite(f) else math.nan
    g = []
    for c, side, limit, _ in _limits(study):
        value = v.outputs.get(c.output.key) if v.status == "ok" else None
        value = math.nan if value is None else float(value)
        g.append(limit - value if side == "max" else value - limit)
    return f, np.array(g)


def _gradients(
    study: Any, x: np.ndarray, lookup: Callable[[np.ndarray], Sequence[StoredVariant] | None]
) -> tuple[float, np.ndarray, np.ndarray, np.ndarray] | None:
    """F, g and their gradients (SI) at x from its stencil; None when a stencil variant is missing or
    failed."""
    low, high = _range(study)
    rows, width = stencil(x, low, high)
    vs = lookup(rows)
    if vs is None:
        return None
    values = [_values(study, v) for v in vs]
    F = np.array([f for f, _ in values])
    G = np.array([g for _, g in values]).reshape(len(vs), -1)
    if not (np.isfinite(F).all() and np.isfinite(G).all()):
        return None
    n = x.size
    dF = (F[1 : n + 1] - F[n + 1 :]) / width
    dG = (G[1 : n + 1] - G[n + 1 :]) / width[:, None]
    return float(F[0]), G[0], dF, dG.T


def _range(study: Any) -> tuple[np.ndarray, np.ndarray]:
    return (
        np.array([p.low for p in study.parameters], dtype=float),
        np.array([p.high for p in study.parameters], dtype=float),
    )


def verdict(measure: float | None, *, feasible: bool = True, iteration_limit: bool = False) -> str:
    """The verdict on a design's first-order optimality.

    Parameters
    ----------
    measure : float or None
        Its first-order measure (:func:`optimality`'s ``measure``); None where it cannot be shown.
    feasible : bool
        Whether it keeps every constraint (a KKT point must: the residual alone does not say so).
    iteration_limit : bool
        Whether the search that ended there ran out of iterations.

    Returns
    -------
    str
        :data:`CONVERGED` (``measure`` ≤ :data:`FIRST_ORDER` and feasible), :data:`ITERATION_LIMIT`
        or :data:`NOT_CONVERGED`.
    """
    if measure is not None and measure <= FIRST_ORDER and feasible:
        return CONVERGED
    return ITERATION_LIMIT if iteration_limit else NOT_CONVERGED


def polish(
    runner: Any,
    starts: Sequence[np.ndarray],
    *,
    objective: Callable[[dict[str, Any]], float] | None = None,
    max_iterations: int | None = None,
) -> dict[str, Any]:
    """SLSQP from each start (at most three), with the study's constraints and ranges; it minimises
    the study's objective, or a synthesis' target cost (:func:`target_cost`).

    Parameters
    ----------
    runner : Runner
        Evaluates (and stores) blocks of variants: ``runner.evaluate(X, objective)``, X in SI.
    starts : sequence of ndarray
        (n,) parameter rows, SI, best first.
    objective : callable, optional
        What each stored variant keeps as its objective value (as the study's sampler stores it).
    max_iterations : int, optional
        SLSQP iterations per start (default :data:`MAX_ITERATIONS`).

    Returns
    -------
    dict
        ``method``, ``starts`` (how many), ``iterations`` (summed), ``evaluations`` (variants asked
        for, stored ones included), ``messages`` (SLSQP's, one per start) and ``per_start``: where
        each start ended, as ``start`` (the parameters, SI), ``variant`` (the stored id of the end
        point; None where a design on the way failed), ``value`` (the objective there, or a
        synthesis' target cost, SI), ``feasible``, ``measure`` (the first-order measure there,
        :func:`optimality`), ``iterations``, ``message`` and ``verdict`` (:func:`verdict`). Which
        design is the optimum, and whether it converged, the kind's findings say: the best start's
        success says nothing of the others, nor of a better design found elsewhere.
    """
    from scipy.optimize import minimize

    st = runner.study
    low, high = _range(st)
    span = high - low
    limits = _limits(st)
    gscale = np.array([s for *_, s in limits])
    asked = 0

    def at(u: np.ndarray) -> np.ndarray:
        return np.clip(low + np.clip(u, 0.0, 1.0) * span, low, high)

    def lookup(rows: np.ndarray) -> list[StoredVariant]:
        nonlocal asked
        asked += len(rows)
        return runner.evaluate(rows, objective=objective)

    cache: dict[bytes, Any] = {}

    def point(u: np.ndarray) -> tuple[float, np.ndarray]:
        x = at(u)
        return _values(st, lookup(x[None, :])[0])

    def grads(u: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
        key = np.asarray(u, dtype=float).tobytes()
        if key not in cache:
            g = _gradients(st, at(u), lookup)
            if g is None:
                raise FloatingPointError("a variant of the gradient's stencil failed")
            cache[key] = g
        return cache[key]

    def ended(u: np.ndarray) -> tuple[StoredVariant, float | None, bool]:
        """The stored end point, its first-order measure and whether it keeps every constraint
        (its stencil is stored by then: looking it up asks for nothing new)."""
        x = at(u)
        end = runner.evaluate(x[None, :], objective=objective)[0]
        proof = _kkt(st, x, lambda rows: runner.evaluate(rows, objective=objective))
        _, g = _values(st, end)
        slack = HOLD_TOLERANCE * np.array([scale for *_, scale in _limits(st)])  # SLSQP's round-off
        return end, (proof["measure"] if proof is not None else None), bool(np.all(g >= -slack))

    messages: list[str] = []
    per_start: list[dict[str, Any]] = []
    iterations = 0
    limit = MAX_ITERATIONS if max_iterations is None else max_iterations
    for x0 in list(starts)[:_MAX_STARTS]:
        given = {p.name: float(x) for p, x in zip(st.parameters, np.asarray(x0, dtype=float), strict=True)}
        u0 = np.clip((np.asarray(x0, dtype=float) - low) / np.where(span > 0, span, 1.0), 0.0, 1.0)
        f0, _ = point(u0)
        fscale = abs(f0) if math.isfinite(f0) and f0 != 0 else 1.0

        def fun(u: np.ndarray, fscale: float = fscale) -> float:
            f, _ = point(u)
            return f / fscale if math.isfinite(f) else math.inf

        def jac(u: np.ndarray, fscale: float = fscale) -> np.ndarray:
            return grads(u)[2] * span / fscale

        cons = [
            {
                "type": "ineq",
                "fun": lambda u, j=j: point(u)[1][j] / gscale[j],
                "jac": lambda u, j=j: grads(u)[3][j] * span / gscale[j],
            }
            for j in range(len(limits))
        ]
        try:
            res = minimize(
                fun,
                u0,
                jac=jac,
                bounds=[(0.0, 1.0)] * len(u0),
                constraints=cons,
                method="SLSQP",
                options={"maxiter": limit, "ftol": 1e-12},
            )
        except FloatingPointError as exc:  # a design on the way failed: keep what was found
            messages.append(str(exc))
            per_start.append(
                {
                    "start": given,
                    "variant": None,
                    "value": None,
                    "feasible": False,
                    "measure": None,
                    "iterations": None,
                    "message": str(exc),
                    "verdict": NOT_CONVERGED,
                }
            )
            continue
        iterations += int(res.nit)
        messages.append(str(res.message))
        try:
            grads(res.x)  # the end point's stencil, for optimality() (stored, usually already)
        except FloatingPointError:
            pass  # its measure is then not shown, and the start not converged
        end, measure, keeps = ended(res.x)
        y = end.objective
        per_start.append(
            {
                "start": given,
                "variant": end.id,
                "value": y if y is not None and math.isfinite(y) else None,
                "feasible": keeps,
                "measure": measure,
                "iterations": int(res.nit),
                "message": str(res.message),
                # SciPy's SLSQP: status 9 is "Iteration limit reached"; its own success is not the
                # verdict (it stops when F changes by less than ftol, which says nothing of ∇F)
                "verdict": verdict(measure, feasible=keeps, iteration_limit=int(res.status) == 9),
            }
        )
    return {
        "method": "SLSQP",
        "starts": min(len(starts), _MAX_STARTS),
        "iterations": iterations,
        "evaluations": asked,
        "messages": messages,
        "per_start": per_start,
    }


def _one_unit_in_si(unit: str, display: str) -> float:
    """The size of one display unit in SI (1 mm → 0.001 m)."""
    if not display or display == unit:
        return 1.0
    from mechdyn.units import convert

    return float(convert(1.0, display, unit))


def optimality(study: Any, best: StoredVariant, stored: Mapping[str, StoredVariant]) -> dict[str, Any] | None:
    """The first-order optimality of ``best``, from its stencil among the stored variants.

    Parameters
    ----------
    study : Study
        One objective; its constraints and parameter ranges.
    best : StoredVariant
        The optimum.
    stored : mapping of variant key → StoredVariant
        The study's variants.

    Returns
    -------
    dict or None
        None when the stencil is not stored (no polish ran there). Otherwise ``measure``: the
        Karush–Kuhn–Tucker residual ‖∇F − Σ λ ∇g‖∞, gradients per parameter range, over the
        largest of |F|, ‖∇F‖∞ and (a synthesis' cost, in tolerances squared) 1: the first-order
        change of F across a whole range that no active limit explains, relative to F (0 at an
        exact first-order point, interior or held by limits; a sampler's best design is of order
        0.01 to 1); ``active``: one
        entry per active constraint side or bound with ``name``, ``kind`` (``"constraint"`` or
        ``"bound"``), ``worth`` (the objective's improvement, in its display unit, per ``per``) and
        ``per`` (one display unit of the limit, e.g. ``"1 mm"``); ``unit`` (the objective's display
        unit); ``tolerance`` (:data:`FIRST_ORDER`, what :func:`verdict` holds ``measure`` to).
    """
    if not (study.objectives or study.targets):
        return None
    x = np.array([best.parameters[p.name] for p in study.parameters], dtype=float)

    def lookup(rows: np.ndarray) -> list[StoredVariant] | None:
        out = [stored.get(variant_key(r.tolist())) for r in rows]
        return None if any(v is None for v in out) else out  # type: ignore[return-value]

    return _kkt(study, x, lookup)


def _kkt(
    study: Any, x: np.ndarray, lookup: Callable[[np.ndarray], Sequence[StoredVariant] | None]
) -> dict[str, Any] | None:
    """:func:`optimality` at ``x`` (SI), its stencil's variants from ``lookup``."""
    from scipy.optimize import nnls

    found = _gradients(study, x, lookup)
    if found is None:
        return None
    F, g, dF, dG = found
    low, high = _range(study)
    span = np.where(high > low, high - low, 1.0)
    limits = _limits(study)
    columns: list[np.ndarray] = []
    entries: list[dict[str, Any]] = []
    for j, (c, side, _, scale) in enumerate(limits):
        if g[j] <= _ACTIVE * scale:
            columns.append(dG[j] * span)
            o = c.output
            per = _one_unit_in_si(o.unit, o.display)
            label = "upper" if side == "max" else "lower"
            entries.append(
                {
                    "name": f"{c.describe()} ({label} limit)" if c.equals is not None else c.describe(),
                    "kind": "constraint",
                    "scale": 1.0,
                    "si_per": per,
                    "per": f"1 {o.display or o.unit}".strip(),
                }
            )
    for i, p in enumerate(study.parameters):
        for side, at_bound, sign in (("lower", x[i] - low[i], 1.0), ("upper", high[i] - x[i], -1.0)):
            if at_bound <= _ACTIVE * span[i]:
                e = np.zeros(x.size)
                e[i] = sign  # the bound u ≥ 0 or 1 − u ≥ 0 in the range's fraction u
                columns.append(e)
                entries.append(
                    {
                        "name": f"{p.name} at its {side} bound",
                        "kind": "bound",
                        "scale": 1.0 / span[i],
                        "si_per": p.factor,
                        "per": f"1 {p.unit}".strip() if p.unit else "1",
                    }
                )
    gF = dF * span
    if columns:
        A = np.array(columns).T
        lam, _ = nnls(A, gF)
        residual = gF - A @ lam
    else:
        lam, residual = np.zeros(0), gF
    # the scale of the residual: F itself, not ‖∇F‖ alone, which vanishes with the residual at an
    # interior optimum (the ratio is then 1 at any point short of it and at it alike); ‖∇F‖ where F
    # is near zero, and 1 for a synthesis' cost (in tolerances squared: below 1 the targets are met)
    norm = max(abs(F), float(np.abs(gF).max()), 0.0 if study.objectives else 1.0)
    o = study.objectives[0].output if study.objectives else None
    active = []
    for k, entry in enumerate(entries):
        # λ: F per SI unit of a constraint's g, or per range fraction of a bound; then per display unit
        worth_si = lam[k] * entry["scale"] * entry["si_per"]
        active.append(
            {
                "name": entry["name"],
                "kind": entry["kind"],
                # a synthesis' cost has no unit a designer reads: only what holds the fit is told
                "worth": o.difference(worth_si) if o is not None else None,
                "per": entry["per"],
            }
        )
    return {
        "measure": float(np.abs(residual).max() / norm) if norm > 0 else 0.0,
        "tolerance": FIRST_ORDER,
        "active": active,
        "unit": (o.display or o.unit) if o is not None else "",
    }


_SQRT_PENALTY = 30.0  # weight of a constraint's scaled violation among a synthesis' residuals


def _residuals(study: Any, v: StoredVariant) -> np.ndarray:
    """A synthesis' residuals: (y − target) / tolerance per target, then √penalty · violation / scale
    per constraint side (0 where it holds); NaN where the variant failed."""
    out = []
    for t in study.targets:
        y = v.outputs.get(t.output.key) if v.status == "ok" else None
        out.append((float(y) - t.equals) / t.tolerance if y is not None else math.nan)
    _, g = _values(study, v)
    scale = np.array([s for *_, s in _limits(study)])
    return np.concatenate([np.array(out), _SQRT_PENALTY * np.maximum(0.0, -g / scale)])


def fit(
    runner: Any,
    start: np.ndarray,
    *,
    objective: Callable[[dict[str, Any]], float] | None = None,
    max_evaluations: int = 100,
) -> dict[str, Any]:
    """A synthesis' least-squares fit from ``start``: the trust-region reflective method
    (:func:`scipy.optimize.least_squares`, ``method="trf"``; Branch, Coleman & Li, *SIAM J. Sci.
    Comput.* 21, 1999) on the residuals (y − target) / tolerance, the ranges as bounds and each
    constraint's violation as a penalty residual. It is Gauss–Newton where the residuals are small,
    so it reaches a fit far faster than a quasi-Newton method on their sum of squares; the constrained
    polish (:func:`polish`) then proves the fit with the constraints as constraints. The Jacobian is
    the central-difference stencil (:func:`stencil`), evaluated as one block.

    Parameters
    ----------
    runner : Runner
        Evaluates (and stores) blocks of variants.
    start : ndarray
        (n,) the first point, SI.
    objective : callable, optional
        What each stored variant keeps as its objective value.
    max_evaluations : int
        Residual evaluations (each Jacobian is one more block).

    Returns
    -------
    dict
        ``x`` (the end point, SI), ``cost`` (Σ residual²), ``message`` and ``evaluations``
        (variants asked for, stored ones included).
    """
    from scipy.optimize import least_squares

    st = runner.study
    low, high = _range(st)
    span = np.where(high > low, high - low, 1.0)
    asked = 0

    def at(u: np.ndarray) -> np.ndarray:
        return np.clip(low + u * span, low, high)

    def lookup(rows: np.ndarray) -> list[StoredVariant]:
        nonlocal asked
        asked += len(rows)
        return runner.evaluate(rows, objective=objective)

    def fun(u: np.ndarray) -> np.ndarray:
        r = _residuals(st, lookup(at(u)[None, :])[0])
        return np.where(np.isfinite(r), r, 1e6)  # a failed design: far from every target

    def jac(u: np.ndarray) -> np.ndarray:
        x = at(u)
        rows, width = stencil(x, low, high)
        R = np.array([_residuals(st, v) for v in lookup(rows)])
        n = x.size
        J = (R[1 : n + 1] - R[n + 1 :]) / width[:, None] * span[:, None]
        return np.where(np.isfinite(J), J, 0.0).T

    u0 = np.clip((np.asarray(start, dtype=float) - low) / span, 0.0, 1.0)
    res = least_squares(
        fun, u0, jac=jac, bounds=(0.0, 1.0), method="trf", x_scale="jac", max_nfev=max_evaluations
    )
    return {"x": at(res.x), "cost": float(2.0 * res.cost), "message": str(res.message), "evaluations": asked}
