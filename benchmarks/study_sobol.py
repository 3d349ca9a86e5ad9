"""A Sobol study of press A on its support: ~10^5 variants (mechanism + 1-DOF support, 360 angles).

    python benchmarks/study_sobol.py            # N = 8192 base samples, 10 parameters: 98 304 variants
    python benchmarks/study_sobol.py --quick    # N = 512: 6 144 variants, within a minute
    python benchmarks/study_sobol.py --json     # one JSON object with the times and ratios
    python benchmarks/study_sobol.py --dask     # also on a Dask LocalCluster of 2 workers

mechdyn: ``run_study`` of a Sobol study (examples/studies/press_sobol.toml's parameters plus the
machine's mass and the support's stiffness) into a fresh SQLite file: the variants go through the
compiled mechanism batch and the batched 1-DOF steady state in blocks, every block stored as it is
done. The share of the time spent writing the database is measured by timing its writes.

Baseline, measured in the same run: a loop over the single-design Python API, the way a script
without the study layer does it — for each variant, build the model from its files, run the
``support`` analysis (inverse dynamics, exact steady state, modes and start-up) and read the
transmitted-force range; timed on a subset and scaled to the study's size. The outputs of the two
are compared on that subset.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from mechdyn.io.modelfile import load_source
from mechdyn.registry import get
from mechdyn.studies import load_study, run_study
from mechdyn.studies.paths import ModelTree
from mechdyn.studies.spec import Parameter
from mechdyn.studies.storage import StudyStore
from mechdyn.studies.study import Study

ROOT = Path(__file__).resolve().parents[1]
STUDY = ROOT / "examples" / "studies" / "press_sobol.toml"


def study(samples: int) -> Study:
    base = load_study(STUDY)
    tree = ModelTree(base.source)
    extra = [
        *Parameter.from_spec(tree, "machine.mass", range="±20 %"),
        *Parameter.from_spec(tree, "support.stiffness", range="±20 %"),
    ]
    from dataclasses import replace

    return replace(
        base,
        name=f"benchmark-sobol-{samples}",
        parameters=(*base.parameters, *extra),
        samples=samples,
        curves=0,
        definition={**base.definition, "study": {**base.definition["study"], "samples": samples}},
    )


def loop(st: Study, X: np.ndarray) -> tuple[float, list[float]]:
    """The single-design API, variant by variant; returns the time per variant and the outputs."""
    analysis = get("support")
    tree = st.tree
    out = []
    t0 = time.perf_counter()
    for row in X:
        values = {}
        for p, x in zip(st.parameters, row, strict=True):
            values.update(p.file_values(float(x)))
        result = analysis.run(load_source(tree.variant(values)), cycles=1)
        out.append(result.summary()["transmitted_force_range_N"])
    return (time.perf_counter() - t0) / len(X), out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 512 (6 144 variants), within a minute")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--dask", action="store_true", help="also run on a Dask LocalCluster with 2 workers")
    args = ap.parse_args(argv)
    samples = 512 if args.quick else 8192
    st = study(samples)
    writes = [0.0]
    add = StudyStore.add

    def timed_add(self, study_id, rows):  # the database's share of the time
        t0 = time.perf_counter()
        try:
            return add(self, study_id, rows)
        finally:
            writes[0] += time.perf_counter() - t0

    StudyStore.add = timed_add  # type: ignore[method-assign]
    with tempfile.TemporaryDirectory() as tmp:
        run_study(study(8), str(Path(tmp) / "warm.db"))  # compile and import before timing
        writes[0] = 0.0
        t0 = time.perf_counter()
        result = run_study(st, str(Path(tmp) / "sobol.db"))
        t_study = time.perf_counter() - t0
        t_db = writes[0]
        n = len(result.variants)
        subset = [v for v in result.variants[:: max(1, n // (8 if args.quick else 20))]]
        X = np.array([[v.parameters[p.name] for p in st.parameters] for v in subset])
        per_variant, loop_out = loop(st, X)
        diff = max(
            abs(a - v.outputs["transmitted_force_range_N"]) / abs(a)
            for a, v in zip(loop_out, subset, strict=True)
        )
        doc = {
            "benchmark": "study_sobol",
            "quick": args.quick,
            "variants": n,
            "parameters": len(st.parameters),
            "angles": 360,
            "study_s": t_study,
            "variants_per_s": n / t_study,
            "database_write_s": t_db,
            "database_share": t_db / t_study,
            "loop_per_variant_s": per_variant,
            "loop_estimated_s": per_variant * n,
            "ratio_vs_loop": per_variant * n / t_study,
            "loop_subset": len(subset),
            "max_rel_diff_vs_loop": diff,
            "failed": result.failed,
        }
        if args.dask:
            StudyStore.add = add  # type: ignore[method-assign]
            t0 = time.perf_counter()
            on_dask = run_study(st, str(Path(tmp) / "dask.db"), dask="local")
            doc["dask_local_2_workers_s"] = time.perf_counter() - t0
            doc["dask_ratio_vs_in_process"] = t_study / doc["dask_local_2_workers_s"]
            doc["dask_identical"] = [v.outputs for v in on_dask.variants] == [
                v.outputs for v in result.variants
            ]
    if args.json:
        print(json.dumps(doc))
        return 0
    print(
        f"Sobol study of press A on its support: {n} variants × 360 angles, {len(st.parameters)} parameters"
    )
    print(f"  mechdyn study         {t_study:8.2f} s   ({n / t_study:,.0f} variants/s)")
    print(f"  of which DB writes    {t_db:8.2f} s   ({100 * t_db / t_study:.1f} %)")
    print(f"  single-design loop    {per_variant * n:8.1f} s   (estimated from {len(subset)} variants)")
    print(f"  ratio                 {per_variant * n / t_study:8.1f} ×   (outputs agree to {diff:.1e})")
    if args.dask:
        print(
            f"  Dask LocalCluster(2)  {doc['dask_local_2_workers_s']:8.2f} s   "
            f"(×{doc['dask_ratio_vs_in_process']:.2f} of in-process; identical: {doc['dask_identical']})"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
