"""What every analysis subcommand shares: load, run, store, print a table or JSON, write plots.

An analysis command returns an :class:`AnalysisOutput`; :func:`run_analysis` does the rest, so every
subcommand stores its run, honours ``--json``, ``--plots DIR`` and ``--db`` the same way.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.io.modelfile import ModelSource, load_with_source
from mechdyn.store import ResultStore
from mechdyn.store.store import jsonable

__all__ = ["AnalysisOutput", "Table", "add_common_options", "column_unit", "run_analysis"]


@dataclass(frozen=True)
class Table:
    """A titled table for the terminal: column headers (with units) and rows of values."""

    title: str
    columns: list[str]
    rows: list[list[Any]]


@dataclass
class AnalysisOutput:
    """What an analysis command hands back to the shared runner.

    Attributes
    ----------
    analysis : str
        Name stored with the run, e.g. ``"modal"``.
    parameters : dict
        The options that shaped the run (stored, and echoed in the JSON).
    summary : dict
        JSON-ready scalar results: printed by ``--json`` and stored as the run's scalars.
    arrays : dict of name → (ndarray, unit)
        Stored bit for bit with the run.
    tables : list of Table
        Printed in order unless ``--json``.
    plots : dict of file name → callable returning matplotlib axes
        Written into ``--plots DIR``.
    """

    analysis: str
    parameters: dict[str, Any]
    summary: dict[str, Any]
    arrays: dict[str, tuple[np.ndarray, str]] = field(default_factory=dict)
    tables: list[Table] = field(default_factory=list)
    plots: dict[str, Callable[[], Any]] = field(default_factory=dict)


_SUFFIX_UNITS = (
    ("_m_per_s2", "m/s^2"),
    ("_m_per_s", "m/s"),
    ("_Nm", "N*m"),
    ("_N", "N"),
    ("_deg", "deg"),
    ("_m", "m"),
    ("_rad", "rad"),
    ("_s", "s"),
    ("_W", "W"),
)


def column_unit(column: str) -> str:
    """The unit a per-angle column's name ends with."""
    return next((u for suffix, u in _SUFFIX_UNITS if column.endswith(suffix)), "")


def add_common_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", help="model file (TOML)")
    p.add_argument("--json", action="store_true", help="print a machine-readable summary (JSON) on stdout")
    p.add_argument("--plots", metavar="DIR", help="write the plots (PNG) into DIR")
    p.add_argument(
        "--db",
        metavar="URL",
        help="results database: a SQLite file path or a SQLAlchemy URL "
        "(default: $MECHDYN_DB, else mechdyn.db in the working directory)",
    )


def _fmt(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if not np.isfinite(v):
            return "—"
        a = abs(v)
        if a == 0:
            return "0"
        if 1e-3 <= a < 1e7:  # 5 significant digits without an exponent
            return f"{v:.{max(0, 4 - int(np.floor(np.log10(a))))}f}"
        return f"{v:.4e}"
    return str(v)


def print_table(t: Table, file: Any = None) -> None:
    """Render a table with rich: its title on a line of its own, then the columns."""
    from rich import box
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table as RichTable

    cells = [[_fmt(v) for v in r] for r in t.rows]
    widths = [max([len(c), *(len(r[i]) for r in cells)]) for i, c in enumerate(t.columns)]
    # as wide as the table needs: a results table is never squeezed into dropping columns
    console = Console(file=file or sys.stdout, width=max(80, sum(widths) + 3 * len(widths)), highlight=False)
    rt = RichTable(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False)
    for i, c in enumerate(t.columns):
        numeric = all(isinstance(r[i], (int, float, np.number)) or r[i] is None for r in t.rows)
        rt.add_column(escape(c), justify="right" if numeric and i else "left", no_wrap=True)
    for r in cells:
        rt.add_row(*(escape(v) for v in r))
    console.print(f"\n[bold]{escape(t.title)}[/bold]")
    console.print(rt)


def run_analysis(
    args: argparse.Namespace,
    analyse: Callable[[Any, ModelSource], AnalysisOutput],
) -> int:
    """Load ``args.file``, run ``analyse(model, source)``, store the run, print and plot."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model, source = load_with_source(args.file)
        out = analyse(model, source)
    notes = [str(w.message) for w in caught]
    for n in notes:
        print(f"warning: {n}", file=sys.stderr)
    plot_files: list[str] = []
    if args.plots:
        from mechdyn.plotting import save_figure

        for name, make in out.plots.items():
            plot_files.append(str(save_figure(make(), Path(args.plots) / name)))
    with ResultStore(args.db) as store:
        run_id = store.record(
            analysis=out.analysis,
            model_name=getattr(model, "name", ""),
            model_path=source.path,
            model_text=source.text,
            model_sha256=source.sha256,
            parameters=out.parameters,
            scalars={**out.summary, "warnings": notes},
            arrays=out.arrays,
        )
    if args.json:
        doc = {
            "run_id": run_id,
            "analysis": out.analysis,
            "model": getattr(model, "name", ""),
            "model_file": source.path,
            "model_sha256": source.sha256,
            "parameters": out.parameters,
            **out.summary,
            "warnings": notes,
            "plots": plot_files,
        }
        print(json.dumps(jsonable(doc), indent=2))
        return 0
    print(f"{getattr(model, 'name', '')}  ({source.path})")
    for t in out.tables:
        print_table(t)
    for p in plot_files:
        print(f"plot: {p}")
    print(f"stored as run {run_id}  (mechdyn results show {run_id})")
    return 0
