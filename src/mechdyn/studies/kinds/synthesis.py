"""Synthesis to targets (``synthesis``)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.kinds.base import (
    Found,
    Kind,
    Ran,
    base_row,
    describe,
    feasible,
    parallel_plot,
    register,
    variant_table,
)
from mechdyn.studies.kinds.optimize import FIRST_ORDER, TIE
from mechdyn.studies.polish import optimality, polish, target_cost
from mechdyn.studies.spec import StudyError
from mechdyn.studies.storage import StoredVariant, variant_key

if TYPE_CHECKING:
    from mechdyn.studies.result import StudyResult
    from mechdyn.studies.study import Study

__all__ = ["Synthesis"]

_PENALTY = 1e3  # weight of a squared, scaled constraint violation in the evolution's cost


@register
class Synthesis(Kind):
    """Fit targets (each ``equals`` within its ``tolerance``): differential evolution (Storn & Price,
    *J. Global Optim.* 11, 1997; :func:`scipy.optimize.differential_evolution`, a whole generation
    evaluated as one block) on the sum of squared residuals over tolerance, constraints as penalties,
    then a constrained SLSQP polish of its best fit (:mod:`mechdyn.studies.polish`)."""

    name = "synthesis"
    title = "synthesis to targets"

    def check(self, study: Study) -> None:
        super().check(study)
        if not study.targets:
            raise StudyError(
                f"{study.path or study.name}: a synthesis study needs [[targets]] (output, equals, tolerance)"
            )

    def run(self, runner: Any) -> Ran:
        from scipy.optimize import differential_evolution

        st = runner.study

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

        def objective_outputs(outputs: dict[str, Any]) -> float:
            return target_cost(st, outputs)

        def f(X: np.ndarray) -> np.ndarray:
            vs = runner.evaluate(np.asarray(X).T, objective=objective_outputs)
            return np.array([cost_of(v) for v in vs])

        bounds = [(p.low, p.high) for p in st.parameters]
        res = differential_evolution(
            f,
            bounds,
            maxiter=st.samples or 100,
            popsize=st.population or 15,
            seed=st.seed,
            vectorized=True,
            updating="deferred",
            polish=False,
            tol=1e-8,
            x0=np.clip(runner.base_row(), *np.array(bounds).T),  # the base design, moved into the ranges
        )
        runner.evaluate(runner.base_row())
        # the local stage: SLSQP on the target cost from the evolution's best, constraints as constraints
        found = [v for v in runner.all_variants() if v.objective is not None and math.isfinite(v.objective)]
        found.sort(key=lambda v: (not feasible(st, v), v.objective))
        starts = [np.array([v.parameters[p.name] for p in st.parameters]) for v in found[:1]]
        polished = polish(
            runner, starts or [np.clip(res.x, *np.array(bounds).T)], objective=objective_outputs
        )
        extra = {"generations": int(res.nit), "polish": polished}
        return Ran(self.order(st, runner.all_variants()), extra)

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """The fit (the variant nearest the targets among those that keep every constraint, preferring
        one as good whose first-order optimality can be shown), a verdict and margin per target
        (``targets``), and, for a missed target, what stops the fit (``missed_because``): the
        constraints and bounds that hold it at a first-order point, or a search that stopped short."""
        base = variants[0] if variants and variants[0].key == variant_key(base_row(study)) else None
        fits = sorted(
            (v for v in variants if feasible(study, v) and v.objective is not None),
            key=lambda v: v.objective or 0.0,
        )
        best_v, proof = (fits[0] if fits else None), None
        by_key = {v.key: v for v in variants}
        for v in fits:  # a fit as good whose first-order optimality can be shown, if there is one
            if (v.objective or 0.0) > (best_v.objective or 0.0) * (1.0 + TIE) + TIE:  # type: ignore[union-attr]
                break
            proof = optimality(study, v, by_key)
            if proof is not None:
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
        if not missed:
            why = None
        elif proof is None:
            why = "the search stopped short: no gradient was stored at the fit"
        elif proof["measure"] > FIRST_ORDER:
            why = f"the search stopped short (first-order residual {proof['measure']:.2g})"
        elif proof["active"]:
            why = "the limits make it unreachable: the fit is held by " + ", ".join(
                a["name"] for a in proof["active"]
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
            "missed_because": why,
        }
        keep = {v.id for v in (best_v, base) if v is not None}
        return Found(out, frozenset(keep))

    def tables(self, result: StudyResult) -> list[Table]:
        st, f = result.study, result.findings
        out = [
            variant_table(result, f[k], t)
            for k, t in (("best", "optimum"), ("base", "base design"))
            if f.get(k)
        ]
        rows = []
        for t in f["targets"]:
            w = next(w for w in st.watched if w.key == t["output"])
            margin = t.get("margin")
            shown = w.show(abs(margin)) if margin is not None else None
            if margin is None or shown is None:
                verdict = "no value"
            elif t.get("holds", margin >= 0):
                verdict = f"holds ({shown:.3g} to spare)"
            else:
                verdict = f"MISSED by {shown:.3g}"
            rows.append(
                [
                    w.label,
                    w.show(t["target"]),
                    w.show(t["tolerance"]),
                    w.show(t["value"]),
                    verdict,
                    w.show(t["base_value"]),
                ]
            )
        out.append(
            Table(f"{st.name}: targets", ["output", "target", "tolerance", "fit", "verdict", "base"], rows)
        )
        if f.get("missed_because"):
            out.append(Table(f"{st.name}: why a target is missed", ["note"], [[f["missed_because"]]]))
        return out

    def plots(self, result: StudyResult) -> dict[str, Callable[[], Any]]:
        from mechdyn.studies import plots as sp

        return {"history.png": lambda: sp.history(result)} | parallel_plot(result)
