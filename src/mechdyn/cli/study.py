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

        for p in ModelTree(read(args.file)).paths():
            print(p)
        return 0
    from mechdyn.store import ResultStore
    from mechdyn.store.store import jsonable
    from mechdyn.studies import load_study, run_study

    study = load_study(args.file)
    with ResultStore(args.db) as store:
        result = run_study(study, store, dask=args.dask, progress=not args.json and sys.stderr.isatty())
        where = store.url
    plot_files = []
    if args.plots:
        from mechdyn.plotting import save_figure

        for name, make in result.plots().items():
            plot_files.append(str(save_figure(make(), Path(args.plots) / name)))
    if args.csv:
        result.to_frame().to_csv(args.csv, index=False, float_format="%.10g")
    if args.json:
        print(json.dumps(jsonable({**result.summary(), "plots": plot_files}), indent=2))
        return 0
    from mechdyn.cli.common import print_table

    print(f"study {study.name!r}: {study.kind} of {study.analysis} on {study.source.path}")
    for t in result.tables():
        print_table(t)
    for p in plot_files:
        print(f"plot: {p}")
    shown = where.split("@")[-1].removeprefix("sqlite:///")
    print(f"stored in {shown}  (mechdyn results list --study {study.name!r})")
    return 0


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
    p.add_argument("--paths", action="store_true", help="list the paths of a model file's values and stop")
    p.set_defaults(func=_run)
