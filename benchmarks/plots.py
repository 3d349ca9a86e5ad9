"""What `--plots` costs: each example's command timed with and without its plots.

    python benchmarks/plots.py           # every example model, its first analysis
    python benchmarks/plots.py --quick   # three examples (a mechanism, a machine on mounts, a drivetrain)
    python benchmarks/plots.py --json    # one JSON object with the times and ratios

mechdyn: ``mechdyn ANALYSIS FILE --plots DIR`` (the analysis, its tables, the run stored in a fresh
SQLite file, then every plot drawn and saved as PNG), timed as the command a user types: a new
process, its imports included. Baseline, in the same run: the same command without ``--plots``. The
two run in turn (without, with, without, with, ...: three pairs, two with ``--quick``), and the ratio
is the median of the pairs' ratios, so that a machine whose speed drifts does not move it; the times
are the medians. At most 1.5 is the aim: a run with plots at most half again as long as one without.
``plot_seconds`` is the difference, the time the plots add.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
QUICK = ("press_link_drive.toml", "press_on_mounts.toml", "turret_milling.toml")


def _cases(quick: bool) -> list[tuple[str, Path]]:
    """(analysis, model file): each example with the first analysis registered for its type."""
    from mechdyn.io.modelfile import read
    from mechdyn.registry import analyses

    files = [EXAMPLES / n for n in QUICK] if quick else sorted(EXAMPLES.glob("*.toml"))
    out = []
    for path in files:
        kind = read(path).model_type
        name = next((n for n, a in analyses().items() if kind in a.model_types), None)
        if name is not None:
            out.append((name, path))
    return out


def _run(args: list[str]) -> float:
    """Wall seconds of one ``mechdyn`` command in a new process, its output discarded."""
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "mechdyn", *args], capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if done.returncode not in (0, 2):
        raise RuntimeError(f"mechdyn {' '.join(args)} failed:\n{done.stderr}")
    return dt


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="three examples, within a minute")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        db = str(Path(tmp) / "plots.db")
        for analysis, path in _cases(args.quick):
            plain = [analysis, str(path), "--db", db]
            pairs = [
                (_run(plain), _run([*plain, "--plots", str(Path(tmp) / path.stem)]))
                for _ in range(2 if args.quick else 3)
            ]
            without = statistics.median(a for a, _ in pairs)
            with_plots = statistics.median(b for _, b in pairs)
            ratio = statistics.median(b / a for a, b in pairs)
            plots = len(list((Path(tmp) / path.stem).glob("*.png")))
            rows.append(
                {
                    "example": path.name,
                    "analysis": analysis,
                    "plots": plots,
                    "seconds_without_plots": without,
                    "seconds_with_plots": with_plots,
                    "plot_seconds": with_plots - without,
                    "ratio": ratio,
                }
            )
    doc = {
        "benchmark": "plots",
        "quick": args.quick,
        "examples": rows,
        "ratio_max": max(r["ratio"] for r in rows),
        "ratio_median": sorted(r["ratio"] for r in rows)[len(rows) // 2],
    }
    if args.json:
        print(json.dumps(doc, indent=2))
        return 0
    print(f"{'example':32} {'analysis':10} {'plots':>5} {'without [s]':>12} {'with [s]':>10} {'ratio':>6}")
    for r in rows:
        print(
            f"{r['example']:32} {r['analysis']:10} {r['plots']:5d} {r['seconds_without_plots']:12.3f} "
            f"{r['seconds_with_plots']:10.3f} {r['ratio']:6.2f}"
        )
    print(f"ratio: median {doc['ratio_median']:.2f}, largest {doc['ratio_max']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
