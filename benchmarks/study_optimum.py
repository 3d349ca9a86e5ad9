"""The press link relocation (examples/studies/press_link_relocation.toml): how far each box's optimum
lowers the floor force, and what it costs, against a plain sampler given the same evaluations.

    python benchmarks/study_optimum.py           # the shipped study: boxes ±10 / ±20 / ±30 %
    python benchmarks/study_optimum.py --quick   # boxes ±10 % and ±30 %, within a minute
    python benchmarks/study_optimum.py --json    # one JSON object with the times and ratios

mechdyn: ``run_studies`` of the study file into a fresh SQLite file (the global TPE stage, then the
constrained SLSQP polish from its best designs, each box starting from the last box's optimum), timed
as a whole; per box the reduction of the transmitted-force range against the base design, the
evaluations used, whether the stroke holds and the first-order optimality measure.

Baseline, in the same run: a plain sampler, Optuna's TPE with the stroke as a constraint (Optuna's
``Trial.set_constraint``) and no polish (the base design its first trial, as in the study), given as
many evaluations per box as mechdyn used there, each evaluated through the same batched evaluator. Its
best feasible design gives the baseline's reduction (none where it found no design that holds the
stroke); the ratio of the two reductions, where the baseline improved on the base at all, says how much
farther the polished optimum goes.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from mechdyn.studies import Evaluator, load_studies
from mechdyn.studies.run import run_studies
from mechdyn.studies.study import Study

ROOT = Path(__file__).resolve().parents[1]
STUDY = ROOT / "examples" / "studies" / "press_link_relocation.toml"
OBJECTIVE = "transmitted_force_range_N"


def plain_sampler(study: Study, trials: int, base: float) -> dict:
    """Optuna TPE with the study's constraints as constraints and no polish, ``trials`` evaluations in
    blocks of the study's batch; the best feasible objective and its reduction against ``base``."""
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    ev = Evaluator(
        study.source, study.analysis, study.parameters, [w.key for w in study.watched], study.options
    )

    def violation(outputs: dict) -> list[float]:
        return [c.violation(outputs.get(c.output.key)) for c in study.constraints]

    sampler = optuna.samplers.TPESampler(seed=study.seed, multivariate=True)
    opt = optuna.create_study(direction="minimize", sampler=sampler)
    opt.enqueue_trial({p.name: float(p.base) for p in study.parameters})  # the base first, as the study
    dists = {
        p.name: optuna.distributions.FloatDistribution(float(p.low), float(p.high)) for p in study.parameters
    }
    best = math.inf
    t0 = time.perf_counter()
    done = feasible = 0
    while done < trials:
        batch = [opt.ask(dists) for _ in range(min(study.batch, trials - done))]
        X = np.array([[t.params[p.name] for p in study.parameters] for t in batch])
        for t, e in zip(batch, ev(X), strict=True):
            y = e.outputs.get(OBJECTIVE) if e.status == "ok" else None
            if y is None or not math.isfinite(y):
                opt.tell(t, state=optuna.trial.TrialState.FAIL)
                continue
            v = violation(e.outputs)
            for i, x in enumerate(v):  # feasible where ≤ 0, as the study's own optimizer
                t.set_constraint(f"{i + 1}", x)
            opt.tell(t, y)
            if max(v, default=0.0) <= 0:
                feasible += 1
                best = min(best, y)
        done += len(batch)
    return {
        "seconds": time.perf_counter() - t0,
        "evaluations": done,
        "feasible": feasible,
        "best_N": best if math.isfinite(best) else None,
        "reduction_percent": 100 * (base - best) / base if math.isfinite(best) else None,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="boxes ±10 %% and ±30 %% only, within a minute")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)

    studies = load_studies(STUDY)
    if args.quick:
        studies = [studies[0], studies[-1]]
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        results = run_studies(studies, str(Path(tmp) / "optimum.db"))
        seconds = time.perf_counter() - t0
    boxes = []
    for r in results:
        f = r.findings
        base = f["base"]["outputs"][OBJECTIVE]
        best = f["best"]["outputs"][OBJECTIVE]
        evaluations = len([v for v in r.variants if v.status == "ok"])
        baseline = plain_sampler(r.study, evaluations, base)
        ours = 100 * (base - best) / base
        boxes.append(
            {
                "box": r.study.name.removeprefix(r.study.family).strip() or r.study.name,
                "study": r.study.name,
                "base_N": base,
                "best_N": best,
                "reduction_percent": ours,
                "constraints_hold": all(c["holds"] for c in f["best"]["constraints"]),
                "evaluations": evaluations,
                "optimality": (f.get("optimality") or {}).get("measure"),
                "plain_sampler": baseline,
                # only where the plain sampler found a better feasible design than the base
                "reduction_ratio_vs_plain": (
                    ours / baseline["reduction_percent"] if (baseline["reduction_percent"] or 0) > 0 else None
                ),
            }
        )
    doc = {
        "benchmark": "study_optimum",
        "quick": args.quick,
        "study": str(STUDY.relative_to(ROOT)),
        "seconds": seconds,
        "plain_sampler_seconds": sum(b["plain_sampler"]["seconds"] for b in boxes),
        "boxes": boxes,
    }
    if args.json:
        print(json.dumps(doc, indent=2))
        return 0
    plain_s = doc["plain_sampler_seconds"]
    print(f"{doc['study']}: {len(boxes)} boxes in {seconds:.1f} s (plain sampler {plain_s:.1f} s)")
    header = ("box", 8), ("reduction %", 12), ("evaluations", 12), ("stroke holds", 13), ("plain TPE %", 12)
    print(" ".join(f"{h:>{w}}" for h, w in (*header, ("ratio", 6))))

    def cell(x: float | None) -> str:
        return "—" if x is None else f"{x:.2f}"

    for b in boxes:
        plain, ratio = b["plain_sampler"]["reduction_percent"], b["reduction_ratio_vs_plain"]
        print(
            f"{b['box']:>8} {b['reduction_percent']:12.2f} {b['evaluations']:12d} "
            f"{b['constraints_hold']!s:>13} {cell(plain):>12} {cell(ratio):>6}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
