"""What the commands share: the table renderer."""

from __future__ import annotations

import math
import sys
from typing import Any

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


def _is_number(v: Any) -> bool:
    if isinstance(v, bool):
        return False
    return isinstance(v, (int, float)) or type(v).__module__ == "numpy"


def _is_float(v: Any) -> bool:
    return isinstance(v, float) or (_is_number(v) and "float" in type(v).__name__)


def _no_negative_zero(text: str) -> str:
    """``-0``, ``-0.000`` and ``-0.0000e+00`` are zero: print them without the sign."""
    mantissa = text[1:].split("e")[0]
    return text[1:] if text.startswith("-") and not mantissa.strip("0.") else text


def _fmt(v: Any, spec: str | None = None) -> str:
    """One cell: ``spec`` is the column's number format (from :func:`_column_spec`), or None for a
    number formatted on its own (5 significant digits)."""
    if v is None:
        return "—"
    if _is_float(v):
        v = float(v)
        if not math.isfinite(v):
            return "—"
        if spec is None:
            a = abs(v)
            if a == 0:
                return "0"
            spec = f".{max(0, 4 - math.floor(math.log10(a)))}f" if 1e-3 <= a < 1e7 else ".4e"
        return _no_negative_zero(format(v, spec))
    return str(v)


# values below this fraction of a column's largest are shown as near zero, not given digits of their own
_MATTERS = 1e-3


def _column_spec(values: list[Any]) -> str | None:
    """One number format for a column of numbers: fixed point with four significant digits for the
    smallest magnitude that matters (at least a thousandth of the largest; smaller ones show as
    near zero), unless the largest would then need more than nine digits (then exponents for the
    whole column). None when the column holds anything but numbers (each row is then another
    quantity, formatted on its own)."""
    numbers = [float(v) for v in values if _is_float(v) and math.isfinite(float(v))]
    if not numbers or any(not (_is_number(v) or v is None) for v in values):
        return None
    largest = max(abs(x) for x in numbers)
    if largest == 0:
        return ".0f"
    smallest = min(abs(x) for x in numbers if abs(x) >= _MATTERS * largest)
    decimals = max(0, 3 - math.floor(math.log10(smallest)))
    digits = math.floor(math.log10(largest)) + 1 + decimals
    if largest < 1e7 and digits <= 9 and decimals <= 6:
        return f".{decimals}f"
    return ".4e"


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
    per_value = "unit" in t.columns
    specs = [None if per_value else _column_spec([r[i] for r in t.rows]) for i in range(len(t.columns))]
    cells = [[_fmt(v, specs[i]) if i < len(specs) else _fmt(v) for i, v in enumerate(r)] for r in rows]
    widths = [max([len(c), *(len(r[i]) for r in cells)]) for i, c in enumerate(t.columns)]
    # as wide as the table needs: a results table is never squeezed into dropping columns
    console = Console(file=file or sys.stdout, width=max(80, sum(widths) + 3 * len(widths)), highlight=False)
    rt = RichTable(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False)
    numeric_columns = [any(_is_number(r[i]) for r in rows) for i in range(len(t.columns))]
    for i, c in enumerate(t.columns):
        numeric = all(_is_number(r[i]) or r[i] is None or r[i] == "⋮" for r in rows)
        rt.add_column(escape(c), justify="right" if numeric and i else "left", no_wrap=True)
    for raw, r in zip(rows, cells, strict=True):  # numbers right-aligned in a column of mixed rows too
        rt.add_row(
            *(
                Text(
                    v,
                    justify="right"
                    if i and (_is_number(x) or (x is None and numeric_columns[i]))
                    else "left",
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
