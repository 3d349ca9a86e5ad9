"""What a counterweight design is judged by: the fluctuation of the shaking force, the shaking moment,
the driving torque and the floor force, each as an RMS, a peak or a range.

Every quantity is judged by its *fluctuating* part, its deviation from its mean over the cycle: the
mean (the weight of the moving parts, the mean torque that does the work) does not shake the frame.

- ``rms``: √(mean over the cycle of |q − q̄|²) (all components of a vector together);
- ``peak``: the largest |q − q̄| over the cycle;
- ``range``: the largest over the components of (max − min) over the cycle (for the driving torque:
  its fluctuation, max − min, as :mod:`mechdyn.mechanism` reports it).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from mechdyn.errors import ModelError

__all__ = ["QUANTITIES", "STATISTICS", "metric", "metric_names", "parse_objective"]

QUANTITIES = {
    "shaking_force": "N",
    "shaking_moment": "Nm",
    "driving_torque": "Nm",
    "floor_force": "N",
}
"""The quantities a design is judged by, with their key suffix (SI unit)."""

STATISTICS = ("rms", "peak", "range")
"""How a quantity's fluctuation over the cycle is measured."""


def metric_names(floor: bool = True) -> list[str]:
    """Every objective name, ``<quantity>_<statistic>`` (``floor_force_*`` only with a support).

    Parameters
    ----------
    floor : bool
        Whether the floor force (through a support model) is known.
    """
    return [f"{q}_{s}" for q in QUANTITIES for s in STATISTICS if floor or q != "floor_force"]


def parse_objective(objective: Any, floor: bool) -> dict[str, float]:
    """An objective as weights per metric: a name, or a mapping of names to weights (a weighted sum of
    each metric relative to its value without counterweights).

    Parameters
    ----------
    objective : str or mapping of str to float
        ``"shaking_force_rms"``, or ``{"shaking_force_rms": 1, "driving_torque_range": 0.5}``
        (weights dimensionless, not negative, not all zero).
    floor : bool
        Whether floor-force metrics are allowed (a support model is given).
    """
    names = metric_names(floor)
    weights = {objective: 1.0} if isinstance(objective, str) else dict(objective)
    if not isinstance(objective, (str, Mapping)) or not weights:
        raise ModelError(
            f"{objective!r}: give a metric name or a mapping of names to weights",
            element="balance",
            field="objective",
        )
    for k, w in weights.items():
        if k not in names:
            hint = (
                " (the floor force needs a support model: run on a support file, or give --support)"
                if k.startswith("floor_force") and not floor
                else ""
            )
            raise ModelError(
                f"{k!r} is not an objective{hint}; choose from {', '.join(names)}",
                element="balance",
                field="objective",
            )
        if not np.isfinite(w) or w < 0:
            raise ModelError(
                f"weight {w!r} of {k!r} must be a number ≥ 0", element="balance", field="objective"
            )
    if sum(weights.values()) <= 0:
        raise ModelError("the weights must not all be zero", element="balance", field="objective")
    return {k: float(w) for k, w in weights.items()}


def metric(values: np.ndarray, statistic: str) -> np.ndarray:
    """A statistic of the fluctuation of ``values`` over the cycle.

    Parameters
    ----------
    values : ndarray
        (..., N, c) a quantity over the N crank angles, c components (N or N·m).
    statistic : {"rms", "peak", "range"}
        See the module docstring.

    Returns
    -------
    ndarray
        (...) in the unit of ``values``.
    """
    d = values - values.mean(axis=-2, keepdims=True)
    if statistic == "rms":
        return np.sqrt(np.mean(np.sum(d**2, axis=-1), axis=-1))
    if statistic == "peak":
        return np.sqrt(np.max(np.sum(d**2, axis=-1), axis=-1))
    if statistic == "range":
        return np.max(values.max(axis=-2) - values.min(axis=-2), axis=-1)
    raise ModelError(f"{statistic!r}: choose rms, peak or range", element="balance", field="objective")


def split(name: str) -> tuple[str, str]:
    """``"shaking_force_rms"`` → ``("shaking_force", "rms")``.

    Parameters
    ----------
    name : str
        A metric name.
    """
    quantity, _, statistic = name.rpartition("_")
    return quantity, statistic
