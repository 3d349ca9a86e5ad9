"""The figures of a study's page, worked out on the server from every stored variant and sent to the
browser small: the optimization history with the best so far, the Pareto front of two outputs, and
the parameters' importances. The slice, contour and parallel-coordinates views are drawn by Plotly in
the browser from the page's sample of variants.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["best_so_far", "history", "importances", "pareto_mask", "thin"]

HISTORY_POINTS = 2_000
"""Variants drawn at most in the history's cloud (the best-so-far line keeps every step): an SVG cloud
that draws in a fraction of a second in a browser without a graphics card."""


def best_so_far(values: np.ndarray, sense: str = "minimize") -> np.ndarray:
    """The best value found up to each variant, NaN until the first finite one.

    Parameters
    ----------
    values : ndarray
        The objective (any unit) in the order the variants were evaluated; NaN for a failed one.
    sense : {"minimize", "maximize"}
        Which way is better.
    """
    v = np.asarray(values, dtype=float)
    sign = -1.0 if sense == "maximize" else 1.0
    filled = np.where(np.isfinite(v), sign * v, np.inf)
    best = np.minimum.accumulate(filled) if v.size else filled
    return np.where(np.isfinite(best), sign * best, np.nan)


def thin(n: int, limit: int) -> np.ndarray:
    """Indices of at most ``limit`` of ``n`` items, evenly spread, the first and last kept."""
    if n <= limit:
        return np.arange(n)
    return np.unique(np.linspace(0, n - 1, limit).round().astype(int))


def history(ids: np.ndarray, values: np.ndarray, sense: str) -> dict[str, Any]:
    """The optimization history: every variant's value (thinned to :data:`HISTORY_POINTS`) against
    its place in the study, and the best so far at each step where it changed (exact, from every
    variant).

    Parameters
    ----------
    ids : ndarray of int
        Variant ids, in the order evaluated.
    values : ndarray
        Their objective, in its shown unit (NaN for a missing one).
    sense : {"minimize", "maximize"}

    Returns
    -------
    dict
        ``x``, ``y``, ``ids`` of the cloud; ``best_x``, ``best_y`` of the best-so-far steps; ``best``
        (the best value) and ``best_id``.
    """
    values = np.asarray(values, dtype=float)
    n = values.size
    keep = thin(n, HISTORY_POINTS)
    best = best_so_far(values, sense)
    changed = np.flatnonzero(np.isfinite(best) & ~(np.r_[np.nan, best[:-1]] == best))
    steps = np.r_[changed, n - 1] if n and changed.size else changed
    finite = np.isfinite(values)
    if finite.any():
        i = int(np.nanargmax(values) if sense == "maximize" else np.nanargmin(values))
        best_value, best_id = float(values[i]), int(ids[i])
    else:
        best_value, best_id = None, None

    def listed(a: np.ndarray) -> list[float | None]:
        return [None if not np.isfinite(x) else float(x) for x in a]

    return {
        "x": (keep + 1).tolist(),
        "y": listed(values[keep]),
        "ids": np.asarray(ids)[keep].tolist(),
        "best_x": (steps + 1).tolist(),
        "best_y": listed(best[steps]),
        "best": best_value,
        "best_id": best_id,
        "sense": sense,
    }


def pareto_mask(
    x: np.ndarray, y: np.ndarray, senses: tuple[str, str] = ("minimize", "minimize")
) -> np.ndarray:
    """Which points are on the Pareto front of two objectives (none better in both, at least as good
    in one): O(n log n), by sorting on the first and keeping each point that improves on the second.

    Parameters
    ----------
    x, y : ndarray
        The two objectives (NaN: not a candidate).
    senses : (str, str)
        ``"minimize"`` or ``"maximize"`` for each.

    Returns
    -------
    ndarray of bool
    """
    a = np.asarray(x, dtype=float) * (-1.0 if senses[0] == "maximize" else 1.0)
    b = np.asarray(y, dtype=float) * (-1.0 if senses[1] == "maximize" else 1.0)
    ok = np.flatnonzero(np.isfinite(a) & np.isfinite(b))
    mask = np.zeros(a.size, dtype=bool)
    if not ok.size:
        return mask
    order = ok[np.lexsort((b[ok], a[ok]))]  # by the first, ties by the second
    best = np.inf
    for i in order:
        if b[i] < best:
            mask[i] = True
            best = b[i]
    return mask


def importances(
    parameters: dict[str, np.ndarray], output: np.ndarray, *, sample: int = 2_000, seed: int = 0
) -> dict[str, Any]:
    """How much each parameter matters to an output, by Optuna's PED-ANOVA evaluator (Watanabe et al.,
    IJCAI 2023: how differently the parameter is distributed among the best tenth of the variants
    than among all), on an evenly spread sample.

    Parameters
    ----------
    parameters : dict of str to ndarray
        Each parameter's values (any unit; a choice by its index).
    output : ndarray
        The output (smaller is taken as better; NaN for a failed variant).
    sample : int
        Variants used at most.
    seed : int
        Seed of the evaluator.

    Returns
    -------
    dict
        ``method`` (in words) and ``values`` (parameter → importance, summing to one).
    """
    import optuna
    from optuna.distributions import FloatDistribution
    from optuna.importance import PedAnovaImportanceEvaluator, get_param_importances

    y = np.asarray(output, dtype=float)
    keep = thin(y.size, sample)
    keep = keep[np.isfinite(y[keep])]
    names = [n for n, v in parameters.items() if np.ptp(np.asarray(v, dtype=float)[keep]) > 0]
    method = "Optuna PED-ANOVA (the best tenth of the variants against all)"
    if len(keep) < 10 or not names:
        return {"method": method, "values": {}}
    distributions: dict[str, Any] = {
        n: FloatDistribution(float(np.min(parameters[n][keep])), float(np.max(parameters[n][keep])))
        for n in names
    }
    trials = [
        optuna.trial.create_trial(
            params={n: float(parameters[n][i]) for n in names}, distributions=distributions, value=float(y[i])
        )
        for i in keep
    ]
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(direction="minimize")
    study.add_trials(trials)
    found = get_param_importances(study, evaluator=PedAnovaImportanceEvaluator(), normalize=True)
    return {"method": method, "values": {k: float(v) for k, v in found.items()}}
