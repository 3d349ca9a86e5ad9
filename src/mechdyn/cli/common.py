"""What the commands share: the table renderer."""

from __future__ import annotations

import math
import sys
from typing import Any

from mechdyn.results import Table

__all__ = ["Table", "print_table"]


def _is_number(v: Any) -> bool:
    if isinstance(v, bool):
        return False
    return isinstance(v, (int, float)) or type(v).__module__ == "numpy"


def _fmt(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, float) or (_is_number(v) and "float" in type(v).__name__):
        v = float(v)
        if not math.isfinite(v):
            return "—"
        a = abs(v)
        if a == 0:
            return "0"
        if 1e-3 <= a < 1e7:  # 5 significant digits without an exponent
            return f"{v:.{max(0, 4 - math.floor(math.log10(a)))}f}"
        return f"{v:.4e}"
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

    rows = list(t.rows)
    hidden = len(rows) - _HEAD - _TAIL if len(rows) > max_rows else 0
    if hidden:
        rows = [*rows[:_HEAD], ["⋮"] * len(t.columns), *rows[-_TAIL:]]
    cells = [[_fmt(v) for v in r] for r in rows]
    widths = [max([len(c), *(len(r[i]) for r in cells)]) for i, c in enumerate(t.columns)]
    # as wide as the table needs: a results table is never squeezed into dropping columns
    console = Console(file=file or sys.stdout, width=max(80, sum(widths) + 3 * len(widths)), highlight=False)
    rt = RichTable(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False)
    for i, c in enumerate(t.columns):
        numeric = all(_is_number(r[i]) or r[i] is None or r[i] == "⋮" for r in rows)
        rt.add_column(escape(c), justify="right" if numeric and i else "left", no_wrap=True)
    for r in cells:
        rt.add_row(*(escape(v) for v in r))
    console.print(f"\n[bold]{escape(t.title)}[/bold]")
    console.print(rt)
    if hidden:
        console.print(f"({hidden} of {len(t.rows)} rows not shown; --json has every value)")
