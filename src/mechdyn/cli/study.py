"""``mechdyn study FILE``: run (or resume) a design study; every variant goes into the results database."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

__all__ = ["register"]

EXAMPLES = (
    "examples:\n"
    "  mechdyn study examples/studies/press_support_influence.toml --plots plots\n"
    "  mechdyn study examples/studies/press_sobol.toml --dask local --json\n"
    "  mechdyn study --paths examples/press_on_support.toml"
)


def _run(args: argparse.Namespace) -> int:
    if args.paths:
        from mechdyn.io.modelfile import read
        from mechdyn.studies.paths import ModelTree

        entries = ModelTree(read(args.file)).entries()
        if args.json:
            print(json.dumps([e.as_dict() for e in entries], indent=2, ensure_ascii=False))
        else:
            for e in entries:
                print(e.line())
        return 0
    from mechdyn.store import ResultStore
    from mechdyn.store.store import jsonable
    from mechdyn.studies.run import run_studies
    from mechdyn.studies.study import load_studies

    studies = load_studies(args.file)
    if args.samples is not None:  # a quick form of the study, stored under its own name
        studies = [s.quick(args.samples) for s in studies]
    with ResultStore(args.db) as store:
        progress = not args.json and sys.stderr.isatty()
        results = run_studies(studies, store, dask=args.dask, progress=progress)
        where, label = store.where, store.label
    # a study none of whose variants (but the base design) could be evaluated shows nothing: no plots,
    # no report, no kind's tables (an output's "range" would be the base design's value alone); its
    # variants stay stored with their errors, and the command says why they failed and exits with 1
    empty = [r for r in results if r.every_variant_failed]
    plot_files = []
    for result in results:
        if result.every_variant_failed:
            continue
        if args.plots:
            from mechdyn.figure_workers import save_figures

            prefix = "" if len(results) == 1 else _safe(result.study.name) + "_"
            plot_files += [str(p) for p in save_figures(result, args.plots, prefix=prefix)]
    if args.report and len(empty) < len(results):
        from mechdyn.reports.html import study_report, write

        for result in results:
            if result.every_variant_failed:
                continue
            target = Path(args.report)
            if len(results) > 1:
                target = target.with_name(f"{target.stem}_{_safe(result.study.name)}{target.suffix}")
            plot_files.append(
                str(write(study_report(result, database=label, study_text=_text(args.file)), target))
            )
    if args.csv:
        import pandas as pd

        from mechdyn.cli.common import write_csv

        frames = [r.to_frame().assign(study=r.study.name) for r in results]
        write_csv(pd.concat(frames), args.csv)
    if args.json:
        if len(results) == 1:
            doc = results[0].summary()
        else:
            first = results[0].study
            doc = {
                "study": first.family or first.name,
                "kind": first.kind,
                **{
                    k: sum(r.summary()[k] for r in results)
                    for k in ("variants", "evaluated", "reused", "failed")
                },
                "studies": [r.summary() for r in results],
            }
        print(json.dumps(jsonable({**doc, "plots": plot_files}), indent=2))
        return _failed(args.file, empty)
    from mechdyn.cli.common import print_table
    from mechdyn.studies.kinds import kind

    for result in results:
        study = result.study
        print(f"study {study.name!r}: {study.kind} of {study.analysis} on {study.source.path}")
        views = None if result.every_variant_failed else kind(study.kind).views(result)
        for sentence in views["headline"] if views else ():  # what the report leads with, too
            print(sentence)
        for t in result.count_tables() if result.every_variant_failed else result.tables():
            print_table(t)
    if len(results) > 1:
        from mechdyn.studies.result import boxes_table

        print_table(boxes_table(results))
    for p in plot_files:
        print(f"plot: {p}")
    shown = where.removeprefix("sqlite:///")
    names = ", ".join(repr(r.study.name) for r in results)
    print(f"stored in {shown}  (mechdyn results list --study NAME; {names})")
    return _failed(args.file, empty)


def _failed(path: str, empty: list) -> int:
    """1, with the reasons on standard error, when a study's variants all failed (but the base
    design): it found nothing; else 0."""
    for r in empty:
        print(
            f"error: {path}: study {r.study.name!r}: {r.failure_line()}; nothing to show. Its variants are "
            f"stored with their errors (mechdyn results list --study {r.study.name!r} shows each)",
            file=sys.stderr,
        )
    return 1 if empty else 0


def _text(path: str) -> str | None:
    try:
        return Path(path).read_text(encoding="utf-8")
    except OSError:
        return None


def _safe(name: str) -> str:
    """A study's name as part of a file name."""
    from mechdyn.studies.kinds.base import safe

    return safe(name).strip("_")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "study",
        help="run or resume a design study (sweeps, sensitivities, optimization, synthesis)",
        description="Run a study file: every variant is stored in the results database as it is "
        "evaluated; running the same study again continues where it stopped.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("file", help="a study file (TOML), or with --paths a model file")
    p.add_argument("--db", metavar="URL", help="results database (default: $MECHDYN_DB, else mechdyn.db)")
    p.add_argument(
        "--dask", metavar="ADDRESS", help='evaluate on Dask: "local" (a LocalCluster) or tcp://HOST:PORT'
    )
    p.add_argument("--json", action="store_true", help="print one JSON object (no progress bar)")
    p.add_argument("--plots", metavar="DIR", help="write the study's plots (PNG) here")
    p.add_argument("--csv", metavar="FILE", help="write one row per variant")
    p.add_argument("--report", metavar="FILE", help="write a self-contained HTML report of the study")
    p.add_argument(
        "--samples",
        type=int,
        metavar="N",
        help="override [study] samples (a quick form, stored as 'NAME [samples N]')",
    )
    p.add_argument(
        "--paths",
        action="store_true",
        help="list every value of a model file a study can vary (path = value, and for a whole number or "
        "a choice what it takes; with --json as JSON) and stop",
    )
    p.set_defaults(func=_run)
