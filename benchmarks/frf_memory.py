"""Peak memory of the forced response against the number of frequencies.

    python benchmarks/frf_memory.py            # 400 disks, 100 / 300 / 1000 frequencies
    python benchmarks/frf_memory.py --quick    # 200 disks, 50 / 100 / 200 frequencies
    python benchmarks/frf_memory.py --json     # one JSON object with memory, times and ratios

``frf`` sums the modes over blocks of frequencies of at most 2¹⁸ modal amplitudes (or, where the
damping couples the modes, solves the dynamic stiffness frequency by frequency: LAPACK on blocks of
at most 2¹⁸ matrix entries, SuperLU for sparse models), so its peak memory is the model's matrices
plus the (frequencies × disks) result, never (frequencies × n × n). Each case is measured with
:mod:`tracemalloc` (NumPy reports its buffers to it). The baseline, measured in the same run, is
what the old all-at-once solve needs for its stacked matrix alone: frequencies × n² complex
entries; ``ratio_vs_stacked`` is that over the measured peak.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import tracemalloc

import numpy as np

from mechdyn.drivetrain import Disk, Drivetrain, Shaft, frf


def chain(n: int) -> Drivetrain:
    rng = np.random.default_rng(0)
    J, k = rng.uniform(0.5, 2.0, n) * 1e-2, rng.uniform(0.5, 2.0, n - 1) * 1e5
    disks = [Disk(f"d{i}", J[i]) for i in range(n)]
    return Drivetrain(disks, [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i]) for i in range(n - 1)])


def measure(dt: Drivetrain, n_f: int) -> dict:
    f = np.geomspace(0.1, 50.0, n_f)
    dt.assembly  # noqa: B018 - assembled once, outside the measurement
    tracemalloc.start()
    t0 = time.perf_counter()
    r = frf(dt, f, {"d0": 1.0}, outputs=("d0",))
    seconds = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    n = len(dt.disks)
    stacked = n_f * n * n * 16
    return {
        "frequencies": n_f,
        "peak_bytes": peak,
        "result_bytes": int(r.angles.nbytes + r.element_loads.nbytes),
        "seconds": seconds,
        "stacked_matrix_bytes": stacked,
        "ratio_vs_stacked": stacked / peak,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="200 disks, up to 200 frequencies")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    n, counts = (200, (50, 100, 200)) if args.quick else (400, (100, 300, 1000))
    dt = chain(n)
    cases = [measure(dt, nf) for nf in counts]
    growth = (cases[-1]["peak_bytes"] - cases[0]["peak_bytes"]) / (counts[-1] - counts[0])
    result = {
        "benchmark": "frf_memory",
        "quick": args.quick,
        "disks": n,
        "cases": cases,
        "peak_growth_bytes_per_frequency": growth,
        "stacked_growth_bytes_per_frequency": n * n * 16,
    }
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    print(f"frf of a {n}-disk chain:")
    for c in cases:
        print(
            f"  {c['frequencies']:5d} frequencies: peak {c['peak_bytes'] / 1e6:7.1f} MB"
            f" in {c['seconds']:6.2f} s"
            f"  (the stacked solve's matrix alone: {c['stacked_matrix_bytes'] / 1e6:8.1f} MB,"
            f" {c['ratio_vs_stacked']:.1f}×)"
        )
    print(
        f"  peak grows by {growth / 1e3:.1f} kB per frequency "
        f"(the stacked solve: {n * n * 16 / 1e3:.0f} kB per frequency)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
