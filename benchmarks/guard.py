"""Regression guard: the benchmarks' ratios against the figures recorded for the previous release.

    python benchmarks/guard.py                # run every guarded benchmark, compare, print a table
    python benchmarks/guard.py --quick        # only the benchmarks that take under half a minute
    python benchmarks/guard.py --only modal_chain --only small_model
    python benchmarks/guard.py --repeat 3     # each benchmark three times, each figure's median
    python benchmarks/guard.py --record       # rewrite baseline.json from this run (a release)
    python benchmarks/guard.py --json         # the comparison as one JSON object

Each benchmark runs as ``python benchmarks/NAME.py --quick --json`` in a fresh process. The guard reads
the figures listed in :data:`GUARDED`: ratios against a baseline measured in the same run (mechdyn
against a bare NumPy/SciPy solve, a loop, a stacked matrix), never absolute times, which depend on the
machine; the few absolute figures (a throughput, bytes per variant) say so in their note. Each is
compared with the figure recorded in ``benchmarks/baseline.json`` for the previous release, in the
direction that is better for it (a time ratio mechdyn / baseline: lower is better; a speed-up baseline /
mechdyn: higher is better):

    worse = current / recorded − 1    (lower is better)
    worse = recorded / current − 1    (higher is better)

and the guard exits with status 1 when some ``worse`` exceeds ``--tolerance`` (0.20: more than 20 %
worse), or a benchmark fails to run. A key a benchmark does not report is "not measured": a failure for a
required key (a renamed key would otherwise hide a regression), a note for an optional one (figures a
benchmark is still gaining). A key without a recorded figure is "no baseline" (``--record`` adds it).

Timings on a shared machine scatter by 10-30 % from run to run (more under load: a ratio of two wall
times moves with whichever of the two the other work slowed); ``--repeat`` takes each figure's median
over several runs, and a failure is worth a second run before it is worth a bisection. The guard is a
command, not a test: the test suite holds no timing thresholds (``tests/test_benchmark_guard.py``
checks the comparison itself on fabricated documents).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import re
import subprocess
import sys
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
BASELINE_FILE = HERE / "baseline.json"
TOLERANCE = 0.20


@dataclass(frozen=True)
class Key:
    """One guarded figure of one benchmark's JSON document.

    Attributes
    ----------
    benchmark : str
        The script's name in ``benchmarks/`` without ``.py``.
    path : str
        Where the figure sits in the document: keys joined by dots, a list item chosen by
        ``[field=value]`` (the item whose ``field`` reads ``value``) or ``[index]``; a path without a dot
        or bracket is also looked for anywhere in the document.
    better : {"lower", "higher"}
        The direction in which the figure improves.
    note : str
        What the figure is, for the table.
    optional : bool
        A figure the benchmark may not report yet: "not measured" is then no failure.
    """

    benchmark: str
    path: str
    better: str
    note: str
    optional: bool = False


#: Benchmarks that take longer than half a minute with ``--quick`` (left out by the guard's ``--quick``).
SLOW = frozenset({"frf_speed", "gear_dynamics", "study_sobol"})

#: The guarded figures, benchmark by benchmark. Ratios against a baseline measured in the same run.
GUARDED: tuple[Key, ...] = (
    # drivetrain modal analysis
    Key("modal_chain", "variant.ratio_variant_vs_bare_eigh", "lower", "new 10-disk variant / bare eigh"),
    Key(
        "modal_chain", "variant.ratio_built_modal_vs_bare_eigh", "lower", "modal of a built model / bare eigh"
    ),
    Key(
        "modal_chain",
        "variant.ratio_element_lists_vs_bare_eigh",
        "lower",
        "variant from element lists / eigh",
    ),
    Key("modal_chain", "build.ratio_build_vs_solve", "lower", "build 10^5 disks from arrays / its solve"),
    Key("modal_chain", "cases[n=1000].ratio_vs_dense", "higher", "dense eigh / mechdyn, N = 1000"),
    Key("modal_chain", "cases[n=100000].ratio_vs_sparse", "higher", "ARPACK / mechdyn, N = 10^5, 10 modes"),
    Key("small_model", "cases[0].ratio_modal_vs_bare", "lower", "modal of a built 10-disk chain / eigh"),
    Key(
        "small_model",
        "cases[0].ratio_with_values_and_modal_vs_bare",
        "lower",
        "with_values + modal, 10 disks / eigh",
    ),
    Key("small_model", "cases[0].ratio_build_and_modal_vs_bare", "lower", "build + modal, 10 disks / eigh"),
    Key("small_model", "cases[1].ratio_vs_bare", "lower", "four-bar inverse dynamics / bare NumPy"),
    Key("model_loading", "ratio_load_vs_parse", "lower", "load a 2000-disk file / tomllib parse"),
    # forced response
    Key(
        "frf_speed",
        "frf[disks=10].ratio_vs_plain_superposition",
        "lower",
        "FRF 10 disks / plain superposition",
    ),
    Key("frf_speed", "frf[disks=100].ratio_vs_plain_superposition", "lower", "FRF 100 disks / plain sum"),
    Key("frf_speed", "frf[disks=400].ratio_vs_plain_superposition", "lower", "FRF 400 disks / plain sum"),
    Key("frf_speed", "rayleigh_banded[0].ratio_vs_bare_banded", "lower", "Rayleigh FRF / bare banded solve"),
    Key("frf_speed", "study_block.ratio_vs_bare", "lower", "study block per variant / eigh_tridiagonal"),
    Key(
        "frf_memory", "cases[frequencies=200].ratio_vs_stacked", "higher", "stacked matrix / FRF peak memory"
    ),
    Key(
        "frf_memory",
        "large[damping=rayleigh].ratio_all_modes_vs_peak",
        "higher",
        "all modes / peak, Rayleigh",
    ),
    Key("frf_memory", "large[damping=modal].ratio_all_modes_vs_peak", "higher", "all modes / peak, modal"),
    # mechanisms (mechanism_cycle's summary figures are new: optional until every run reports them)
    Key("mechanism_cycle", "ratio_vs_loop", "higher", "per-angle fsolve loop / inverse dynamics"),
    Key("mechanism_cycle", "ratio_vs_bare_dyads", "lower", "press cycle / bare dyad-by-dyad NumPy", True),
    Key(
        "mechanism_cycle",
        "summary_variant_cycles_per_s",
        "higher",
        "summary batch, variant-cycles/s (absolute)",
        True,
    ),
    Key("mechanism_cycle", "summary_bytes_per_variant", "lower", "summary batch, bytes per variant", True),
    Key("balance", "cases[objective=shaking_force_rms].speedup", "higher", "sampler / exact balancing"),
    # periodic steady states
    Key("periodic_response", "ratio_min", "higher", "solve_ivp to steady state / frequency domain"),
    Key("gear_dynamics", "ratio", "higher", "solve_ivp / speed_sweep at equal accuracy"),
    Key("study_sobol", "ratio_vs_loop", "higher", "single-design loop / Sobol study"),
)


# -- reading figures -------------------------------------------------------------------------------

_STEP = re.compile(r"([^.\[\]]+)|\[([^\]]*)\]")


def _steps(path: str) -> list[tuple[str, str]]:
    """``a.b[n=10].c`` → [("key", "a"), ("key", "b"), ("item", "n=10"), ("key", "c")]."""
    out = []
    for name, item in _STEP.findall(path):
        out.append(("key", name) if name else ("item", item))
    return out


def _find_anywhere(doc: Any, name: str) -> Any:
    if isinstance(doc, Mapping):
        if name in doc:
            return doc[name]
        children: Iterable[Any] = doc.values()
    elif isinstance(doc, list):
        children = doc
    else:
        return None
    for child in children:
        found = _find_anywhere(child, name)
        if found is not None:
            return found
    return None


def lookup(doc: Any, path: str) -> float | None:
    """The number at ``path`` in a benchmark's JSON document (see :class:`Key`), or None if absent.

    Parameters
    ----------
    doc : dict
        The document a benchmark printed with ``--json``.
    path : str
        Dotted keys and ``[field=value]`` or ``[index]`` list selectors.
    """
    node: Any = doc
    for kind, step in _steps(path):
        if kind == "key":
            node = node.get(step) if isinstance(node, Mapping) else None
        elif isinstance(node, list):
            if "=" in step:
                field, want = step.split("=", 1)
                node = next(
                    (x for x in node if isinstance(x, Mapping) and str(x.get(field)) == want.strip()), None
                )
            else:
                i = int(step)
                node = node[i] if -len(node) <= i < len(node) else None
        else:
            node = None
        if node is None:
            break
    if node is None and not any(c in path for c in ".["):
        node = _find_anywhere(doc, path)
    if isinstance(node, bool) or not isinstance(node, int | float):
        return None
    return float(node)


# -- comparing -------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Row:
    """One guarded figure: recorded, current, how much worse, and the verdict.

    ``status`` is one of ``"ok"``, ``"worse"`` (beyond the tolerance: a failure), ``"not measured"``,
    ``"no baseline"``, ``"benchmark failed"`` and ``"not run"``; ``failed`` says whether it fails the guard.
    """

    key: Key
    recorded: float | None
    current: float | None
    worse: float | None
    status: str
    failed: bool


def worse_by(key: Key, recorded: float, current: float) -> float:
    """How much worse ``current`` is than ``recorded``, as a fraction (negative: better).

    Parameters
    ----------
    key : Key
        The figure, whose ``better`` gives the direction.
    recorded, current : float
        The previous release's figure and this run's, both positive.
    """
    if key.better == "lower":
        return current / recorded - 1.0
    if key.better == "higher":
        return recorded / current - 1.0 if current > 0 else float("inf")
    raise ValueError(f"{key.benchmark}: {key.path}: better must be 'lower' or 'higher', not {key.better!r}")


def compare(
    recorded: Mapping[str, Mapping[str, float]],
    documents: Mapping[str, Any],
    *,
    keys: Iterable[Key] = GUARDED,
    tolerance: float = TOLERANCE,
    failed_benchmarks: Iterable[str] = (),
) -> list[Row]:
    """Each guarded figure of this run against the one recorded.

    Parameters
    ----------
    recorded : mapping of benchmark → (path → figure)
        The ``figures`` of ``baseline.json``.
    documents : mapping of benchmark → dict or list of dict
        This run's JSON documents, by benchmark (several runs of one: each figure's median over them);
        a benchmark not in it was not run.
    keys : iterable of Key
        The figures to compare (default :data:`GUARDED`).
    tolerance : float
        The largest accepted ``worse``, a fraction (0.2: 20 % worse).
    failed_benchmarks : iterable of str
        Benchmarks that ran but failed (non-zero exit, no JSON).

    Returns
    -------
    list of Row
        In the order of ``keys``.
    """
    failed = set(failed_benchmarks)
    rows = []
    for key in keys:
        before = recorded.get(key.benchmark, {}).get(key.path)
        if key.benchmark in failed:
            rows.append(Row(key, before, None, None, "benchmark failed", True))
            continue
        if key.benchmark not in documents:
            rows.append(Row(key, before, None, None, "not run", False))
            continue
        docs = documents[key.benchmark]
        now = median_of(lookup(d, key.path) for d in (docs if isinstance(docs, list) else [docs]))
        if now is None:
            rows.append(Row(key, before, None, None, "not measured", not key.optional))
        elif before is None:
            rows.append(Row(key, None, now, None, "no baseline", False))
        else:
            w = worse_by(key, before, now)
            bad = w > tolerance
            rows.append(Row(key, before, now, w, "worse" if bad else "ok", bad))
    return rows


def table(rows: Iterable[Row], tolerance: float = TOLERANCE) -> str:
    """The comparison as text, one line per figure."""
    rows = list(rows)
    lines = [
        f"{'benchmark':17} {'figure':46} {'better':6} {'recorded':>10} {'now':>10} {'worse':>7}  verdict",
    ]
    for r in rows:
        rec = f"{r.recorded:10.4g}" if r.recorded is not None else f"{'—':>10}"
        cur = f"{r.current:10.4g}" if r.current is not None else f"{'—':>10}"
        worse = f"{100 * r.worse:+6.0f}%" if r.worse is not None else f"{'':>7}"
        verdict = r.status.upper() if r.failed else r.status
        lines.append(
            f"{r.key.benchmark:17} {r.key.note[:46]:46} {r.key.better:6} {rec} {cur} {worse}  {verdict}"
        )
    failures = [r for r in rows if r.failed]
    lines.append(
        f"{len(failures)} of {len(rows)} figures fail (tolerance {100 * tolerance:.0f} % worse)"
        if failures
        else f"all figures within {100 * tolerance:.0f} % of the recorded ones (or not compared)"
    )
    return "\n".join(lines)


# -- running ---------------------------------------------------------------------------------------


def run_benchmark(name: str, timeout: float = 1800.0) -> tuple[dict | None, str]:
    """``python benchmarks/NAME.py --quick --json`` in a fresh process: its document, or None and why."""
    try:
        proc = subprocess.run(
            [sys.executable, str(HERE / f"{name}.py"), "--quick", "--json"],
            capture_output=True,
            text=True,
            timeout=timeout,
            cwd=HERE.parent,
        )
    except subprocess.TimeoutExpired:
        return None, f"no result within {timeout:.0f} s"
    if proc.returncode != 0:
        return None, f"exit status {proc.returncode}: {proc.stderr.strip().splitlines()[-1:] or ''}"
    try:
        return json.loads(proc.stdout), ""
    except json.JSONDecodeError as exc:
        return None, f"no JSON document on its output ({exc})"


def median_of(values: Iterable[float | None]) -> float | None:
    """The median of several runs' figures (None where none was measured).

    The median, not the best: a ratio's best run is as often the one whose baseline a busy machine
    slowed down as the one where mechdyn ran well.
    """
    got = sorted(v for v in values if v is not None)
    if not got:
        return None
    mid = len(got) // 2
    return got[mid] if len(got) % 2 else 0.5 * (got[mid - 1] + got[mid])


def _git(*args: str) -> str:
    try:
        out = subprocess.run(["git", *args], capture_output=True, text=True, cwd=HERE.parent, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return ""
    return out.stdout.strip() if out.returncode == 0 else ""


def record(rows: Iterable[Row], path: Path, tolerance: float, note: str = "") -> dict:
    """Write ``path`` from this run's figures (keeping recorded figures this run did not measure).

    Parameters
    ----------
    rows : iterable of Row
        This run's comparison; each measured figure is recorded.
    path : Path
        The baseline file.
    tolerance : float
        The tolerance to record with the figures (fraction).
    note : str
        The conditions of the run, in words (the machine, its load).
    """
    old = json.loads(path.read_text()) if path.exists() else {}
    figures: dict[str, dict[str, float]] = {k: dict(v) for k, v in old.get("figures", {}).items()}
    for r in rows:
        if r.current is not None:
            figures.setdefault(r.key.benchmark, {})[r.key.path] = r.current
    doc = {
        "recorded": {
            "commit": _git("rev-parse", "HEAD"),
            "working_tree_changed": bool(_git("status", "--porcelain", "--untracked-files=no")),
            "date": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
            "command": "python benchmarks/guard.py --record (each benchmark with --quick --json)",
            "note": note,
        },
        "tolerance": tolerance,
        "figures": figures,
    }
    path.write_text(json.dumps(doc, indent=2) + "\n")
    return doc


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="leave out the benchmarks that take minutes")
    p.add_argument("--only", action="append", default=[], metavar="NAME", help="run this benchmark only")
    p.add_argument(
        "--repeat", type=int, default=1, help="runs of each benchmark; each figure's median is compared"
    )
    p.add_argument("--tolerance", type=float, default=None, help="accepted fraction worse (default 0.2)")
    p.add_argument("--baseline", type=Path, default=BASELINE_FILE, help="the recorded figures")
    p.add_argument("--record", action="store_true", help="write this run's figures as the baseline")
    p.add_argument("--note", default="", help="with --record: the machine and its load, in words")
    p.add_argument("--json", action="store_true", help="print the comparison as one JSON object")
    args = p.parse_args(argv)
    names = list(dict.fromkeys(k.benchmark for k in GUARDED))
    unknown = [n for n in args.only if n not in names]
    if unknown:
        p.error(f"not a guarded benchmark: {', '.join(unknown)}; guarded: {', '.join(names)}")
    if args.only:
        names = [n for n in names if n in args.only]
    elif args.quick:
        names = [n for n in names if n not in SLOW]
    baseline = json.loads(args.baseline.read_text()) if args.baseline.exists() else {}
    tolerance = args.tolerance if args.tolerance is not None else baseline.get("tolerance", TOLERANCE)
    runs: dict[str, list[dict]] = {}
    failed: dict[str, str] = {}
    for name in names:
        for _ in range(max(1, args.repeat)):
            t0 = time.perf_counter()
            doc, why = run_benchmark(name)
            if not args.json:
                print(
                    f"{name}: {why or 'done'} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr, flush=True
                )
            if doc is None:
                failed[name] = why
                break
            runs.setdefault(name, []).append(doc)
    keys = [k for k in GUARDED if k.benchmark in names]
    rows = compare(
        baseline.get("figures", {}), runs, keys=keys, tolerance=tolerance, failed_benchmarks=failed
    )
    if args.record:
        record(rows, args.baseline, tolerance, args.note)
    if args.json:
        print(
            json.dumps(
                {
                    "tolerance": tolerance,
                    "baseline": baseline.get("recorded", {}),
                    "failed_benchmarks": failed,
                    "figures": [
                        {
                            "benchmark": r.key.benchmark,
                            "path": r.key.path,
                            "better": r.key.better,
                            "recorded": r.recorded,
                            "current": r.current,
                            "worse": r.worse,
                            "status": r.status,
                            "failed": r.failed,
                        }
                        for r in rows
                    ],
                },
                indent=2,
            )
        )
    else:
        rec = baseline.get("recorded", {})
        print(f"recorded: commit {rec.get('commit', '?')[:12]}, {rec.get('date', '?')}")
        print(table(rows, tolerance))
        for name, why in failed.items():
            print(f"{name} failed: {why}")
        if args.record:
            print(f"recorded this run's figures in {args.baseline.name}")
    return 1 if any(r.failed for r in rows) and not args.record else 0


if __name__ == "__main__":
    sys.exit(main())
