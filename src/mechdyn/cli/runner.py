"""One generic command for every registered analysis: load, run, store, print, plot.

``mechdyn NAME FILE [options]`` is built from the analysis' registration (:mod:`mechdyn.registry`):
its options become flags, and the result protocol (:mod:`mechdyn.results`) gives the tables, the
JSON summary, the CSV table, the plots and the arrays kept in the results database. Nothing here
knows an analysis by name.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from mechdyn.registry import Analysis, Option

__all__ = ["add_analysis_parser", "run"]

_QUANTITY_LABEL = {"rad/s": "speed", "Hz": "frequency"}


def _quantity(option: Option) -> Any:
    label = _QUANTITY_LABEL.get(option.unit or "", option.name.replace("_", " "))

    def parse(text: str) -> float:
        from mechdyn.units import UnitError, to_si

        try:
            return to_si(text, option.unit or "")
        except UnitError as exc:
            raise argparse.ArgumentTypeError(f"{label} {text!r}: {exc}") from None

    return parse


def _number(option: Option, cast: type) -> Any:
    def parse(text: str) -> Any:
        try:
            value = cast(text)
        except ValueError:
            value = None
        if value is not None and not math.isfinite(value):
            value = None  # "nan" and "inf" read as floats but are no setting
        if value is None or (option.minimum is not None and value < option.minimum):
            least = "" if option.minimum is None else f" of at least {cast(option.minimum)}"
            kind = "a whole number" if cast is int else "a number"
            raise argparse.ArgumentTypeError(f"{option.name.replace('_', ' ')} {text!r}: give {kind}{least}")
        return value

    return parse


def _add_option(p: argparse.ArgumentParser, o: Option) -> None:
    kw: dict[str, Any] = {"help": o.help, "dest": o.name, "default": o.default}
    if o.metavar is not None:
        kw["metavar"] = o.metavar
    if o.nargs:
        kw["nargs"] = o.nargs
    if o.kind == "flag":
        p.add_argument(o.flag, action="store_true", help=o.help, dest=o.name)
        return
    if o.kind == "quantity":
        kw["type"] = _quantity(o)
    elif o.kind == "int":
        kw["type"] = _number(o, int)
    elif o.kind == "float":
        kw["type"] = _number(o, float)
    elif o.kind == "choice":
        kw["choices"] = o.choices
    elif o.kind == "names":
        kw["nargs"] = "+"
    p.add_argument(o.flag, **kw)


def _display_unit(si: str, kind: str) -> Callable[[str], str]:
    """An argparse type: a unit of ``kind`` (compatible with ``si``), else a message naming the value
    and what is expected."""

    def parse(text: str) -> str:
        from mechdyn.units import registry

        try:
            ok = registry().Quantity(1.0, text).is_compatible_with(si)
        except Exception:  # pint raises several kinds of errors for a unit it cannot read
            ok = False
        if not ok:
            raise argparse.ArgumentTypeError(f"{text!r} is not a unit of {kind} (e.g. kN, tonf for a force)")
        return text

    return parse


def _animation_path(text: str) -> str:
    """An argparse type: a file an animation can be written to (.gif, or .mp4 with ffmpeg), else a
    message saying what to give instead."""
    from mechdyn.errors import MechdynError
    from mechdyn.mechanism.animation import check_animation_path

    try:
        check_animation_path(text)
    except MechdynError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return text


def add_analysis_parser(sub: argparse._SubParsersAction, analysis: Analysis) -> None:
    """Add ``mechdyn NAME``: the common options, then the analysis' own."""
    epilog = None
    if analysis.examples:
        epilog = "examples:\n" + "\n".join(f"  {e}" for e in analysis.examples)
    p = sub.add_parser(
        analysis.name,
        help=analysis.help,
        description=analysis.help,
        epilog=epilog,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    types = " or ".join(f'type = "{t}"' for t in analysis.model_types)
    p.add_argument("file", help=f"model file (TOML, {types})")
    p.add_argument("--json", action="store_true", help="print a machine-readable summary (JSON) on stdout")
    p.add_argument("--plots", metavar="DIR", help="write the plots (PNG) into DIR")
    if analysis.animates:  # its result draws the linkage over a crank cycle
        p.add_argument(
            "--animate",
            metavar="PATH",
            type=_animation_path,
            help="write the linkage animated over one crank cycle to PATH: a .gif, or an .mp4 where "
            "ffmpeg is installed",
        )
        p.add_argument(
            "--animate-frames",
            metavar="N",
            type=_number(Option("animate_frames", "int", "", minimum=1), int),
            default=72,
            help="frames of the animation: equally spaced crank angles, at most one per angle analysed "
            "(default: 72, one per 5 deg)",
        )
    p.add_argument("--csv", metavar="FILE", help="write the result table (columns named with their units)")
    p.add_argument("--report", metavar="FILE", help="write a self-contained HTML report of the run")
    p.add_argument(
        "--force-unit",
        metavar="UNIT",
        type=_display_unit("N", "force"),
        help="show forces in this unit (kN, tonf, lbf; default: by their size)",
    )
    p.add_argument(
        "--length-unit",
        metavar="UNIT",
        type=_display_unit("m", "length"),
        help="show lengths in this unit (mm, m, in; default: by their size)",
    )
    p.add_argument(
        "--db",
        metavar="URL",
        help="results database: a SQLite file path or a SQLAlchemy URL "
        "(default: $MECHDYN_DB, else mechdyn.db in the working directory)",
    )
    for o in analysis.options:
        _add_option(p, o)
    p.set_defaults(func=lambda args: run(args, analysis))


def run(args: argparse.Namespace, analysis: Analysis) -> int:
    """Load ``args.file``, run the analysis, store the run, print a table or JSON, write plots (and an
    animation, for a linkage)."""
    from mechdyn.figure_workers import FigureWorkers

    with FigureWorkers() as drawing:
        return _run(args, analysis, drawing)


def _drawing_modules(analysis: Analysis) -> list[str]:
    """The modules the processes that draw a result import before it comes: the analysis' own, its
    capability's plots, and those the analysis imports where it runs (its ``import`` statements, read
    from its bytecode: the result's classes)."""
    import dis

    module = analysis.function.__module__
    runs = [
        str(i.argval)
        for i in dis.get_instructions(analysis.function)
        if i.opname == "IMPORT_NAME" and str(i.argval).startswith("mechdyn.")
    ]
    return list(dict.fromkeys([module, module.rpartition(".")[0] + ".plots", *runs]))


def _model_modules(analysis: Analysis) -> list[str]:
    """The modules of mechdyn that reading a model imported, less those of reading files: those its
    result may hold objects of (SciPy's where it was imported)."""
    package = analysis.function.__module__.rpartition(".")[0]
    skip = (".schema", ".analyses", ".io", ".cli", ".store", ".studies", ".reports", ".dashboard")
    found = [
        m
        for m in list(sys.modules)
        if m.startswith("mechdyn.") and not any(m.endswith(x) or f"{x}." in m for x in skip) and m != package
    ]
    return (["scipy"] if "scipy" in sys.modules else []) + found + ["mechdyn.results"]


def _run(args: argparse.Namespace, analysis: Analysis, drawing: Any) -> int:
    from mechdyn.figure_workers import core_free, one_blas_thread

    if args.plots:  # the other cores draw: this process's BLAS must not spin on them
        one_blas_thread()
    drawn_by = _drawing_modules(analysis)  # imported by the drawing processes
    early = bool(args.plots) and core_free()
    if early:
        # a core is idle: the process that will draw the plots starts now, before this one imports
        # what reading the model and storing the run need, and imports matplotlib beside it while it
        # reads the model (mostly imports too) and runs the analysis
        drawing.start(*drawn_by)

    from mechdyn.errors import LongRunWarning, MechdynError, ModelFileError
    from mechdyn.io.modelfile import load_model
    from mechdyn.store import ResultStore
    from mechdyn.store.store import StoreError, check_name, jsonable

    options = {o.name: getattr(args, o.name) for o in analysis.options}
    caught: list[warnings.WarningMessage] = []
    told: set[str] = set()

    def keep(
        message: Any, category: Any, filename: str, lineno: int, file: Any = None, line: Any = None
    ) -> None:
        caught.append(warnings.WarningMessage(message, category, filename, lineno, file, line))
        if issubclass(category, LongRunWarning):  # said before the work, not after it
            told.add(str(message))
            print(f"warning: {message}", file=sys.stderr, flush=True)

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.showwarning = keep
        loaded = load_model(args.file)
        check_name("[model] name", loaded.name, args.file)
        if early:  # what the result will hold: the modules of the model just read
            drawing.expect(*_model_modules(analysis))
        elif args.plots:
            # no core to spare: started once the model is read, the drawing processes inherit what
            # reading it imported (NumPy, pint, pydantic) instead of importing it a second time while
            # this process competes with them for one core
            drawing.start(*drawn_by)
        # the database is checked before the work: a wrong --db costs nothing
        with ResultStore(args.db) as store:
            label = store.label
            try:
                extra = {"store": store} if analysis.uses_store else {}
                result = analysis.run(loaded, **extra, **options)
                summary = result.summary()
            except (ModelFileError, StoreError):
                raise
            except MechdynError as exc:  # found while analysing the file's model: name the file
                raise MechdynError(f"{args.file}: {exc}") from None
    planned: list[Path] = []
    if args.plots:  # the other processes draw while this one stores the run and prints its tables
        planned = drawing.begin(result, args.plots)
    notes = [
        n for n in dict.fromkeys([str(w.message) for w in caught] + list(result.warnings)) if n not in told
    ]
    for n in notes:
        print(f"warning: {n}", file=sys.stderr)
    source = loaded.source
    assert source is not None  # the command line loads a file
    writes = {o.name for o in analysis.options if o.writes}  # a file written once, not again by a report
    parameters = {k: v for k, v in options.items() if v is not None and v is not False and k not in writes}
    failed: list[str] = []
    run_id = _store_run(
        args.db,
        failed,
        analysis=analysis.name,
        model_name=loaded.name,
        model_path=source.path,
        model_text=source.text,
        model_sha256=source.sha256,
        parameters=jsonable(parameters),
        scalars={**summary, "warnings": notes},
        arrays=result.arrays(),
    )
    # the run is stored (or kept in a file); a file that cannot be written is an error that loses nothing
    if not args.json:  # the tables, while the other processes draw
        from mechdyn.cli.common import print_table

        print(f"{loaded.name}  ({source.path})")
        shown = {k: u for k in ("force_unit", "length_unit") if (u := getattr(args, k, None))}
        for t in result.tables(**shown):
            print_table(t)
        sys.stdout.flush()
    if args.csv:
        with _writing(args.csv, "the table", run_id, failed):
            path = Path(args.csv)
            path.parent.mkdir(parents=True, exist_ok=True)
            from mechdyn.cli.common import write_csv

            write_csv(result.to_frame(), path)
    animation_file = None
    if getattr(args, "animate", None):
        with _writing(args.animate, "the animation", run_id, failed):
            result.animate(args.animate, frames=args.animate_frames)
            animation_file = args.animate
    report_file = None
    if args.report:
        from mechdyn.reports.html import run_report, write

        report = run_report(
            result,
            analysis=analysis.name,
            model_name=loaded.name,
            model_path=source.path,
            model_text=source.text,
            model_sha256=source.sha256,
            options=parameters,
            warnings=notes,
            run_id=run_id,
            database=label,
        )
        with _writing(args.report, "the report", run_id, failed):
            report_file = str(write(report, args.report))
    plot_files: list[str] = []
    if args.plots:  # drawn meanwhile by the other processes
        with _writing(args.plots, "the plots", run_id, failed):
            drawing.end()
            plot_files = [str(p) for p in planned]
    if args.json:
        doc = {
            "run_id": run_id,
            "analysis": analysis.name,
            "model": loaded.name,
            "model_file": source.path,
            "model_sha256": source.sha256,
            "parameters": parameters,
            **summary,
            "warnings": notes,
            "plots": plot_files,
            "report": report_file,
        }
        print(json.dumps(jsonable(doc), indent=2))
        return 2 if failed else 0
    for p in plot_files:
        print(f"plot: {p}")
    if animation_file:
        print(f"animation: {animation_file}")
    if report_file:
        print(f"report: {report_file}")
    if run_id is not None:
        print(f"stored as run {run_id} in the {label}  (mechdyn results show {run_id})")
    return 2 if failed else 0


def _store_run(db: str | None, failed: list[str], **run: Any) -> int | None:
    """Store the run; returns its id. A run the database refuses (server
    gone, disk full, …) is kept in a file beside it, with a line that says how to import it."""
    from mechdyn.store import ResultStore, resolve_url
    from mechdyn.store.store import StoreError
    from mechdyn.store.unsaved import keep_unsaved

    try:
        with ResultStore(db) as store:
            return store.record(**run)
    except StoreError as exc:
        url = resolve_url(db)
        kept = keep_unsaved(url, "run", run)
        print(
            f"error: the run could not be stored ({exc}); it is kept in {kept}: "
            f"`mechdyn results import {kept}{'' if db is None else f' --db {db}'}` stores it",
            file=sys.stderr,
        )
        failed.append(str(kept))
        return None


@contextmanager
def _writing(path: str, what: str, run_id: int | None, failed: list[str]) -> Iterator[None]:
    """Write an output file; if it cannot be written, say so in one line naming the path (the run is
    already stored) and note the failure, so that the command ends with status 2."""
    try:
        yield
    except OSError as exc:
        if isinstance(exc, FileExistsError | NotADirectoryError):
            reason = f"{exc.filename} is a file, not a folder"
        else:
            reason = exc.strerror or str(exc)
            if exc.filename and str(exc.filename) != str(path):
                reason += f" ({exc.filename})"
        print(
            f"error: cannot write {what} to {path}: {reason}; the analysis is "
            + (f"stored as run {run_id}" if run_id is not None else "kept in the file named above"),
            file=sys.stderr,
        )
        failed.append(path)
