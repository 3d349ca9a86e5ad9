"""What the exact counterweight solve saves: mechdyn's optimiser against a Latin-hypercube sampler.

    python benchmarks/balance.py           # press A: shaking force RMS, floor force range and RMS
    python benchmarks/balance.py --quick   # the same cases, a smaller sampler budget (under a minute)
    python benchmarks/balance.py --json    # one JSON object with the times and ratios

mechdyn: :func:`mechdyn.balance.balance` on press A (``examples/press_link_drive.toml``, on its mounts
``examples/press_on_mounts.toml`` for the floor force) with counterweights on the crank and the
rocker, each up to 100 t at up to 1.5 m from its pivot: the exact least-squares solve (RMS), or the
cone programme by cutting planes (the floor force, the rocking rocker's inertia included). Timed:
the optimisation alone (``solve_time_s``); the linear maps it shares with the sampler (one inverse
dynamics, the support's responses) are built
once, before either, and their time is reported apart.

Baseline, in the same run: a plain random sampler over the same bounds, scipy's Latin hypercube
(:class:`scipy.stats.qmc.LatinHypercube`, mass, radius and angle per link), evaluated in batches on
the same linear maps, doubling its sample count from 256 until its best design comes within 1 % of
the optimiser's objective value or its time budget (20 s per case with ``--quick``, 120 s without)
runs out. ``speedup`` is the sampler's time over the optimiser's; when the sampler does not reach the
value, the speedup is a lower bound (``reached`` false) and ``sampler_best_over_optimum`` says how
far it got. The sampler already uses the linear maps; ``sampler_by_inverse_dynamics_s_estimate`` is
what its samples would cost evaluated one by one by :func:`mechdyn.mechanism.inverse_dynamics`
(one such run, timed, times the sample count).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
TOLERANCE = 0.01


def _cases() -> list[dict]:
    import mechdyn
    from mechdyn.balance import CounterweightSlot

    sp = mechdyn.load(EXAMPLES / "press_on_mounts.toml")
    e = sp.settings.excitation
    slots = [CounterweightSlot(k, (0, "100 t"), (0, "1.5 m")) for k in ("crank", "rocker")]
    base = {"mechanism": e.mechanism, "slots": slots, "n_angles": e.angles}
    mounts = {"support": sp.model, "placement": e.placement}
    return [
        {"name": "press A, shaking force RMS", "objective": "shaking_force_rms", **base},
        {"name": "press A on mounts, floor force RMS", "objective": "floor_force_rms", **base, **mounts},
        {"name": "press A on mounts, floor force range", "objective": "floor_force_range", **base, **mounts},
    ]


def _sampler(ev, slots, objective: str, target: float, budget: float) -> dict:
    """Latin hypercube batches of doubling size until the best reaches ``target`` or time runs out."""
    from scipy.stats import qmc

    lo = np.array([v for s in slots for v in (s.mass[0], s.radius[0], -np.pi)])
    hi = np.array([v for s in slots for v in (s.mass[1], s.radius[1], np.pi)])
    L = len(slots)
    n, total, best, t0 = 256, 0, np.inf, time.perf_counter()
    seed = 0
    while True:
        z = qmc.LatinHypercube(d=lo.size, seed=seed).random(n)
        seed += 1
        designs = (lo + z * (hi - lo)).reshape(n, L, 3)
        for k in range(0, n, 4096):
            x = ev.coefficients(designs[k : k + 4096])
            best = min(best, float(ev.metrics(x, [objective])[objective].min()))
        total += n
        dt = time.perf_counter() - t0
        if best <= target * (1 + TOLERANCE) or dt > budget:
            return {
                "samples": total,
                "seconds": dt,
                "best": best,
                "reached": best <= target * (1 + TOLERANCE),
            }
        n *= 2


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a smaller sampler budget, within a minute")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)

    from mechdyn.balance import balance
    from mechdyn.balance.solve import Evaluator
    from mechdyn.mechanism import inverse_dynamics

    budget = 15.0 if args.quick else 120.0
    repeats = 3 if not args.quick else 1
    out = {"tolerance_relative": TOLERANCE, "sampler_budget_s": budget, "cases": []}
    for case in _cases():
        kw = {k: v for k, v in case.items() if k not in ("name", "mechanism", "slots", "objective")}
        balance(case["mechanism"], case["slots"], case["objective"], front=False, **kw)  # imports, caches
        runs = [
            balance(case["mechanism"], case["slots"], case["objective"], front=False, **kw)
            for _ in range(repeats)
        ]
        r = runs[-1]
        solve = statistics.median(x.solve_seconds for x in runs)
        target = r.after[case["objective"]]
        ev = Evaluator(r.influence, r.floor)
        s = _sampler(ev, r.slots, case["objective"], target, budget)
        t0 = time.perf_counter()
        inverse_dynamics(r.mechanism, case["n_angles"])  # what one sample costs without the linear maps
        one = time.perf_counter() - t0
        row = {
            "case": case["name"],
            "objective": case["objective"],
            "method": r.method,
            "setup_s": statistics.median(x.setup_seconds for x in runs),
            "optimiser_s": solve,
            "optimum": target,
            "before": r.before[case["objective"]],
            "sampler_s": s["seconds"],
            "sampler_samples": s["samples"],
            "reached": s["reached"],
            "sampler_best_over_optimum": s["best"] / target,
            "speedup": s["seconds"] / solve,
            "inverse_dynamics_s": one,
            "sampler_by_inverse_dynamics_s_estimate": one * s["samples"],
        }
        out["cases"].append(row)
        if not args.json:
            bound = "" if s["reached"] else " (sampler did not reach it: a lower bound)"
            print(
                f"{row['case']}: optimiser {solve * 1e3:.1f} ms ({r.method}) to {target:.4g}; "
                f"Latin hypercube {s['seconds']:.2f} s, {s['samples']} samples, best {s['best']:.4g} "
                f"({row['sampler_best_over_optimum']:.3f}× the optimum); "
                f"speedup {row['speedup']:.0f}×{bound}; "
                f"the same samples by inverse dynamics would take about "
                f"{row['sampler_by_inverse_dynamics_s_estimate']:.0f} s"
            )
    if args.json:
        json.dump(out, sys.stdout)
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
