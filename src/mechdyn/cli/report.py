"""``mechdyn report``: one self-contained HTML file of a stored run or a stored study."""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any

__all__ = ["register", "run_from_store"]

EXAMPLES = (
    "examples:\n"
    "  mechdyn report 3 --output press.html\n"
    "  mechdyn report --study press-support-influence --output influence.html"
)


def run_from_store(store: Any, run_id: int) -> tuple[Any, Any, str]:
    """Run a stored analysis again from its stored model file and options; returns the stored run,
    the result and a note on how the recomputed summary compares with the stored one."""
    import tomllib

    from mechdyn.io.modelfile import ModelSource, load_source
    from mechdyn.registry import get

    run = store.get(run_id)
    source = ModelSource(run.model_path, run.model_text, run.model_sha256, tomllib.loads(run.model_text))
    analysis = get(run.analysis)
    options = {k: v for k, v in run.parameters.items() if k in {o.name for o in analysis.options}}
    if analysis.uses_store:
        options["store"] = store
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = analysis.run(load_source(source), **options)
    worst = _largest_difference(run.scalars, result.summary())
    note = (
        "Recomputed from the model file and options stored with the run; the summary agrees with the "
        f"stored one to {worst:.1e} (relative)."
        if worst is not None
        else "Recomputed from the model file and options stored with the run."
    )
    return run, result, note


def _largest_difference(stored: dict[str, Any], now: dict[str, Any]) -> float | None:
    worst = None
    for k, v in stored.items():
        w = now.get(k)
        if isinstance(v, (int, float)) and isinstance(w, (int, float)) and not isinstance(v, bool):
            if math.isfinite(v) and math.isfinite(w):
                d = abs(v - w) / max(abs(v), abs(w), 1e-300)
                worst = d if worst is None else max(worst, d)
    return worst


def _report(args: argparse.Namespace) -> int:
    from mechdyn.errors import MechdynError
    from mechdyn.reports.html import run_report, study_report, write
    from mechdyn.store import ResultStore

    if (args.id is None) == (args.study is None):
        raise MechdynError("give a run id (`mechdyn results list`) or --study NAME, one of them")
    with ResultStore(args.db) as store:
        if args.study is not None:
            from mechdyn.studies.run import stored_result

            # what the study found, from the stored variants alone (nothing is evaluated again)
            report = study_report(stored_result(store, args.study), database=store.label)
        else:
            run, result, note = run_from_store(store, args.id)
            report = run_report(
                result,
                analysis=run.analysis,
                model_name=run.model_name,
                model_path=run.model_path,
                model_text=run.model_text,
                model_sha256=run.model_sha256,
                options=run.parameters,
                warnings=run.scalars.get("warnings") or (),
                run_id=run.id,
                created=run.created_at,
                database=store.label,
                note=note,
            )
    print(f"report: {write(report, args.output)}", file=sys.stdout)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "report",
        help="write one self-contained HTML report of a stored run or study",
        description="A report: the summary with units, every plot (embedded), the tables, the checks "
        "and warnings, and the model file. A run is recomputed from what is stored with it.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("id", type=int, nargs="?", help="run id (`mechdyn results list`)")
    p.add_argument("--study", metavar="NAME", help="a stored study instead of a run")
    p.add_argument("--output", "-o", metavar="FILE", required=True, help="the HTML file to write")
    p.add_argument("--db", metavar="URL", help="results database (default: $MECHDYN_DB, else mechdyn.db)")
    p.set_defaults(func=_report)
