"""The protocol of a study kind, its registry, and what the kinds share.

A kind is one object (a subclass of :class:`Kind`, registered once with :func:`register`) that
designs the variants of a study, evaluates them through a runner, and states what they show:

- :meth:`Kind.check` — what the kind needs of a study (levels or ranges, objectives, targets);
- :meth:`Kind.design` — the rows of a fixed design (``None`` for a search that adapts);
- :meth:`Kind.run` — the evaluation: a fixed design is evaluated as it is, a search asks for its
  variants as it goes; it returns the study's variants and what only the run knows (trials, the
  polish);
- :meth:`Kind.order` — the stored variants in the order :meth:`findings` expects them;
- :meth:`Kind.findings` — a pure function of the study and its variants (JSON-ready, SI), the same
  after a run and from the database alone;
- :meth:`Kind.tables` and :meth:`Kind.plots` — how the result shows them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.cells import number, parameter_text, table, unit_text
from mechdyn.studies.errors import StudyError
from mechdyn.studies.storage import StoredVariant, variant_key

if TYPE_CHECKING:
    from mechdyn.studies.parameters import Parameter
    from mechdyn.studies.plan import Study, StudyFindings

__all__ = ["KINDS", "Found", "Kind", "Ran", "kind", "least_violation", "level_kinds", "register"]


@dataclass(frozen=True)
class Found:
    """What a kind found.

    Attributes
    ----------
    findings : dict
        JSON-ready, SI (see each kind's ``findings``).
    best : frozenset of int
        Ids of the variants whose curves are always kept (the base, the optimum, the front).
    """

    findings: dict[str, Any]
    best: frozenset[int] = frozenset()


@dataclass(frozen=True)
class Ran:
    """What a run of a kind gives: the study's variants (in the order of :meth:`Kind.order`) and the
    findings only the run knows (Optuna's trials, the polish, the optimum evaluated again)."""

    variants: list[StoredVariant]
    extra: dict[str, Any] = field(default_factory=dict)


class Kind:
    """A study kind. Subclasses set :attr:`name`, :attr:`title` and :attr:`uses`, and define
    :meth:`findings`; a kind with a fixed design defines :meth:`design`, a search :meth:`run`."""

    name: ClassVar[str]
    title: ClassVar[str]
    """How the docs and the study file's field help name it (``"one at a time"``)."""
    uses: ClassVar[str] = "ranges"
    """``"levels"`` (levels, or a range's two ends) or ``"ranges"`` (a continuous range each)."""

    # -- the study ----------------------------------------------------------------------------
    def check(self, study: Study) -> None:
        """Refuse a study this kind cannot run (:class:`StudyError` naming the file and the fix)."""
        where = study.path or study.name
        self.refuse_discrete(study.parameters, where)
        for p in study.parameters:
            if self.uses == "levels" and not p.levels and not p.bounded:
                raise StudyError(
                    f"{where}: parameter {p.name!r} needs levels or a range for a {self.name} study"
                )
            if self.uses == "ranges" and not p.bounded:
                raise StudyError(
                    f'{where}: parameter {p.name!r} needs a range ("±10 %" or [low, high]) '
                    f"for a {self.name} study"
                )

    def refuse_discrete(self, parameters: Sequence[Parameter], where: str) -> None:
        """Refuse a whole number or a choice (levels only) in a kind that varies continuous ranges.

        Parameters
        ----------
        parameters : sequence of Parameter
        where : str
            The study file and row, for the message.
        """
        from mechdyn.studies.paths import file_text

        if self.uses == "levels":
            return
        for p in parameters:
            if not p.discrete:
                continue
            what = "a whole number" if p.integer else "a choice"
            if p.choices:
                example = "[" + ", ".join(file_text(c) for c in p.choices[1:3]) + "]"
            else:
                example = f"[{round(p.base) + 1}, {round(p.base) + 2}]"
            raise StudyError(
                f"{where}: {p.name!r} is {what} ({p.shown(p.base)} in the model), which takes levels, not a "
                f"range: a {self.name} study varies continuous ranges only. Vary it in a study of kind "
                f"{' or '.join(level_kinds())}, with levels = {example}"
            )

    def design(self, study: Study) -> np.ndarray | None:
        """The variants of a fixed design, one row of parameter values (SI) each; ``None`` for a
        search, whose variants depend on what it finds."""
        return None

    # -- running ------------------------------------------------------------------------------
    def run(self, runner: Any) -> Ran:
        """Evaluate the study's variants through ``runner`` (:class:`mechdyn.studies.run.Runner`:
        ``evaluate(X)`` returns the stored variants of the rows of X, evaluating those not stored)."""
        X = self.design(runner.study)
        if X is None:
            raise NotImplementedError(f"the {self.name} kind defines neither a design nor a run")
        return Ran(runner.evaluate(X))

    def confirm(self, runner: Any, found: Found) -> dict[str, Any]:
        """Findings that need one more evaluation once the others are known (the optimum through the
        single-design path); none by default."""
        return {}

    def order(self, study: Study, variants: Sequence[StoredVariant]) -> list[StoredVariant]:
        """The stored variants of a study in the order :meth:`findings` expects: a fixed design's rows
        in design order; a search's variants, the base first, then in the order stored.

        Raises
        ------
        StudyError
            When a fixed design's variants are not all stored yet (the study is still running).
        """
        X = self.design(study)
        if X is None:
            base = base_variant(study, variants)
            rest = sorted((v for v in variants if base is None or v.id != base.id), key=lambda v: v.id)
            return [base, *rest] if base is not None else rest
        by_key = {v.key: v for v in variants}
        keys = [variant_key(r) for r in np.atleast_2d(X)]
        missing = sum(1 for k in keys if k not in by_key)
        if missing:
            raise StudyError(
                f"{missing} of the study's {len(keys)} variants are not stored yet (is it still running?)"
            )
        return [by_key[k] for k in keys]

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """What the variants show (a pure function: nothing evaluated, nothing written)."""
        raise NotImplementedError

    # -- showing ------------------------------------------------------------------------------
    def tables(self, result: StudyFindings) -> list[Table]:
        """The tables a designer expects of the kind, in the study's units."""
        return []

    def plots(self, result: StudyFindings) -> dict[str, Callable[[], Any]]:
        """The kind's plots: file name → a function that draws it."""
        return {}

    def views(self, result: StudyFindings) -> dict[str, Any] | None:
        """What a report and the dashboard's study page lead with, or None (the findings' tables
        and plots alone): ``title``, ``headline`` (sentences), ``note``, ``warnings`` and ``figures``
        ((file name, caption, draw) each), as :meth:`mechdyn.studies.kinds.tolerance.Tolerance.views`
        gives them."""
        return None


KINDS: dict[str, Kind] = {}
"""Every study kind by name (:func:`register`)."""


def register(cls: type[Kind]) -> type[Kind]:
    """Register a kind (a class decorator): its one instance becomes ``KINDS[cls.name]``."""
    if cls.name in KINDS:
        raise ValueError(f"a study kind {cls.name!r} is registered already")
    KINDS[cls.name] = cls()
    return cls


def kind(name: str) -> Kind:
    """The registered kind of this name.

    Raises
    ------
    StudyError
        For a name no kind has, listing those there are.
    """
    try:  # importing this module ran its package's __init__, which registers every kind
        return KINDS[name]
    except KeyError:
        raise StudyError(f"no study kind {name!r}: the kinds are {', '.join(KINDS)}") from None


def level_kinds() -> tuple[str, ...]:
    """The study kinds that take levels (one-at-a-time and factorial): those a whole number or a
    choice can be a parameter of."""
    return tuple(name for name, k in KINDS.items() if k.uses == "levels")


# -- what the kinds share ---------------------------------------------------------------------
def value(v: StoredVariant, key: str) -> float:
    """An output of a variant, NaN where it has none (or failed)."""
    x = v.outputs.get(key)
    return float(x) if x is not None and v.status == "ok" else math.nan


def base_row(study: Study) -> np.ndarray:
    """The base design's parameter values (SI)."""
    return np.array([p.base for p in study.parameters], dtype=float)


def base_variant(study: Study, variants: Sequence[StoredVariant]) -> StoredVariant | None:
    """The stored variant of the base design (the model as given), if there is one."""
    key = variant_key(base_row(study))
    return next((v for v in variants if v.key == key), None)


def feasible(study: Study, v: StoredVariant) -> bool:
    """Evaluated, and every constraint of the study holds."""
    return v.status == "ok" and all(c.holds(v.outputs.get(c.output.key)) for c in study.constraints)


def best(study: Study, variants: Sequence[StoredVariant]) -> StoredVariant | None:
    """The feasible variant best in the first objective (None without objective or feasible variant)."""
    if not study.objectives:
        return None
    o = study.objectives[0]
    cands = [v for v in variants if feasible(study, v) and math.isfinite(value(v, o.output.key))]
    return min(cands, key=lambda v: o.sign * value(v, o.output.key)) if cands else None


def least_violation(study: Study, variants: Sequence[StoredVariant]) -> dict[str, Any] | None:
    """How near a search came to keeping every constraint, when no variant keeps them all: the
    evaluated variant whose worst violation is least, each violation relative to its constraint's
    scale (the tolerance of an ``equals``, else the size of the limit) so that limits in different
    units compare.

    Parameters
    ----------
    study : Study
        Its constraints.
    variants : sequence of StoredVariant
        The study's variants.

    Returns
    -------
    dict or None
        None when a variant keeps every constraint, or none was evaluated. Otherwise ``variant``
        (its id), ``relative`` (its worst violation over that constraint's scale) and
        ``constraints``: per constraint ``constraint`` (in words), ``value`` (SI), ``violation``
        (how far outside its limits, in the output's SI unit; ≤ 0 where it holds) and ``holds``.
    """
    if not study.constraints or any(feasible(study, v) for v in variants):
        return None

    def worst(v: StoredVariant) -> float:
        return max(c.relative_violation(v.outputs.get(c.output.key)) for c in study.constraints)

    evaluated = [v for v in variants if v.status == "ok" and math.isfinite(worst(v))]
    if not evaluated:
        return None
    nearest = min(evaluated, key=worst)
    return {
        "variant": nearest.id,
        "relative": worst(nearest),
        "constraints": [
            {
                "constraint": c.describe(),
                "value": nearest.outputs.get(c.output.key),
                "violation": c.violation(nearest.outputs.get(c.output.key)),
                "holds": c.holds(nearest.outputs.get(c.output.key)),
            }
            for c in study.constraints
        ],
    }


def least_violation_table(result: StudyFindings) -> Table:
    """:func:`least_violation` of the findings as a table: the variant that came nearest, and how far
    it breaks each constraint in the constraint's display unit."""
    st, near = result.study, result.findings.get("least_violation")
    rows: list[list[Any]] = [["nearest to keeping every constraint", "none: no variant could be evaluated"]]
    if near:
        rows = [["nearest to keeping every constraint", f"variant {near['variant']}"]]
        for c, d in zip(st.constraints, near["constraints"], strict=True):
            o = c.output
            by = o.difference(d["violation"]) if math.isfinite(d["violation"]) else None
            shown = "no value" if by is None else f"broken by {number(by)} {unit_text(o.shown_unit)}".strip()
            rows.append([d["constraint"], "holds" if d["holds"] else shown])
    return table(f"{st.name}: no variant keeps every constraint", ["", "value"], rows)


def describe(study: Study, v: StoredVariant) -> dict[str, Any]:
    """A variant as findings hold it: id, parameters (SI and as given), outputs, and each constraint
    with its value and whether it holds."""
    return {
        "variant": v.id,
        "parameters": v.parameters,
        "given": v.given,
        "outputs": v.outputs,
        "constraints": [
            {
                "constraint": c.describe(),
                "value": v.outputs.get(c.output.key),
                "holds": c.holds(v.outputs.get(c.output.key)),
            }
            for c in study.constraints
        ],
    }


def variant_table(result: StudyFindings, d: dict[str, Any], title: str) -> Table:
    """One variant of the findings (:func:`describe`) as a table: its parameters as the study file
    gives them, each output in words in the study's unit (else the unit its size reads best in),
    whether each constraint holds."""
    st = result.study
    rows: list[list[Any]] = [
        [p.name, parameter_text(p, x) if (x := d["parameters"].get(p.name)) is not None else None]
        for p in st.parameters
    ]
    for w in st.watched:
        y = d["outputs"].get(w.key)
        shown = w.readable([y])
        rows.append([shown.label, shown.show(y)])
    rows += [[c["constraint"], "holds" if c["holds"] else "VIOLATED"] for c in d.get("constraints", [])]
    if title == "optimum" and result.findings.get("improvement_percent") is not None:
        rows.append(["improvement of the objective [%]", result.findings["improvement_percent"]])
    return table(f"{st.name}: {title} (variant {d['variant']})", ["", "value"], rows)


def safe(key: str) -> str:
    """An output key as part of a file name."""
    return "".join(c if c.isalnum() or c in "_-" else "_" for c in key)


def parallel_plot(result: StudyFindings) -> dict[str, Callable[[], Any]]:
    """The parallel-coordinates plot of the variants."""
    from mechdyn.studies import plots as sp

    return {"parallel_coordinates.png": lambda: sp.parallel(result)}
