"""What the commands share: the table renderer."""

from __future__ import annotations

import sys
from typing import Any

from mechdyn.numbers import column_format, is_number, number_text
from mechdyn.results import Table

__all__ = ["Table", "print_table", "write_csv"]


def write_csv(frame: Any, path: Any) -> None:
    """Write a table as CSV: column names without spaces (``shaft_1_Nm``), numbers to ten digits.

    Parameters
    ----------
    frame : pandas.DataFrame
        The table; numeric columns are named with their unit.
    path : str or Path
        The file.
    """
    frame.rename(columns=lambda c: "_".join(str(c).split())).to_csv(path, index=False, float_format="%.10g")


def _is_float(v: Any) -> bool:
    return isinstance(v, float) or (is_number(v) and "float" in type(v).__name__)


def _fmt(v: Any, spec: str | None = None) -> str:
    """One cell: ``spec`` is the column's number format (:func:`mechdyn.numbers.column_format`), or
    None for a number written on its own (:func:`mechdyn.numbers.number_text`)."""
    if v is None:
        return "—"
    if _is_float(v):
        return number_text(float(v), spec)
    return str(v)


# a terminal table longer than this shows its head and tail (a 10⁴-disk mode-shape table is 10⁴ rows)
MAX_ROWS = 40
_HEAD, _TAIL = 30, 5


def print_table(t: Table, file: Any = None, max_rows: int = MAX_ROWS) -> None:
    """Render a table with rich: its title on a line of its own, then the columns.

    A table of more than ``max_rows`` rows shows its first and last rows and says how many it left
    out (``--json`` and ``--csv`` keep every value).
    """
    from rich import box
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table as RichTable
    from rich.text import Text

    rows = list(t.rows)
    hidden = len(rows) - _HEAD - _TAIL if len(rows) > max_rows else 0
    if hidden:
        rows = [*rows[:_HEAD], ["⋮"] * len(t.columns), *rows[-_TAIL:]]
    # a table with a unit column holds another quantity in each row: each value is formatted on its own
    per_value = t.per_value or "unit" in t.columns
    specs = [None if per_value else column_format([r[i] for r in t.rows]) for i in range(len(t.columns))]
    cells = [[_fmt(v, specs[i]) if i < len(specs) else _fmt(v) for i, v in enumerate(r)] for r in rows]
    widths = [max([len(c), *(len(r[i]) for r in cells)]) for i, c in enumerate(t.columns)]
    # as wide as the table needs: a results table is never squeezed into dropping columns
    console = Console(file=file or sys.stdout, width=max(80, sum(widths) + 3 * len(widths)), highlight=False)
    rt = RichTable(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False)
    numeric_columns = [any(is_number(r[i]) for r in rows) for i in range(len(t.columns))]
    for i, c in enumerate(t.columns):
        numeric = all(is_number(r[i]) or r[i] is None or r[i] == "⋮" for r in rows)
        rt.add_column(escape(c), justify="right" if numeric and i else "left", no_wrap=True)
    for raw, r in zip(rows, cells, strict=True):  # numbers right-aligned in a column of mixed rows too
        rt.add_row(
            *(
                Text(
                    v,
                    justify="right" if i and (is_number(x) or (x is None and numeric_columns[i])) else "left",
                )
                for i, (x, v) in enumerate(zip(raw, r, strict=True))
            )
        )
    console.print(f"\n[bold]{escape(t.title)}[/bold]")
    console.print(rt)
    if t.note:  # a verdict under the table, wrapped, never stretching a column
        console.print(escape(t.note))
    if hidden:
        console.print(f"({hidden} of {len(t.rows)} rows not shown; --json has every value)")
