"""Forced response and new small variants of free torsional chains, against the bare algorithms.

    python benchmarks/frf_speed.py            # FRF at 10 to 3000 disks; banded to 10^5 disks; study block
    python benchmarks/frf_speed.py --quick    # 10, 100, 400 disks, banded to 10^4, fewer repeats: a minute
    python benchmarks/frf_speed.py --json     # one JSON object with the times and ratios

Three measurements, each against baselines timed in the same run:

* **FRF**, 1 000 log-spaced frequencies, a unit torque at the first disk, modal damping ζ = 0.02.
  ``mechdyn`` is :func:`mechdyn.drivetrain.frf` from the built model (assembly, modes, sum), asked for
  what the baseline computes: every disk's angle (``select``; the element loads are left out).
  ``plain`` is modal superposition written here in a few lines on the same assembled matrices:
  ``scipy.linalg.eigh(K, M)``, then X = Φ diag(1/(λ − ω² + 2iζ√λ ω)) Φᵀ F for every frequency at once,
  disk angles only. ``direct`` is mechdyn's own frequency-by-frequency solve (``method="direct"``,
  the only one before; up to 400 disks, 100 with ``--quick``). ``opentorsion`` is openTorsion's
  ``ss_response`` with the same (modal) damping matrix, where installed and the size is practical (it
  inverts the dynamic stiffness at every frequency; up to 400 disks, 100 with ``--quick``). Each
  baseline's largest difference from mechdyn, relative to the largest amplitude, is reported.
* **Rayleigh damping on long chains** (1 000, 3 000, 10⁴, 10⁵ disks; 1 000 and 10⁴ with ``--quick``),
  1 000 log-spaced frequencies from 1 Hz to 10 kHz, the response of two disks and one shaft asked for
  (``select``). ``mechdyn`` is :func:`mechdyn.drivetrain.frf` (one banded solve per frequency); the
  baseline, ``bare_banded``, is that algorithm written here on the same assembled matrices: the
  tridiagonal K + iωC − ω²M of each frequency solved by LAPACK ``zgtsv`` (:func:`scipy.linalg.solve_banded`),
  the same two disk angles kept.
* **A study block of 10-disk variants**: 1 000 variants of a 10-disk chain file whose 10 inertias and
  9 stiffnesses vary, evaluated as a design study evaluates them (:class:`mechdyn.studies.Evaluator`
  with the ``modal`` analysis: its batch path), per variant; against the bare tridiagonal solve of
  each variant's M^-½ K M^-½ (``scipy.linalg.eigh_tridiagonal``, one call per variant, matrices
  prepared beforehand), and openTorsion (``Assembly`` + ``undamped_modal_analysis`` per variant).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np
import scipy.linalg as sla
from _timing import best_time

from mechdyn.drivetrain import Disk, Drivetrain, Shaft, frf
from mechdyn.drivetrain.response import ModalDamping

ZETA = 0.02
FREQUENCIES = np.geomspace(1.0, 1e4, 1000)
COMPARED_UP_TO = 400  # the direct solve and openTorsion take seconds to minutes beyond
COMPARED_UP_TO_QUICK = 100  # at 400 disks they take 15-20 s each


def chain_data(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.uniform(0.5, 2.0, n) * 1e-2, rng.uniform(0.5, 2.0, n - 1) * 1e5


def chain(J: np.ndarray, k: np.ndarray) -> Drivetrain:
    disks = [Disk(f"d{i}", J[i]) for i in range(J.size)]
    return Drivetrain(disks, [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i]) for i in range(k.size)])


def plain_superposition(K: np.ndarray, M: np.ndarray, F: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Modal superposition in its textbook form (Ewins, *Modal Testing*, §2.3): all modes at once."""
    lam, Phi = sla.eigh(K, M)
    lam = np.clip(lam, 0.0, None)
    Y = (Phi.T @ F) / (lam - w[:, None] ** 2 + 2j * ZETA * np.sqrt(lam) * w[:, None])
    return Y @ Phi.T


def opentorsion_frf(J: np.ndarray, k: np.ndarray, C: np.ndarray, w: np.ndarray) -> np.ndarray:
    import opentorsion as ot

    asm = ot.Assembly(
        [ot.Shaft(i, i + 1, 0, 0, k=k[i]) for i in range(k.size)],
        disk_elements=[ot.Disk(i, J[i]) for i in range(J.size)],
    )
    F = np.zeros((J.size, w.size), dtype=complex)
    F[0] = 1.0
    q, _ = asm.ss_response(F, w, C=C)
    return q.T


def _diff(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


def frf_case(n: int, quick: bool) -> dict:
    J, k = chain_data(n)
    model = chain(J, k)
    asm = model.assembly
    w = 2 * np.pi * FREQUENCIES
    budget, repeats = (0.3, 3) if quick else (1.0, 5)
    t_md, res = best_time(
        lambda: frf(model, FREQUENCIES, {"d0": 1.0}, damping=ModalDamping(ZETA), select=model.disk_names),
        budget,
        repeats,
    )
    K, M = asm.K.toarray(), np.diag(asm.mass)
    F = np.zeros(n)
    F[0] = 1.0
    t_plain, x_plain = best_time(lambda: plain_superposition(K, M, F, w), budget, repeats)
    case: dict = {
        "disks": n,
        "frequencies": FREQUENCIES.size,
        "method": res.method,
        "mechdyn_s": t_md,
        "plain_superposition_s": t_plain,
        "ratio_vs_plain_superposition": t_md / t_plain,
        "max_rel_diff_vs_plain_superposition": _diff(res.angles, x_plain),
    }
    if n <= (COMPARED_UP_TO_QUICK if quick else COMPARED_UP_TO):
        t_direct, direct = best_time(
            lambda: frf(model, FREQUENCIES, {"d0": 1.0}, damping=ModalDamping(ZETA), method="direct"), 0.1, 1
        )
        case.update(
            direct_s=t_direct,
            ratio_direct_vs_mechdyn=t_direct / t_md,
            max_rel_diff_vs_direct=_diff(res.angles, direct.angles),
        )
        try:
            import opentorsion  # noqa: F401
        except ImportError:
            case["opentorsion"] = "not installed"
        else:
            from mechdyn.drivetrain.modal import modal

            modes = modal(asm)
            MPhi = asm.mass[:, None] * modes.reduced_shapes
            C = (MPhi * (2 * ZETA * modes.omega)) @ MPhi.T
            t_ot, x_ot = best_time(lambda: opentorsion_frf(J, k, C, w), 0.1, 1)
            case.update(
                opentorsion_s=t_ot,
                ratio_opentorsion_vs_mechdyn=t_ot / t_md,
                max_rel_diff_vs_opentorsion=_diff(res.angles, x_ot),
            )
    return case


def rayleigh_case(n: int, quick: bool) -> dict:
    """The banded direct solve of a long chain against the same algorithm written bare."""
    from mechdyn.drivetrain.response import RayleighDamping

    J, k = chain_data(n)
    model = Drivetrain.chain(J, k)
    asm = model.assembly
    damping = RayleighDamping.from_ratios(10.0, 1000.0, ZETA)
    w = 2 * np.pi * FREQUENCIES
    picked = ("d0", f"d{n - 1}", "s0")
    budget, repeats = (0.3, 2) if quick else (1.0, 3)
    t_md, res = best_time(
        lambda: frf(model, FREQUENCIES, {"d0": 1.0}, damping=damping, select=picked), budget, repeats
    )
    K, M = asm.K, asm.mass_diagonal
    kd, ko = K.diagonal(), K.diagonal(1)
    cd, co = damping.alpha * M + damping.beta * kd, damping.beta * ko

    def bare() -> np.ndarray:
        out = np.empty((w.size, 2), dtype=complex)
        F = np.zeros(n, dtype=complex)
        F[0] = 1.0
        ab = np.empty((3, n), dtype=complex)
        for i, wi in enumerate(w):
            ab[1] = kd + 1j * wi * cd - wi**2 * M
            ab[0, 1:] = ab[2, :-1] = ko + 1j * wi * co
            x = sla.solve_banded((1, 1), ab, F, overwrite_ab=True, check_finite=False)
            out[i] = x[0], x[-1]
        return out

    t_bare, x_bare = best_time(bare, budget, repeats)
    return {
        "disks": n,
        "frequencies": FREQUENCIES.size,
        "method": res.method,
        "mechdyn_s": t_md,
        "bare_banded_s": t_bare,
        "ratio_vs_bare_banded": t_md / t_bare,
        "max_rel_diff_vs_bare_banded": _diff(res.angles, x_bare),
    }


def _chain_file(folder: Path, J: np.ndarray, k: np.ndarray) -> Path:
    lines = ['[model]\ntype = "drivetrain"\nname = "10-disk chain"\n']
    lines += [f'[[disks]]\nname = "d{i}"\ninertia = "{float(J[i])!r} kg*m^2"\n' for i in range(J.size)]
    lines += [
        f'[[shafts]]\nname = "s{i}"\ndisks = ["d{i}", "d{i + 1}"]\nstiffness = "{float(k[i])!r} N*m/rad"\n'
        for i in range(k.size)
    ]
    path = folder / "chain10.toml"
    path.write_text("\n".join(lines))
    return path


def study_block_case(quick: bool) -> dict:
    from mechdyn.io.modelfile import read
    from mechdyn.studies import Evaluator, ModelTree, Parameter

    n, V = 10, 1000
    J, k = chain_data(n)
    with tempfile.TemporaryDirectory() as folder:
        source = read(_chain_file(Path(folder), J, k))
        tree = ModelTree(source)
        paths = [
            *(f"disks.d{i}.inertia" for i in range(n)),
            *(f"shafts.s{i}.stiffness" for i in range(n - 1)),
        ]
        params = [q for path in paths for q in Parameter.from_spec(tree, path, range="±30 %")]
    rng = np.random.default_rng(1)
    X = np.array([[rng.uniform(p.low, p.high) for p in params] for _ in range(V)])
    outputs = [f"frequencies_hz.{m}" for m in range(1, n)]
    budget, repeats = (0.5, 3) if quick else (2.0, 5)

    def block() -> list:
        ev = Evaluator(source, "modal", params, outputs)
        out = ev(X)
        assert ev.batch, "the study block left the batch path"
        return out

    t_block, got = best_time(block, budget, repeats)
    hz = np.array([[e.outputs[o] for o in outputs] for e in got])
    # the bare solve of every variant: A = M^-½ K M^-½ is tridiagonal for a chain, prepared beforehand
    Jv, kv = X[:, :n], X[:, n:]
    d = 1.0 / np.sqrt(Jv)
    diag = np.zeros((V, n))
    diag[:, :-1] += kv
    diag[:, 1:] += kv
    diag *= d**2
    off = -kv * d[:, :-1] * d[:, 1:]

    def bare() -> np.ndarray:
        return np.array([sla.eigh_tridiagonal(diag[v], off[v], eigvals_only=True) for v in range(V)])

    t_bare, lam = best_time(bare, budget, repeats)
    hz_bare = np.sqrt(np.clip(lam[:, 1:], 0.0, None)) / (2 * np.pi)
    case: dict = {
        "disks": n,
        "variants": V,
        "parameters": len(params),
        "mechdyn_study_block_per_variant_s": t_block / V,
        "bare_eigh_tridiagonal_per_variant_s": t_bare / V,
        "ratio_vs_bare": t_block / t_bare,
        "max_rel_diff_vs_bare": float(np.abs(hz / hz_bare - 1).max()),
    }
    try:
        import opentorsion as ot
    except ImportError:
        case["opentorsion"] = "not installed"
        return case
    some = 50 if quick else 200

    def with_ot() -> list:
        out = []
        for v in range(some):
            asm = ot.Assembly(
                [ot.Shaft(i, i + 1, 0, 0, k=kv[v, i]) for i in range(n - 1)],
                disk_elements=[ot.Disk(i, Jv[v, i]) for i in range(n)],
            )
            out.append(asm.undamped_modal_analysis()[0])
        return out

    t_ot, lam_ot = best_time(with_ot, budget, repeats)
    w_ot = np.sqrt(np.clip(np.sort(np.real(np.array(lam_ot)), axis=1), 0, None))[:, 1:] / (2 * np.pi)
    case.update(
        opentorsion_per_variant_s=t_ot / some,
        ratio_opentorsion_vs_mechdyn=(t_ot / some) / (t_block / V),
        max_rel_diff_vs_opentorsion=float(np.abs(hz[:some] / w_ot - 1).max()),
    )
    return case


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="10, 100 and 400 disks, fewer repeats")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    args = p.parse_args(argv)
    sizes = [10, 100, 400] + ([] if args.quick else [1000, 3000])
    cases = []
    for n in sizes:
        cases.append(frf_case(n, args.quick))
        if not args.json:
            c = cases[-1]
            ratio, diff = c["ratio_vs_plain_superposition"], c["max_rel_diff_vs_plain_superposition"]
            line = (
                f"FRF {n:>5} disks × {c['frequencies']} f: mechdyn {c['mechdyn_s'] * 1e3:8.1f} ms, plain "
                f"superposition {c['plain_superposition_s'] * 1e3:8.1f} ms ({ratio:.2f}×, Δ {diff:.1e})"
            )
            if "direct_s" in c:
                line += f", direct {c['direct_s'] * 1e3:.0f} ms (Δ {c['max_rel_diff_vs_direct']:.1e})"
            if "opentorsion_s" in c:
                diff = c["max_rel_diff_vs_opentorsion"]
                line += f", openTorsion {c['opentorsion_s'] * 1e3:.0f} ms (Δ {diff:.1e})"
            print(line, flush=True)
    banded = []
    for n in [1000, 10_000] if args.quick else [1000, 3000, 10_000, 100_000]:
        banded.append(rayleigh_case(n, args.quick))
        if not args.json:
            c = banded[-1]
            print(
                f"Rayleigh {n:>6} disks × {c['frequencies']} f: mechdyn {c['mechdyn_s'] * 1e3:8.1f} ms, bare "
                f"banded {c['bare_banded_s'] * 1e3:8.1f} ms ({c['ratio_vs_bare_banded']:.2f}×, "
                f"Δ {c['max_rel_diff_vs_bare_banded']:.1e})",
                flush=True,
            )
    block = study_block_case(args.quick)
    if not args.json:
        print(
            f"study block, {block['variants']} variants of {block['disks']} disks: "
            f"{block['mechdyn_study_block_per_variant_s'] * 1e6:.1f} µs per variant, bare eigh_tridiagonal "
            f"{block['bare_eigh_tridiagonal_per_variant_s'] * 1e6:.1f} µs ({block['ratio_vs_bare']:.2f}×, "
            f"Δ {block['max_rel_diff_vs_bare']:.1e})"
            + (
                f", openTorsion {block['opentorsion_per_variant_s'] * 1e6:.0f} µs"
                if "opentorsion_per_variant_s" in block
                else ""
            )
        )
    if args.json:
        doc = {
            "benchmark": "frf_speed",
            "quick": args.quick,
            "frf": cases,
            "rayleigh_banded": banded,
            "study_block": block,
        }
        print(json.dumps(doc, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
