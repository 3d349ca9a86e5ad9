"""``mechdyn results``: list and show the runs and study variants kept in the results database,
compare variants, export a study."""

from __future__ import annotations

import argparse
import json
from typing import Any

from mechdyn.cli.common import Table, print_table

__all__ = ["register"]


def _list(args: argparse.Namespace) -> int:
    from mechdyn.store import ResultStore
    from mechdyn.store.store import jsonable

    if args.study:
        return _list_study(args)
    with ResultStore(args.db, read_only=True) as store:
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
            f"runs in {store.where}",
            ["id", "time (UTC)", "analysis", "model", "file", "sha256"],
            rows,
        )
    )
    return 0


def _show(args: argparse.Namespace) -> int:
    from mechdyn.numbers import is_number, number_text
    from mechdyn.store import ResultStore
    from mechdyn.store.store import jsonable

    with ResultStore(args.db, read_only=True) as store:
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
    rows: list[list[object]] = []

    def add(key: str, value: object) -> None:  # nested tables one row each, named in words with the unit
        if isinstance(value, dict):
            for k, v in value.items():
                add(f"{key}.{k}", v)
        elif isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
            for i, v in enumerate(value, start=1):
                add(f"{key}.{i}", v)
        elif isinstance(value, list):
            rows.append([_heading(key, {}), ", ".join(_text(v) for v in value)])
        else:
            plain = isinstance(value, (int, float, str)) or value is None
            rows.append([_heading(key, {}), value if plain else json.dumps(jsonable(value))])

    def _text(v: object) -> str:
        return number_text(float(v)) if is_number(v) else json.dumps(jsonable(v))  # type: ignore[arg-type]

    for k, v in r.scalars.items():
        add(k, v)
    print_table(
        Table("results (SI; every digit with --json)", ["", "value"], rows, per_value=True),
        max_rows=len(rows) + 1,
    )
    print_table(
        Table(
            "arrays (in Python: ResultStore(db).get(id).arrays)",
            ["", "shape", "dtype"],
            [
                [_array_heading(k, u), "×".join(map(str, a.shape)), str(a.dtype)]
                for k, (a, u) in r.arrays.items()
            ],
        )
    )
    if args.model:
        print(r.model_text)
    return 0


def _given_text(text: Any) -> Any:
    """A parameter's value as stored (``"4.05e+08 N/m"``) with at least three significant digits
    (:func:`mechdyn.studies.cells.given`): a choice or a name as it is."""
    from mechdyn.studies.cells import given

    if not isinstance(text, str):
        return text
    number, _, unit = text.partition(" ")
    try:
        return f"{given(float(number))} {unit}".rstrip()
    except ValueError:
        return text


def _heading(key: str, shown: dict[str, Any]) -> str:
    """An output's heading in words with its unit: as its study shows it, else its key in words, SI."""
    from mechdyn.studies.outputs import Watched
    from mechdyn.units import key_unit

    if key in shown:
        return str(shown[key].label)
    unit = next((u for part in key.split(".") if (u := key_unit(part))), "")
    return str(Watched(key, unit, "").label)


def _array_heading(key: str, unit: str) -> str:
    """A stored array's name in words with the unit it is stored in."""
    heading = _heading(key, {})
    return heading if "[" in heading or not unit else f"{heading} [{unit}]"


def _list_study(args: argparse.Namespace) -> int:
    from mechdyn.store import ResultStore
    from mechdyn.store.store import jsonable
    from mechdyn.studies.run import display_units
    from mechdyn.studies.storage import StudyStore

    with ResultStore(args.db, read_only=True) as store:
        studies = StudyStore(store)
        st = studies.study(args.study)
        variants = studies.variants(args.study, limit=args.limit)
        shown = display_units(store, args.study)
    if args.json:  # machine-readable: SI, as stored
        print(json.dumps([jsonable(v.describe()) for v in variants], indent=2))
        return 0
    names = list(variants[0].parameters) if variants else []
    outs = list(variants[0].outputs) if variants else []
    rows = [
        [
            v.id,
            v.status,
            *(_given_text(v.given.get(n)) for n in names),
            *(shown[o].show(v.outputs.get(o)) if o in shown else v.outputs.get(o) for o in outs),
            v.error or "",
        ]
        for v in variants
    ]
    where = "outputs in the study's units" if shown else "outputs in SI"
    print_table(
        Table(
            f"study {st.name!r} ({st.kind} of {st.analysis}, {len(variants)} variants; {where})",
            ["id", "status", *names, *(_heading(o, shown) for o in outs), "error"],
            rows,
            per_value=True,  # each number on its own: a study's outputs spread over decades
        )
    )
    return 0


def _compare(args: argparse.Namespace) -> int:
    from pathlib import Path

    from mechdyn.store import ResultStore
    from mechdyn.store.store import jsonable
    from mechdyn.studies.storage import StudyStore

    with ResultStore(args.db, read_only=not args.plots) as store:  # --plots keeps the curves it computes
        studies = StudyStore(store)
        variants = [studies.variant(i) for i in args.ids]
        if args.plots:  # a selected variant keeps its curves: computed once, from what is stored
            from mechdyn.studies.run import recompute

            for v in variants:
                if not v.curves and v.status == "ok":
                    ev = recompute(store, v.id, curves=True)
                    if ev.curves:
                        studies.add_curves(v.id, ev.curves)
            variants = [studies.variant(i) for i in args.ids]
        from mechdyn.studies.run import display_units

        shown: dict[str, Any] = {}
        for name in dict.fromkeys(v.study for v in variants):
            shown.update(display_units(store, name))
    keys = list(dict.fromkeys(k for v in variants for k in (*v.parameters, *v.outputs)))
    if args.json:  # machine-readable: SI, as stored
        print(json.dumps([jsonable(v.describe()) for v in variants], indent=2))
        return 0
    rows = []
    for k in keys:
        if any(k in v.given for v in variants):  # a parameter, as its study file gives it
            rows.append([k, *(_given_text(v.given.get(k)) for v in variants)])
        elif k in shown:  # an output, in the unit its study shows it
            rows.append([_heading(k, shown), *(shown[k].show(v.outputs.get(k)) for v in variants)])
        else:  # in words, SI
            rows.append([_heading(k, shown), *(v.outputs.get(k) for v in variants)])
    print_table(
        Table(
            "variants side by side (outputs in their study's units, else SI)",
            ["", *(f"variant {v.id}" for v in variants)],
            rows,
            per_value=True,  # each number on its own: a row's values may differ by decades
        )
    )
    curves = sorted(set.intersection(*(set(v.curves) for v in variants))) if variants else []
    if args.plots and curves:
        from mechdyn.plotting import save_figure
        from mechdyn.studies.plots import curves as plot_curves

        x = next((c for c in curves if c.startswith(("crank_angle", "time"))), None)
        for name in args.curve or [c for c in curves if c != x][:4]:
            if name not in curves:
                _unknown_curve(name, curves)
            ax = plot_curves(variants, name, x)
            print(f"plot: {save_figure(ax, Path(args.plots) / f'compare_{name}.png')}")
    elif args.plots:
        print("no curve is kept for all of these variants (a study keeps them up to [study] curves variants)")
    return 0


def _unknown_curve(name: str, curves: list[str]) -> None:
    from mechdyn.errors import MechdynError

    raise MechdynError(f"no curve {name!r} kept for these variants; kept: {', '.join(curves)}")


def _export(args: argparse.Namespace) -> int:
    import pandas as pd

    from mechdyn.reports.columns import stored_columns
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    if not (args.csv or args.parquet):
        from mechdyn.errors import MechdynError

        raise MechdynError("give --csv FILE or --parquet FILE (or both)")
    with ResultStore(args.db, read_only=True) as store:
        variants = StudyStore(store).variants(args.study)
        columns = stored_columns(store, args.study, variants)
    if args.csv:  # for people: the study's units, each in its column's header
        rows = []
        for v in variants:
            row: dict[str, Any] = {"variant": v.id, "status": v.status, "error": v.error}
            row |= {f"{c.role}:{c.label}": c.of(v) for c in columns}
            rows.append(row)
        header = ["variant", "status", "error", *(f"{c.role}:{c.label}" for c in columns)]
        frame = pd.DataFrame(rows, columns=header)
        frame.to_csv(args.csv, index=False, float_format="%.10g")
        print(f"wrote {args.csv} ({len(frame)} variants, in the study's units)")
    if args.parquet:  # for programs: SI as stored, each column's unit in the file's schema
        _write_parquet(variants, columns, args.parquet)
        print(f"wrote {args.parquet} ({len(variants)} variants, SI; each column's unit in its metadata)")
    return 0


def _write_parquet(variants: list[Any], columns: list[Any], path: str) -> None:
    """Variants as Parquet, SI as stored (``parameter:NAME``, ``output:KEY``), a choice by the name of
    its level; each column's field metadata holds ``unit`` (its SI unit, ``""`` for a pure number or a
    choice) and ``shown_unit`` (the study's)."""
    import pandas as pd
    import pyarrow as pa
    import pyarrow.parquet as pq

    rows = []
    for v in variants:
        row: dict[str, Any] = {"variant": v.id, "status": v.status, "error": v.error}
        row |= {f"parameter:{k}": x for k, x in v.parameters.items()}
        row |= {f"output:{k}": x for k, x in v.outputs.items()}
        rows.append(row)
    names = [f"{c.role}:{c.key}" for c in columns]
    frame = pd.DataFrame(rows)
    extra = [n for n in frame.columns if n not in names and n not in ("variant", "status", "error")]
    frame = frame.reindex(columns=["variant", "status", "error", *names, *extra])
    levels = {f"{c.role}:{c.key}": c.levels for c in columns if c.levels}
    for n in [*names, *extra]:
        frame[n] = pd.to_numeric(frame[n], errors="coerce").astype("float64")
        if n in levels:  # a choice: the name of its level, not the index the database holds
            frame[n] = [levels[n][int(i)] if i == i and 0 <= i < len(levels[n]) else None for i in frame[n]]
    table = pa.Table.from_pandas(frame, preserve_index=False)
    units = {f"{c.role}:{c.key}": c for c in columns}
    fields = [
        f.with_metadata({b"unit": units[f.name].si_unit.encode(), b"shown_unit": units[f.name].unit.encode()})
        if f.name in units
        else f
        for f in table.schema
    ]
    pq.write_table(table.cast(pa.schema(fields, metadata=table.schema.metadata)), path)


def _delete(args: argparse.Namespace) -> int:
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(args.db) as store:
        n = StudyStore(store).delete(args.study)
    print(f"deleted study {args.study!r} and its {n} variants")
    return 0


def _studies(args: argparse.Namespace) -> int:
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(args.db, read_only=True) as store:
        studies = StudyStore(store)
        rows = []
        for st in studies.studies():
            n = studies.counts(st.id)
            rows.append([st.name, st.kind, st.analysis, st.model_path, n["variants"], n["failed"],
                         st.created_at.strftime("%Y-%m-%d %H:%M:%S")])  # fmt: skip
        where = store.where
    if args.json:
        keys = ["name", "kind", "analysis", "model", "variants", "failed", "created_utc"]
        print(json.dumps([dict(zip(keys, r, strict=True)) for r in rows], indent=2))
        return 0
    print_table(
        Table(
            f"studies in {where}",
            ["study", "kind", "analysis", "model", "variants", "failed", "created (UTC)"],
            rows,
        )
    )
    return 0


def _upgrade(args: argparse.Namespace) -> int:
    from mechdyn.store import ResultStore, resolve_url
    from mechdyn.store.database import shown

    before, after = ResultStore.upgrade(args.db)
    where = shown(resolve_url(args.db))
    if before == after:
        print(f"{where} has schema {after} already: nothing to do")
    else:
        print(f"upgraded {where} from schema {before or '(before versions)'} to {after}")
    return 0


def _import(args: argparse.Namespace) -> int:
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import import_unsaved

    with ResultStore(args.db) as store:
        for path in args.files:
            what = import_unsaved(store, path)
            print(f"{path}: stored {what} in {store.where}")
    return 0


_EXPORT_UNITS = """\
A study's variants, one row each: id, status, error, parameters and outputs.

--csv is for people and spreadsheets: each parameter and output in the unit the study file
gives it (a parameter in the unit its model file writes it in, an output in its [[outputs]]
row's unit), the unit in the column's header: "parameter:points.C.x [mm]",
"output:transmitted_force_range_N [tonf]". A study built in Python has no file units: SI,
with the SI unit named.

--parquet is for programs: SI, as the database holds it (and as `results list --json`
prints it), columns named "parameter:NAME" and "output:KEY"; each column's SI unit is in its
Parquet field metadata "unit" ("" for a pure number), the study's unit in "shown_unit"."""

_EXAMPLES = {
    "list": "  mechdyn results list --limit 10\n"
    "  mechdyn results list --study press-support-influence --json",
    "show": "  mechdyn results show 3 --model",
    "compare": "  mechdyn results compare 4 7 --plots plots",
    "export": "  mechdyn results export --study press-sobol --parquet sobol.parquet\n"
    "  mechdyn results export --study press-support-influence --csv influence.csv",
    "delete": "  mechdyn results delete --study press-sobol",
    "studies": "  mechdyn results studies",
    "upgrade": "  mechdyn results upgrade --db old.db",
    "import": "  mechdyn results import mechdyn-unsaved-20261125-101500-4242-run.json",
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "results",
        help="list and show stored runs and study variants, compare variants, export a study",
        epilog="examples:\n" + "\n".join(_EXAMPLES.values()),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    rs = p.add_subparsers(
        dest="results_command",
        required=True,
        metavar="{list,show,compare,export,delete,studies,upgrade,import}",
    )
    for name, func, hlp in (
        ("list", _list, "list stored runs, newest first, or a study's variants (--study)"),
        ("show", _show, "show one stored run"),
        ("compare", _compare, "study variants side by side, with their curves overlaid"),
        ("export", _export, "a study's variants as CSV (the study's units) or Parquet (SI), one row each"),
        ("delete", _delete, "remove a study with all of it (variants, curves, optimizer trials)"),
        ("studies", _studies, "list the studies of the database"),
        ("upgrade", _upgrade, "bring a database written by an older mechdyn to this one's schema"),
        ("import", _import, "store results that were kept in a file because the database refused them"),
    ):
        q = rs.add_parser(
            name,
            help=hlp,
            epilog="examples:\n" + _EXAMPLES[name],
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        q.add_argument("--db", metavar="URL", help="results database (default: $MECHDYN_DB, else mechdyn.db)")
        q.set_defaults(func=func)
        if name in ("list", "show", "compare", "studies"):
            q.add_argument("--json", action="store_true", help="machine-readable output")
        if name == "list":
            q.add_argument("--analysis", help="only runs of this analysis")
            q.add_argument("--study", help="the variants of this study instead of runs")
            q.add_argument("--limit", type=int, help="at most this many rows")
        elif name == "show":
            q.add_argument("id", type=int, help="run id (see `mechdyn results list`)")
            q.add_argument("--model", action="store_true", help="also print the stored model file")
        elif name == "compare":
            q.add_argument(
                "ids", type=int, nargs="+", metavar="ID", help="variant ids (`results list --study`)"
            )
            q.add_argument("--plots", metavar="DIR", help="write the overlaid curves here")
            q.add_argument("--curve", action="append", help="which stored curve to overlay (repeatable)")
        elif name == "import":
            q.add_argument("files", nargs="+", metavar="FILE", help="mechdyn-unsaved-….json files")
        elif name in ("delete", "export"):
            q.add_argument("--study", required=True, help="the study's name")
            if name == "export":
                q.description = _EXPORT_UNITS  # raw: kept as written
                q.add_argument(
                    "--csv",
                    metavar="FILE",
                    help="for people and spreadsheets: values in the study's units, the unit in each "
                    'header ("output:transmitted_force_range_N [tonf]")',
                )
                q.add_argument(
                    "--parquet",
                    metavar="FILE",
                    help="for programs: SI as stored, columns named as in the database "
                    '("output:transmitted_force_range_N"), each column\'s SI unit in its field metadata',
                )
