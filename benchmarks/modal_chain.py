"""Modal analysis of free torsional chains: mechdyn against dense eigh and openTorsion.

    python benchmarks/modal_chain.py            # N = 10, 100, 1000, 10^4 (all modes) and 10^5 (lowest 10)
    python benchmarks/modal_chain.py --quick    # N = 10, 100, 1000 and 10^5 (lowest 10), within a minute
    python benchmarks/modal_chain.py --json     # one JSON object with the times and ratios

Every case times the whole job from the element lists (build the model, assemble, solve) and checks
that the frequencies agree with the baselines (relative difference printed). Baselines measured in
the same run: dense ``scipy.linalg.eigh(K, M)`` on the same assembled matrices (solve only, so it is
flattered), mechdyn's own sparse shift-invert path for the lowest modes of the largest chain, and
openTorsion (``Assembly`` + ``undamped_modal_analysis``) where it is installed and
the size is practical (it solves the unsymmetric problem with a dense ``eig``).
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np
import scipy.linalg as sla
from _timing import best_time

from mechdyn.drivetrain import Disk, Drivetrain, Shaft, assemble, modal

OPENTORSION_MAX_N = 2000
DENSE_MAX_N = 10_000


def chain_data(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.uniform(0.5, 2.0, n) * 1e-2, rng.uniform(0.5, 2.0, n - 1) * 1e5


def mechdyn_modal(J: np.ndarray, k: np.ndarray, n_modes: int | None = None, solver: str = "auto"):
    disks = [Disk(f"d{i}", J[i]) for i in range(J.size)]
    shafts = [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i]) for i in range(k.size)]
    return modal(Drivetrain(disks, shafts), n_modes=n_modes, solver=solver)


def opentorsion_modal(J: np.ndarray, k: np.ndarray) -> np.ndarray:
    import opentorsion as ot

    asm = ot.Assembly(
        [ot.Shaft(i, i + 1, 0, 0, k=k[i]) for i in range(k.size)],
        disk_elements=[ot.Disk(i, J[i]) for i in range(J.size)],
    )
    lam, _ = asm.undamped_modal_analysis()
    return np.sqrt(np.clip(np.sort(np.real(lam)), 0, None))[1:]


def run_case(n: int, n_modes: int | None) -> dict:
    J, k = chain_data(n)
    t_md, res = best_time(lambda: mechdyn_modal(J, k, n_modes))
    omega = res.omega
    case: dict = {
        "n": n,
        "modes": "all" if n_modes is None else n_modes,
        "solver": res.solver,
        "mechdyn_s": t_md,
    }
    if n <= DENSE_MAX_N and n_modes is None:
        asm = assemble(res.drivetrain)
        K, M = asm.K.toarray(), np.diag(asm.mass)
        t_dense, lam = best_time(lambda: sla.eigh(K, M, eigvals_only=False)[0], budget=0.1, max_repeats=3)
        ref = np.sqrt(np.clip(lam, 0, None))[1:]
        case.update(
            dense_eigh_s=t_dense,
            ratio_vs_dense=t_dense / t_md,
            max_rel_diff_vs_dense=float(np.max(np.abs(omega / ref - 1))),
        )
    elif n_modes is not None:
        # lowest modes: the sparse shift-invert Lanczos path (ARPACK), timed the same way
        t_sp, ref_res = best_time(
            lambda: mechdyn_modal(J, k, n_modes, solver="sparse"), budget=0.1, max_repeats=2
        )
        case.update(
            sparse_s=t_sp,
            ratio_vs_sparse=t_sp / t_md,
            max_rel_diff_vs_sparse=float(np.max(np.abs(omega / ref_res.omega - 1))),
        )
    try:
        import opentorsion  # noqa: F401

        have_ot = True
    except ImportError:
        have_ot = False
    if have_ot and n <= OPENTORSION_MAX_N and n_modes is None:
        t_ot, ref = best_time(lambda: opentorsion_modal(J, k), budget=0.1, max_repeats=3)
        case.update(
            opentorsion_s=t_ot,
            ratio_vs_opentorsion=t_ot / t_md,
            max_rel_diff_vs_opentorsion=float(np.max(np.abs(omega / ref - 1))),
        )
    elif not have_ot:
        case["opentorsion"] = "not installed"
    return case


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="small sizes, finishes within a minute")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    args = p.parse_args(argv)
    cases: list[tuple[int, int | None]] = [(10, None), (100, None), (1000, None)]
    if not args.quick:
        cases.append((10_000, None))
    cases.append((100_000, 10))
    results = []
    for n, m in cases:
        results.append(run_case(n, m))
        if not args.json:
            r = results[-1]
            line = (
                f"N = {n:>6}  modes {r['modes']!s:>3}  mechdyn {r['mechdyn_s'] * 1e3:9.2f} ms ({r['solver']})"
            )
            for key, label in (
                ("dense", "dense eigh"),
                ("sparse", "sparse (ARPACK)"),
                ("opentorsion", "openTorsion"),
            ):
                if f"{key}_s" in r or f"{key}_eigh_s" in r:
                    t = r.get(f"{key}_s", r.get(f"{key}_eigh_s"))
                    ratio, diff = r[f"ratio_vs_{key}"], r[f"max_rel_diff_vs_{key}"]
                    line += f"  {label} {t * 1e3:9.2f} ms ({ratio:6.1f}×, Δ {diff:.1e})"
            print(line, flush=True)
    if args.json:
        print(json.dumps({"benchmark": "modal_chain", "quick": args.quick, "cases": results}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
