"""What if: one design of a stored study evaluated at once, from values a designer sets on sliders.

The study's own parameters only, each a number within its range (a choice: one of its levels), in
the unit its study file shows; the design is built from the study's stored definition and model
files, as a variant of it would be, and its analysis run one by one; nothing is written. The answer
holds its outputs beside the study's best, its first curves, and, for a mechanism, the linkage over
the cycle to animate.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Mapping
from typing import Any

import numpy as np

from mechdyn.errors import MechdynError

__all__ = ["WhatIf", "WhatIfError"]

FRAMES = 36
"""Poses of an animated linkage over one cycle."""

CURVE_POINTS = 400
"""Samples at most of each curve sent to the page."""


class WhatIfError(MechdynError):
    """A value the what-if form does not take: names the parameter, the value and what it takes."""


class WhatIf:
    """The what-if evaluations of one stored study.

    Parameters
    ----------
    store : ResultStore
        The results database (read-only is enough).
    name : str
        The study's name.
    columns : list of Column
        Its columns as shown (:func:`mechdyn.reports.columns.stored_columns`).
    """

    def __init__(self, store: Any, name: str, columns: list[Any]) -> None:
        from mechdyn.studies.evaluate import Evaluator
        from mechdyn.studies.run import stored_study

        study = stored_study(store, name)
        self.parameters = list(study.parameters)
        self.columns = {c.key: c for c in columns}
        self.outputs = [c for c in columns if c.role == "output"]
        self.evaluator = Evaluator(
            study.source,
            study.analysis,
            study.parameters,
            [c.key for c in self.outputs],
            study.options,
            batch=False,
        )
        self._lock = threading.Lock()  # one evaluation at a time: an analysis is not made for threads

    def sliders(self) -> list[dict[str, Any]]:
        """One slider (or, for a choice, one list) per parameter: name, label with unit, range and
        base value in the shown unit."""
        out = []
        for p in self.parameters:
            c = self.columns.get(p.name)
            label = c.label if c is not None else p.name
            if p.choices:
                out.append(
                    {"name": p.name, "label": label, "levels": list(c.levels) if c else [], "value": 0}
                )
                continue
            lo, hi = self._range(p)
            per = p.factor or 1.0  # SI per shown unit
            a, b, base = lo / per, hi / per, p.base / per
            out.append(
                {
                    "name": p.name,
                    "label": label,
                    "min": a,
                    "max": b,
                    "value": min(max(base, a), b),
                    "step": 1 if p.integer else (b - a) / 200 if b > a else 1,
                }
            )
        return out

    @staticmethod
    def _range(p: Any) -> tuple[float, float]:
        """A parameter's range, SI: its own, else the span of its levels and base."""
        if p.low is not None and p.high is not None:
            return float(p.low), float(p.high)
        values = [p.base, *p.levels]
        return float(min(values)), float(max(values))

    def row(self, given: Mapping[str, str]) -> list[float]:
        """The SI values of a design from the form's values (shown units); a missing one is the
        base. Raises :class:`WhatIfError` for anything else than the study's parameters as numbers
        within their ranges."""
        names = {p.name for p in self.parameters}
        unknown = sorted(set(given) - names)
        if unknown:
            raise WhatIfError(
                f"{unknown[0]!r} is not a parameter of this study; it takes {', '.join(sorted(names))}"
            )
        row = []
        for p in self.parameters:
            text = given.get(p.name)
            if text is None:
                row.append(float(p.base))
                continue
            try:
                x = float(text)
            except ValueError:
                raise WhatIfError(f"{p.name} = {text!r} is not a number") from None
            if not math.isfinite(x):
                raise WhatIfError(f"{p.name} = {text!r} is not a finite number")
            if p.choices:
                if x != int(x) or not 0 <= x < len(p.choices):
                    raise WhatIfError(
                        f"{p.name} = {text!r}: give the index of one of its {len(p.choices)} levels"
                    )
                row.append(float(x))
                continue
            si = x * p.factor if p.factor else x
            lo, hi = self._range(p)
            tol = 1e-9 * max(abs(lo), abs(hi), 1e-300)
            if not lo - tol <= si <= hi + tol:
                c = self.columns.get(p.name)
                unit = f" {c.unit}" if c is not None and c.unit else ""
                a, b = (lo / p.factor, hi / p.factor) if p.factor else (lo, hi)
                raise WhatIfError(f"{p.name} = {x:g}{unit} is outside its range, {a:g} to {b:g}{unit}")
            row.append(min(max(si, lo), hi))
        return row

    def evaluate(self, row: list[float]) -> dict[str, Any]:
        """The design's outputs (shown units), first curves and, for a mechanism, its linkage.

        Parameters
        ----------
        row : list of float
            The parameters' SI values, in the study's order (:meth:`row`).
        """
        t0 = time.perf_counter()
        with self._lock:
            ev = self.evaluator.one(row, curves=True, keep_result=True)
        seconds = time.perf_counter() - t0
        outputs = [
            {"key": c.key, "label": c.label, "value": c.shown(ev.outputs.get(c.key))} for c in self.outputs
        ]
        return {
            "status": ev.status,
            "error": ev.error or "",
            "seconds": seconds,
            "outputs": outputs,
            "curves": _curves(ev.curves),
            "linkage": linkage(ev.result),
        }


def _curves(curves: dict[str, tuple[np.ndarray, str]], limit: int = 3) -> list[dict[str, Any]]:
    """The curves that vary most, against the run's own x (time or angle), thinned for the page."""
    from mechdyn.dashboard.views import thin
    from mechdyn.studies.plots import choose_curves

    if not curves:
        return []
    x, names = choose_curves([curves], limit)
    if x is None:
        return []
    xs = np.asarray(curves[x][0], dtype=float)
    keep = thin(xs.size, CURVE_POINTS)
    out = []
    for name in names:
        y = np.asarray(curves[name][0], dtype=float)
        if y.shape != xs.shape:
            continue
        out.append(
            {
                "name": name,
                "unit": curves[name][1],
                "x_name": x,
                "x": xs[keep].tolist(),
                "y": [float(v) if math.isfinite(v) else None for v in y[keep]],
            }
        )
    return out


def linkage(result: Any, frames: int = FRAMES) -> dict[str, Any] | None:
    """A mechanism's bodies over one cycle, mm, for an animation: per body its points' x and y at
    ``frames`` crank angles (a closed outline for three points and more); None for any other result.

    Parameters
    ----------
    result : Result
        An analysis' result; a mechanism's (it has ``kinematics`` and ``mechanism``) draws.
    frames : int
        Poses over the cycle.
    """
    if result is None or not hasattr(result, "kinematics") or not hasattr(result, "mechanism"):
        return None
    from mechdyn.mechanism.plots import linkage_tracks

    tracks = linkage_tracks(result)
    n = len(result.kinematics.angle)
    idx = np.linspace(0, n, frames, endpoint=False).astype(int)
    bodies = []
    for b in result.mechanism.bodies:
        points = [tracks[(b.name, p)] for p in b.points if (b.name, p) in tracks]
        if not points:
            continue
        if len(points) >= 3:
            points = [*points, points[0]]
        bodies.append(
            {
                "name": b.name,
                "x": [[float(pt[i, 0]) for pt in points] for i in idx],
                "y": [[float(pt[i, 1]) for pt in points] for i in idx],
            }
        )
    angles = np.degrees(np.asarray(result.kinematics.angle, dtype=float))[idx]
    return {"bodies": bodies, "angles_deg": angles.tolist()}
