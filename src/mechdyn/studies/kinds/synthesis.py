"""Synthesis to targets (``synthesis``)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.cells import MEASURE_DIGITS, given, number, table, unit_text
from mechdyn.studies.errors import StudyError
from mechdyn.studies.kinds.base import (
    Found,
    Kind,
    Ran,
    base_row,
    describe,
    feasible,
    least_violation,
    least_violation_table,
    parallel_plot,
    register,
    variant_table,
)
from mechdyn.studies.kinds.optimize import TIE
from mechdyn.studies.polish import (
    CONVERGED,
    FIRST_ORDER,
    NOT_CONVERGED,
    fit,
    optimality,
    polish,
    stencil,
    target_cost,
    verdict,
)
from mechdyn.studies.storage import StoredVariant, variant_key

if TYPE_CHECKING:
    from mechdyn.studies.plan import Study, StudyFindings

__all__ = ["Synthesis"]

_PENALTY = 1e3  # weight of a squared, scaled constraint violation in the evolution's cost

FITS = 3
"""Least-squares fits per stage, from the best members of the evolution's last population that lie
in distinct basins."""

STAGES = 6
"""At most this many stages (evolution, fits, polish), each from a new seed, until every target holds."""

_JUDGED = 1e-3
"""Relative: a missed target is judged at the best fit whose gradient is stored within this of the
best cost (a step of the gradient's own stencil may land a hair below the point it was taken at)."""


@register
class Synthesis(Kind):
    """Fit targets (each ``equals`` within its ``tolerance``), in stages until every target holds (at
    most :data:`STAGES`). A stage is differential evolution (Storn & Price, *J. Global Optim.* 11,
    1997; :func:`scipy.optimize.differential_evolution`, a whole generation evaluated as one block)
    on the sum of squared residuals over tolerance with the constraints as penalties, a least-squares
    fit (:func:`mechdyn.studies.polish.fit`, Gauss–Newton with a trust region) from the best members
    of its last population that lie in distinct basins, and a constrained SLSQP polish of the best
    fit (:func:`mechdyn.studies.polish.polish`). The first stage starts from the study's seed and the
    base design; each later one from a seed spawned off it (a restart: a fit in the wrong basin is a
    local optimum that more generations rarely leave)."""

    name = "synthesis"
    title = "synthesis to targets"

    def check(self, study: Study) -> None:
        super().check(study)
        if not study.targets:
            raise StudyError(
                f"{study.path or study.name}: a synthesis study needs [[targets]] (output, equals, tolerance)"
            )

    def run(self, runner: Any) -> Ran:
        st = runner.study
        bounds = np.array([(p.low, p.high) for p in st.parameters], dtype=float)
        # later stages draw from streams spawned off the study's seed: the first stage is the seed's own
        spawned = np.random.SeedSequence(st.seed).spawn(STAGES - 1)
        seeds = [st.seed, *(int(s.generate_state(1)[0]) for s in spawned)]
        stages = []
        for k, seed in enumerate(seeds):
            stage = self._stage(runner, seed, bounds, first=k == 0)
            stages.append(stage)
            if stage["targets_met"]:
                break
        # the stencil of the best fit, so that its first-order optimality can always be judged
        best = self._best(st, runner.all_variants())
        if best is not None:
            runner.evaluate(stencil(self._row(st, best), *bounds.T)[0], objective=self._objective(st))
        extra = {
            "generations": sum(s["generations"] for s in stages),
            "stages": stages,
            "polish": stages[-1]["polish"],
        }
        return Ran(self.order(st, runner.all_variants()), extra)

    @staticmethod
    def _objective(st: Study) -> Callable[[dict[str, Any]], float]:
        return lambda outputs: target_cost(st, outputs)

    @staticmethod
    def _row(st: Study, v: StoredVariant) -> np.ndarray:
        return np.array([v.parameters[p.name] for p in st.parameters], dtype=float)

    @staticmethod
    def _best(st: Study, variants: list[StoredVariant]) -> StoredVariant | None:
        fits = [
            v for v in variants if v.objective is not None and math.isfinite(v.objective) and feasible(st, v)
        ]
        return min(fits, key=lambda v: v.objective or 0.0, default=None)

    def _stage(self, runner: Any, seed: int, bounds: np.ndarray, *, first: bool) -> dict[str, Any]:
        """One stage: the evolution from ``seed`` (the first from the base design too), the
        least-squares fits of the best members of its last population in distinct basins, and the
        constrained polish of the best fit."""
        from scipy.optimize import differential_evolution

        st = runner.study
        objective = self._objective(st)

        def cost_of(v: StoredVariant) -> float:
            total = target_cost(st, v.outputs) if v.status == "ok" else math.inf
            if not math.isfinite(total):
                return 1e12
            for c in st.constraints:
                scale = abs(c.max if c.max is not None else c.min if c.min is not None else c.equals or 1.0)
                total += (
                    _PENALTY * max(0.0, c.violation(v.outputs.get(c.output.key))) ** 2 / (scale**2 or 1.0)
                )
            return total

        def f(X: np.ndarray) -> np.ndarray:
            return np.array([cost_of(v) for v in runner.evaluate(np.asarray(X).T, objective=objective)])

        res = differential_evolution(
            f,
            bounds,
            maxiter=st.samples or 100,
            popsize=st.population or 15,
            seed=seed,
            vectorized=True,
            updating="deferred",
            polish=False,
            tol=1e-8,
            x0=np.clip(runner.base_row(), *bounds.T) if first else None,  # the base, moved into the ranges
        )
        if first:
            runner.evaluate(runner.base_row())
        fits = [fit(runner, x, objective=objective) for x in _distinct(res, bounds, FITS)]
        fitted = min(fits, key=lambda r: r["cost"])
        polished = polish(runner, [fitted["x"]], objective=objective)
        best = self._best(st, runner.all_variants())
        met = best is not None and all(
            abs(best.outputs[t.output.key] - t.equals) <= t.tolerance for t in st.targets
        )
        return {
            "seed": seed,
            "generations": int(res.nit),
            "evolution_cost": float(res.fun),
            "fit": [{k: r[k] for k in ("cost", "message", "evaluations")} for r in fits],
            "polish": polished,
            "targets_met": bool(met),
        }

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """The fit (the variant nearest the targets among those that keep every constraint, preferring
        one as good whose first-order optimality can be shown), a verdict and margin per target
        (``targets``), and, for a missed target, what stops the fit (``missed_because``): the
        constraints and bounds that hold it at a first-order point, or a search that stopped short),
        the ``verdict`` on the fit's first-order measure (:func:`mechdyn.studies.polish.verdict`) and
        ``converged`` (true only when it is ``"converged"``), and where no variant keeps every
        constraint, the one that came nearest (``least_violation``)."""
        base = variants[0] if variants and variants[0].key == variant_key(base_row(study)) else None
        fits = sorted(
            (v for v in variants if feasible(study, v) and v.objective is not None),
            key=lambda v: v.objective or 0.0,
        )
        best_v, proof = (fits[0] if fits else None), None
        by_key = {v.key: v for v in variants}
        for v in fits:  # a fit as good whose first-order optimality can be shown, if there is one
            near = (v.objective or 0.0) - (best_v.objective or 0.0)  # type: ignore[union-attr]
            if near > _JUDGED * abs(best_v.objective or 0.0) + TIE:  # type: ignore[union-attr]
                break
            proof = optimality(study, v, by_key)
            if proof is not None:
                if near <= TIE * (1.0 + abs(best_v.objective or 0.0)):  # type: ignore[union-attr]
                    best_v = v
                break
        targets = []
        for t in study.targets:
            val = best_v.outputs.get(t.output.key) if best_v is not None else None
            equals, tolerance = float(t.equals or 0.0), float(t.tolerance or 0.0)  # a target has both
            off = abs(val - equals) if val is not None else None
            targets.append(
                {
                    "output": t.output.key,
                    "target": t.equals,
                    "tolerance": t.tolerance,
                    "value": val,
                    "base_value": base.outputs.get(t.output.key) if base is not None else None,
                    "holds": off is not None and off <= tolerance,
                    "margin": tolerance - off if off is not None else None,  # < 0: missed by that much
                }
            )
        missed = [t for t in targets if not t["holds"]]
        judged = verdict(proof["measure"]) if best_v is not None and proof is not None else NOT_CONVERGED
        if not missed:
            why = None
        elif proof is None:
            why = "the search stopped short: no gradient could be formed near the fit"
        elif judged != CONVERGED:
            residual = number(proof["measure"], MEASURE_DIGITS)
            why = f"the search stopped short (first-order residual {residual})"
        elif proof["active"]:
            why = (
                "the limits make it unreachable from this fit: it is a first-order point held by "
                + ", ".join(a["name"] for a in proof["active"])
                + " (a local optimum; the global search found no better one, which does not prove "
                "there is none)"
            )
        else:
            why = "the targets cannot all be met together by these parameters (a least-squares compromise)"
        out = {
            "feasible": bool(fits),
            "evaluations": len(variants),
            "cost": best_v.objective if best_v is not None else None,
            "best": describe(study, best_v) if best_v is not None else None,
            "base": describe(study, base) if base is not None else None,
            "targets": targets,
            "optimality": proof,
            "verdict": judged,
            "converged": judged == CONVERGED,
            "least_violation": least_violation(study, variants) if best_v is None else None,
            "missed_because": why,
        }
        keep = {v.id for v in (best_v, base) if v is not None}
        return Found(out, frozenset(keep))

    def tables(self, result: StudyFindings) -> list[Table]:
        st, f = result.study, result.findings
        out = [
            variant_table(result, f[k], t)
            for k, t in (("best", "optimum"), ("base", "base design"))
            if f.get(k)
        ]
        if f.get("best") is None and st.constraints:
            out.insert(0, least_violation_table(result))
        rows = []
        for t in f["targets"]:
            w = next(w for w in st.watched if w.key == t["output"])
            w = w.readable([t["target"], t["value"], t["base_value"]])
            margin = t.get("margin")
            shown = w.difference(abs(margin)) if margin is not None else None
            unit = unit_text(w.shown_unit)
            if margin is None or shown is None:
                verdict = "no value"
            elif t.get("holds", margin >= 0):
                verdict = f"holds ({number(shown)} {unit} to spare)".replace("  ", " ")
            else:
                verdict = f"MISSED by {number(shown)} {unit}".strip()
            rows.append(
                [
                    w.label,
                    w.show(t["target"]),
                    w.difference(t["tolerance"]),
                    w.show(t["value"]),
                    verdict,
                    w.show(t["base_value"]),
                ]
            )
        out.append(
            table(f"{st.name}: targets", ["output", "target", "tolerance", "fit", "verdict", "base"], rows)
        )
        if f.get("missed_because"):
            out.append(table(f"{st.name}: why a target is missed", ["note"], [[f["missed_because"]]]))
        out.append(_search_table(result))
        return out

    def plots(self, result: StudyFindings) -> dict[str, Callable[[], Any]]:
        from mechdyn.studies import plots as sp

        return {"history.png": lambda: sp.history(result)} | parallel_plot(result)


def _distinct(res: Any, bounds: np.ndarray, n: int, apart: float = 0.1) -> list[np.ndarray]:
    """Up to ``n`` members of the evolution's last population, best first, each at least ``apart``
    (a fraction of every range, in the largest coordinate) from those before it: starts in distinct
    basins. SI."""
    low, high = bounds.T
    span = np.where(high > low, high - low, 1.0)
    chosen: list[np.ndarray] = []
    for x in res.population[np.argsort(res.population_energies)]:  # SI
        if all(np.abs((x - c) / span).max() >= apart for c in chosen):
            chosen.append(x)
        if len(chosen) == n:
            break
    return chosen


def _search_table(result: StudyFindings) -> Table:
    """How the fit was found: each stage's seed, generations, best least-squares fit and whether it
    met every target (a run only: a stored study keeps its variants, not its stages), the first-order
    measure at the fit and the variants evaluated."""
    f = result.findings
    rows: list[list[Any]] = []
    for k, stage in enumerate(f.get("stages") or [], start=1):
        best = min((x["cost"] for x in stage["fit"]), default=math.nan)
        rows.append(
            [
                f"stage {k} (seed {stage['seed']})",
                f"{stage['generations']} generation{'' if stage['generations'] == 1 else 's'}, "
                f"best fit Σ((y − target)/tolerance)² = {number(best)}: "
                + ("every target holds" if stage["targets_met"] else "a target missed")
                + "; polish "
                + ", ".join(e["verdict"] for e in stage["polish"].get("per_start", [])),
            ]
        )
    proof = f.get("optimality")
    rows.append(["verdict", _verdict_words(f)])
    rows.append(
        [
            "first-order optimality (KKT residual, relative)",
            proof["measure"] if proof is not None else "not shown (no gradient stored at the fit)",
        ]
    )
    rows.append(["variants evaluated in all", f.get("evaluations")])
    return table(f"{result.study.name}: search", ["", "value"], rows)


def _verdict_words(f: dict[str, Any]) -> str:
    """The fit's verdict in words, with its first-order measure against the tolerance."""
    proof = f.get("optimality")
    if f.get("best") is None:
        return f"{NOT_CONVERGED}: no variant keeps every constraint"
    if proof is None:
        return f"{NOT_CONVERGED}: its first-order measure cannot be shown (no gradient stored there)"
    sign = "≤" if f.get("verdict") == CONVERGED else ">"
    measure = number(proof["measure"], MEASURE_DIGITS)
    words = f"{f.get('verdict')}: first-order measure {measure} {sign} {given(FIRST_ORDER)}"
    if f.get("verdict") != CONVERGED and all(t.get("holds") for t in f.get("targets", [])):
        words += " (every target holds: the fit need not be the least-squares optimum)"
    return words
