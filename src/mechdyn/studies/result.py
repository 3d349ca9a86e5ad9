"""A study's result, with the result protocol: its summary, its tables and its plots."""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from mechdyn.results import Result, Table
from mechdyn.studies.cells import table
from mechdyn.studies.storage import StoredStudy, StoredVariant
from mechdyn.studies.study import Study

__all__ = ["StudyResult", "boxes_table", "failure_reason"]


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
        the study), each counted once, whether they succeeded or failed.
    reused : int
        Variants of the result found already stored (a resumed study; all of a result read from the
        database alone), succeeded or failed. ``evaluated + reused`` is :attr:`count`, the number of
        distinct variants, on a first run and on every rerun.
    failed : int
        Of those, the variants that could not be evaluated (stored with their error), each counted
        once, whether they failed now or before: ``count − failed`` succeeded. Why they failed:
        :attr:`failures`.
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

    @property
    def count(self) -> int:
        """The number of distinct variants: each design once, the base design among them where the
        kind evaluates it (one at a time, factorial, Latin hypercube, optimization, synthesis; a Sobol
        sample has none), however often the design lists it (a factorial's base that is also a point
        of its grid). ``evaluated + reused`` is this number."""
        return len({v.key for v in self.variants})

    @property
    def failures(self) -> list[dict[str, Any]]:
        """Why variants failed, grouped by reason, the most frequent first: each ``reason`` (the error
        with its numbers left out, ``…``, so that "the crank stops at 12°" and "at 40°" are one
        reason), ``count``, ``variants`` (their ids) and ``example`` (the first one's error in full)."""
        groups: dict[str, dict[str, Any]] = {}
        for v in {v.key: v for v in self.variants}.values():
            if v.status == "ok":
                continue
            reason = failure_reason(v.error)
            g = groups.setdefault(reason, {"reason": reason, "count": 0, "variants": [], "example": v.error})
            g["count"] += 1
            g["variants"].append(v.id)
        return sorted(groups.values(), key=lambda g: -g["count"])  # stable: first seen first on ties

    @property
    def every_variant_failed(self) -> bool:
        """True when no variant but the base design could be evaluated: the study shows nothing of
        what its parameters do (an output's range would be the base design's value alone)."""
        from mechdyn.studies.kinds.base import base_variant

        if not self.failed:
            return False
        distinct = list({v.key: v for v in self.variants}.values())
        base = base_variant(self.study, distinct)
        return not any(v.status == "ok" for v in distinct if base is None or v.key != base.key)

    def failure_line(self) -> str:
        """How many variants failed and why, in one line: ``20 of 20 variants failed: 14 × 'the crank
        stops at …° turned', 6 × '…'`` (empty when none failed)."""
        if not self.failed:
            return ""
        from mechdyn.studies.kinds.base import base_variant

        base = base_variant(self.study, list(self.variants))
        but_base = (
            ", every one but the base design"
            if self.every_variant_failed and base is not None and base.status == "ok"
            else ""
        )
        reasons = ", ".join(f"{g['count']} × '{g['reason']}'" for g in self.failures)
        return f"{self.failed} of {self.count} variants failed{but_base}: {reasons}"

    def summary(self) -> dict[str, Any]:
        """``study``, ``kind``, ``variants`` (:attr:`count`), ``evaluated``, ``reused``, ``failed``,
        ``every_variant_failed``, ``failures`` (:attr:`failures`) and the findings."""
        return {
            "study": self.study.name,
            "kind": self.study.kind,
            "analysis": self.study.analysis,
            "variants": self.count,
            "evaluated": self.evaluated,
            "reused": self.reused,
            "failed": self.failed,
            "every_variant_failed": self.every_variant_failed,
            "failures": self.failures,
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
        the units the study file gives, then :meth:`count_tables`."""
        from mechdyn.studies.kinds import kind

        return [*kind(self.study.kind).tables(self), *self.count_tables()]

    def count_tables(self) -> list[Table]:
        """The variant counts (evaluated now and reused add up to the variants; of those, how many
        failed) and, where some failed, why: one row per reason with how many."""
        name = self.study.name
        out = [
            table(
                f"{name}: variants",
                ["variants", "evaluated now", "reused", "failed"],
                [[self.count, self.evaluated, self.reused, self.failed]],
                note="evaluated now + reused = variants, each design once (the base design among "
                "them where the kind has one); failed: those of them that could not be evaluated, now "
                "or before",
            )
        ]
        if self.failed:
            out.append(
                table(
                    f"{name}: why variants failed",
                    ["variants", "reason", "first"],
                    [[g["count"], g["reason"], g["variants"][0]] for g in self.failures],
                    note=f"{self.failed} of {self.count} variants failed, grouped by reason (numbers left "
                    "out: …); `mechdyn results list --study` shows each variant's error in full",
                )
            )
        return out

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


def boxes_table(results: list[StudyResult]) -> Table:
    """One row per study of a file with boxes (:func:`mechdyn.studies.load_studies`): its optimum's
    improvement of the objective and its outputs, each output in its study unit (else the unit the
    column's largest value reads best in).

    Parameters
    ----------
    results : list of StudyResult
        The boxes' results, in order.
    """
    watched = [
        w.readable((r.findings.get("best") or {}).get("outputs", {}).get(w.key) for r in results)
        for w in results[0].study.watched
    ]
    rows: list[list[Any]] = []
    for r in results:
        best = r.findings.get("best")
        if best is None:
            rows.append([r.study.name, "no feasible variant", *([None] * len(watched))])
            continue
        rows.append(
            [
                r.study.name,
                r.findings.get("improvement_percent"),
                *(w.show(best["outputs"].get(w.key)) for w in watched),
            ]
        )
    return table(
        "the optimum of each box", ["study", "objective improved [%]", *(w.label for w in watched)], rows
    )


# a number on its own in an error message (not part of a name, a row number "#2" or an exponent "m^2")
_NUMBER = re.compile(r"(?<![\w#'\"^./-])[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?![\w'\"])")
# what leads an error without saying why: the exception's class, a batch's index of the variant
_ERROR_CLASS = re.compile(r"^(?:[A-Z]\w*: )?(?:variant \d+: )?")


def failure_reason(error: str | None) -> str:
    """A failed variant's error as a reason shared with others: without the exception's class (and a
    batch's index of the variant) and with its numbers left out (``StallError: the crank stops at
    12.5° turned`` → ``the crank stops at …° turned``).

    Parameters
    ----------
    error : str or None
        The error as stored with the variant.
    """
    text = _ERROR_CLASS.sub("", (error or "no reason stored").strip(), count=1)
    return _NUMBER.sub("…", text)


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
