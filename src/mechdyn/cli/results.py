"""``mechdyn results``: list and show the runs kept in the results database."""

from __future__ import annotations

import argparse
import json

from mechdyn.cli.common import Table, print_table

__all__ = ["register"]


def _list(args: argparse.Namespace) -> int:
    from mechdyn.store import ResultStore
    from mechdyn.store.store import jsonable

    with ResultStore(args.db) as store:
        runs = store.runs(analysis=args.analysis, limit=args.limit)
    if args.json:
        print(
            json.dumps(
                [
                    jsonable({k: v for k, v in r.__dict__.items() if k not in ("model_text", "arrays")})
                    for r in runs
                ],
                indent=2,
                default=str,
            )
        )
        return 0
    rows = [
        [
            r.id,
            r.created_at.strftime("%Y-%m-%d %H:%M:%S"),
            r.analysis,
            r.model_name,
            r.model_path,
            r.model_sha256[:12],
        ]
        for r in runs
    ]
    print_table(
        Table(
            f"runs in {store.url.split('@')[-1]}",
            ["id", "time (UTC)", "analysis", "model", "file", "sha256"],
            rows,
        )
    )
    return 0


def _show(args: argparse.Namespace) -> int:
    from mechdyn.store import ResultStore
    from mechdyn.store.store import jsonable

    with ResultStore(args.db) as store:
        r = store.get(args.id)
    if args.json:
        doc = {k: v for k, v in r.__dict__.items() if k != "arrays"}
        doc["arrays"] = {
            k: {"unit": u, "shape": list(a.shape), "dtype": str(a.dtype)} for k, (a, u) in r.arrays.items()
        }
        print(json.dumps(jsonable(doc), indent=2, default=str))
        return 0
    print(
        f"run {r.id}: {r.analysis} of {r.model_name!r} ({r.model_path}), "
        f"{r.created_at:%Y-%m-%d %H:%M:%S} UTC, mechdyn {r.package_version}"
    )
    print(f"model sha256 {r.model_sha256}")
    print("parameters: " + json.dumps(jsonable(r.parameters)))
    rows = []
    for k, v in r.scalars.items():
        text = json.dumps(jsonable(v))
        rows.append([k, text if len(text) <= 100 else text[:97] + "..."])
    print_table(Table("results", ["key", "value"], rows))
    print_table(
        Table(
            "arrays",
            ["name", "shape", "dtype", "unit"],
            [[k, "×".join(map(str, a.shape)), str(a.dtype), u] for k, (a, u) in r.arrays.items()],
        )
    )
    if args.model:
        print(r.model_text)
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("results", help="list and show stored runs")
    rs = p.add_subparsers(dest="results_command", required=True, metavar="{list,show}")
    for name, func, hlp in (
        ("list", _list, "list stored runs, newest first"),
        ("show", _show, "show one stored run"),
    ):
        q = rs.add_parser(name, help=hlp)
        q.add_argument("--db", metavar="URL", help="results database (default: $MECHDYN_DB, else mechdyn.db)")
        q.add_argument("--json", action="store_true", help="machine-readable output")
        q.set_defaults(func=func)
        if name == "list":
            q.add_argument("--analysis", help="only runs of this analysis")
            q.add_argument("--limit", type=int, help="at most this many runs")
        else:
            q.add_argument("id", type=int, help="run id (see `mechdyn results list`)")
            q.add_argument("--model", action="store_true", help="also print the stored model file")
