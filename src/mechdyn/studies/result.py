"""A study's result, with the result protocol: its summary, its tables and its plots."""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from mechdyn.results import Result, Table
from mechdyn.studies.storage import StoredStudy, StoredVariant
from mechdyn.studies.study import Study

__all__ = ["StudyResult"]


@dataclass(frozen=True, repr=False)  # the short repr of Result
class StudyResult(Result):
    """What a study found, and every variant it holds.

    Attributes
    ----------
    study : Study
    stored : StoredStudy
        Its row in the results database.
    variants : tuple of StoredVariant
        The study's variants in design order (optimization and synthesis: every variant stored, the
        base first); a design may list one twice (a factorial's base that is also a point of its grid).
    evaluated : int
        Variants of the result evaluated by this run (or stored meanwhile by another process sharing
        the study), each counted once; ``evaluated + reused`` is the number of distinct variants.
    reused : int
        Variants of the result found already stored (a resumed study; all of a result read from the
        database alone).
    failed : int
        Variants that could not be evaluated (stored with their error), each counted once.
    findings : dict
        What the kind found (SI): ``effects`` (oat), ``indices`` (sobol), ``best`` and
        ``improvement_percent`` (optimize), ``pareto_front``, ``targets`` (synthesis), ...
    kept : tuple of StoredVariant
        Variants with their curves (the base and the best; every variant of a small study).
    """

    study: Study
    stored: StoredStudy
    variants: tuple[StoredVariant, ...]
    evaluated: int
    reused: int
    failed: int
    findings: dict[str, Any]
    kept: tuple[StoredVariant, ...] = ()

    def summary(self) -> dict[str, Any]:
        """``study``, ``kind``, ``evaluated``, ``reused``, ``failed``, ``variants`` and the findings."""
        return {
            "study": self.study.name,
            "kind": self.study.kind,
            "analysis": self.study.analysis,
            "variants": len(self.variants),
            "evaluated": self.evaluated,
            "reused": self.reused,
            "failed": self.failed,
            "parameters": {
                p.name: {
                    "base": p.base,
                    "unit": p.unit,
                    "low": p.low,
                    "high": p.high,
                    "levels": list(p.levels),
                    # a choice's values are indices: the names they stand for, in the file's words
                    **({"choices": [p.shown(float(i)) for i in range(len(p.choices))]} if p.choices else {}),
                }
                for p in self.study.parameters
            },
            **self.findings,
        }

    def to_frame(self) -> Any:
        """One row per variant: id, status, parameters (SI; a choice by its name) and outputs (SI)."""
        import pandas as pd

        def given(p: Any, x: float | None) -> Any:
            return p.shown(x) if p.choices and x is not None else x

        rows = []
        for v in self.variants:
            row: dict[str, Any] = {"variant": v.id, "status": v.status}
            row |= {
                _column(p.name, _si_unit(p)): given(p, v.parameters.get(p.name))
                for p in self.study.parameters
            }
            row |= {_column(w.key, _key_suffix(w.unit)): v.outputs.get(w.key) for w in self.study.watched}
            row["error"] = v.error
            rows.append(row)
        return pd.DataFrame(rows)

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        return {}

    # -- tables ----------------------------------------------------------------------------------
    def tables(self, **display_units: str) -> list[Table]:
        """The tables a designer expects of the kind (:meth:`mechdyn.studies.kinds.Kind.tables`), in
        the units the study file gives, and the variant counts."""
        from mechdyn.studies.kinds import kind

        return [
            *kind(self.study.kind).tables(self),
            Table(
                f"{self.study.name}: variants",
                ["variants", "evaluated now", "reused", "failed"],
                [[self.evaluated + self.reused, self.evaluated, self.reused, self.failed]],
            ),
        ]

    @property
    def base_id(self) -> int | None:
        """The stored id of the study's base design (the model as given), or None when the study has
        none among its variants (a Sobol or Latin-hypercube sample)."""
        f = self.findings
        if f.get("base_variant") is not None:
            return int(f["base_variant"])
        base = f.get("base")
        return int(base["variant"]) if isinstance(base, dict) and base.get("variant") is not None else None

    # -- plots ---------------------------------------------------------------------------------
    def plots(self, **display_units: str) -> dict[str, Any]:
        """The kind's plots (:meth:`mechdyn.studies.kinds.Kind.plots`: tornado, main effects, Sobol
        bars, history, Pareto front, parallel coordinates) and the overlaid curves of the kept
        variants."""
        from mechdyn.studies import plots as sp
        from mechdyn.studies.kinds import kind
        from mechdyn.studies.kinds.base import safe

        out = kind(self.study.kind).plots(self)
        x, names = sp.curve_choice(self.kept)
        for name in names:
            out[f"curves_{safe(name)}.png"] = partial(sp.curves, self.kept, name, x, base=self.base_id)
        return out


def _si_unit(p: Any) -> str:
    return _key_suffix(p.unit)


def _key_suffix(unit: str) -> str:
    from mechdyn.units import key_suffix

    return key_suffix(unit)


def _column(name: str, suffix: str) -> str:
    """A column name without spaces that ends with its SI unit (``support.stiffness_N_per_m``)."""
    from mechdyn.units import key_unit

    name = name.replace(" ", "_")
    if key_unit(name) is not None or not suffix:
        return name
    return f"{name}_{suffix}"
