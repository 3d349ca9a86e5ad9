"""Loading a large drivetrain file, against solving it.

    python benchmarks/model_loading.py            # a 10 000-disk chain
    python benchmarks/model_loading.py --quick    # a 2 000-disk chain
    python benchmarks/model_loading.py --json     # one JSON object with the times and ratios

Writes a chain of N disks and N − 1 shafts as a model file (every value a quantity with its unit, as
a user writes it), then times ``mechdyn.load`` (read the TOML, validate every field, convert every
quantity to SI, build the immutable model) against what the command line then does by default on a
model that size: the lowest 20 flexible modes (``modal(model, n_modes=20)``, assembly included).
The baseline of the ratio is ``tomllib.loads`` of the same text: the part of loading no model
layer can avoid.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

import mechdyn
from mechdyn.drivetrain import modal


def chain_file(n: int, path: Path) -> Path:
    rng = np.random.default_rng(0)
    J, k = rng.uniform(0.5, 2.0, n) * 1e-2, rng.uniform(0.5, 2.0, n - 1) * 1e5
    parts = ['[model]\ntype = "drivetrain"\nname = "chain"\n']
    parts += [f'[[disks]]\nname = "d{i}"\ninertia = "{J[i]:.6g} kg*m^2"\n' for i in range(n)]
    parts += [
        f'[[shafts]]\nname = "s{i}"\ndisks = ["d{i}", "d{i + 1}"]\nstiffness = "{k[i]:.6g} N*m/rad"\n'
        for i in range(n - 1)
    ]
    path.write_text("\n".join(parts), encoding="utf-8")
    return path


def _time(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a 2 000-disk chain")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    n = 2_000 if args.quick else 10_000
    mechdyn.load(Path(__file__).resolve().parents[1] / "examples" / "turret_milling.toml")  # imports
    with tempfile.TemporaryDirectory() as tmp:
        path = chain_file(n, Path(tmp) / "chain.toml")
        text = path.read_text(encoding="utf-8")
        t_toml, _ = _time(lambda: tomllib.loads(text))
        t_load, loaded = _time(lambda: mechdyn.load(path))
    t_solve, res = _time(lambda: modal(loaded.model, n_modes=20))
    result = {
        "benchmark": "model_loading",
        "quick": args.quick,
        "disks": n,
        "file_bytes": len(text.encode()),
        "tomllib_parse_s": t_toml,
        "mechdyn_load_s": t_load,
        "ratio_load_vs_parse": t_load / t_toml,
        "modal_lowest_20_s": t_solve,
        "solver": res.solver,
        "ratio_load_vs_solve": t_load / t_solve,
    }
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    print(f"{n}-disk chain file ({result['file_bytes'] / 1e6:.1f} MB):")
    print(f"  tomllib.loads (baseline)      {t_toml:7.3f} s")
    print(
        f"  mechdyn.load                  {t_load:7.3f} s  ({result['ratio_load_vs_parse']:.2f}× the parse)"
    )
    print(
        f"  modal, lowest 20 modes        {t_solve:7.3f} s  ({res.solver}); load/solve {t_load / t_solve:.1f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
