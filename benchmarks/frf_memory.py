"""Peak memory of the forced response against the number of frequencies.

    python benchmarks/frf_memory.py            # 400 disks, 100 / 300 / 1000 frequencies; 10^5 disks × 1000
    python benchmarks/frf_memory.py --quick    # 200 disks, 50 / 100 / 200 frequencies; 2·10^4 disks × 200
    python benchmarks/frf_memory.py --json     # one JSON object with memory, times and ratios

``frf`` sums the modes over blocks of frequencies of at most 2¹⁸ modal amplitudes (or, where the
damping couples the modes, solves the dynamic stiffness frequency by frequency: LAPACK on blocks of
at most 2¹⁸ matrix entries, SuperLU for sparse models), so its peak memory is the model's matrices
plus the (frequencies × disks) result, never (frequencies × n × n). Each case is measured with
:mod:`tracemalloc` (NumPy reports its buffers to it). The baseline, measured in the same run, is
what the old all-at-once solve needs for its stacked matrix alone: frequencies × n² complex
entries; ``ratio_vs_stacked`` is that over the measured peak.

The large cases run a chain of 10⁵ disks (2·10⁴ with ``--quick``, built with :meth:`Drivetrain.chain`)
at 1 000 frequencies (200), asking for two disk angles and one shaft torque (``select``): with Rayleigh
damping over 1 Hz–10 kHz (one banded solve per frequency), and with modal damping ζ = 0.02 over a low
band (the modes below 4 × its top frequency and the residual of the others). Each reports its peak
traced memory against what every mode would need (n² mode-shape entries, the old path) and against
4 GB, its time, and the estimated truncation error.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import tracemalloc

import numpy as np

from mechdyn.drivetrain import Disk, Drivetrain, Shaft, frf
from mechdyn.drivetrain.response import ModalDamping, RayleighDamping


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


def large_case(n: int, n_f: int, damping: str) -> dict:
    """Peak memory and time of a long chain's response at two disks and one shaft."""
    import warnings

    rng = np.random.default_rng(0)
    J, k = rng.uniform(0.5, 2.0, n) * 1e-2, rng.uniform(0.5, 2.0, n - 1) * 1e5
    dt = Drivetrain.chain(J, k)
    dt.assembly  # noqa: B018 - assembled once, outside the measurement
    if damping == "rayleigh":
        f, how = np.geomspace(1.0, 1e4, n_f), RayleighDamping.from_ratios(10.0, 1000.0, 0.02)
    else:  # modal damping: a band low enough for the modes below 4 × its top to be a few hundred
        top = 1.0 if n >= 50_000 else 2.0
        f, how = np.geomspace(top / 100, top, n_f), ModalDamping(0.02)
    tracemalloc.start()
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the estimated truncation error is reported below
        r = frf(dt, f, {"d0": 1.0}, damping=how, select=("d0", f"d{n - 1}", "s0"))
    seconds = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    all_modes = n * n * 8
    return {
        "disks": n,
        "frequencies": n_f,
        "damping": damping,
        "method": r.method,
        "kept_modes": int(r.natural_frequencies_hz.size),
        "truncation_error_relative": r.truncation_error,
        "seconds": seconds,
        "peak_bytes": peak,
        "all_modes_bytes": all_modes,
        "ratio_all_modes_vs_peak": all_modes / peak,
        "within_4_GB": peak < 4e9,
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
    big, big_f = (20_000, 200) if args.quick else (100_000, 1000)
    large = [large_case(big, big_f, d) for d in ("rayleigh", "modal")]
    result = {
        "benchmark": "frf_memory",
        "quick": args.quick,
        "disks": n,
        "cases": cases,
        "peak_growth_bytes_per_frequency": growth,
        "stacked_growth_bytes_per_frequency": n * n * 16,
        "large": large,
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
    for c in large:
        print(
            f"{c['disks']} disks × {c['frequencies']} f, {c['damping']} damping: "
            f"peak {c['peak_bytes'] / 1e6:.0f} MB in {c['seconds']:.1f} s "
            f"(all modes alone: {c['all_modes_bytes'] / 1e9:.0f} GB); {c['method']}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
