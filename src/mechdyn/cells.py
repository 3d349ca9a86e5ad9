"""A value as a table cell, and tables as HTML: one way for the reports, the dashboard and a
result's ``_repr_html_`` in a notebook (the numbers by :mod:`mechdyn.numbers`' one rule)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from mechdyn.numbers import number_text

__all__ = ["Cell", "HtmlTable", "html_table", "table_cell", "tables_html"]


@dataclass
class Cell:
    """A table cell as shown.

    Parameters
    ----------
    text : str
        What the cell reads.
    css : str
        Its CSS class: ``num`` aligns a number, ``holds`` and ``fails`` colour a verdict.
    """

    text: str
    css: str = ""


@dataclass
class HtmlTable:
    """A table as shown.

    Parameters
    ----------
    title : str
        Above the table.
    columns : list of str
        The column heads.
    rows : list of list of Cell
        The rows, one cell per column.
    note : str
        Below the table (its sources, what it leaves out).
    """

    title: str
    columns: list[str]
    rows: list[list[Cell]]
    note: str = ""


def table_cell(v: Any) -> Cell:
    """A value as a report's (and the dashboard's) table cell: a number written by the one rule of
    :mod:`mechdyn.numbers` and aligned as a number, a count as a whole number, a flag as yes or no,
    none as a dash.

    Parameters
    ----------
    v : any
        The cell's value (SI numbers already converted to the column's unit).
    """
    if v is None:
        return Cell("—")
    if isinstance(v, bool):
        return Cell("yes" if v else "no")
    if isinstance(v, int) or (type(v).__module__ == "numpy" and "int" in type(v).__name__):
        return Cell(str(int(v)), "num")  # a count stays a whole number
    if isinstance(v, float) or type(v).__module__ == "numpy":
        try:
            return Cell(number_text(float(v)), "num")
        except (TypeError, ValueError):
            pass
    if isinstance(v, str) and v in ("holds", "VIOLATED"):
        return Cell(v, "holds" if v == "holds" else "fails")
    if isinstance(v, (list, tuple)) and v and all(isinstance(x, (int, float)) for x in v):
        return Cell(", ".join(table_cell(x).text for x in v), "num")
    if isinstance(v, (list, tuple)) and all(isinstance(x, str) for x in v):
        return Cell(", ".join(v))  # names (a model's coordinates, the dominant one of each mode)
    if isinstance(v, (dict, list, tuple)):
        return Cell(json.dumps(v, default=str))
    return Cell(str(v))


def html_table(t: Any) -> HtmlTable:
    """A :class:`mechdyn.results.Table` as HTML cells.

    Parameters
    ----------
    t : Table
        Its title, columns, rows and note.
    """
    return HtmlTable(t.title, list(t.columns), [[table_cell(v) for v in row] for row in t.rows], t.note)


def tables_html(tables: Sequence[Any]) -> str:
    """Tables (:class:`mechdyn.results.Table`) as an HTML fragment, each with its title and note, the
    cells as the report writes them (a result's ``_repr_html_`` in a notebook).

    Parameters
    ----------
    tables : sequence of Table
    """
    from html import escape

    parts = []
    for t in map(html_table, tables):
        head = "".join(f"<th>{escape(c)}</th>" for c in t.columns)
        body = "".join(
            "<tr>" + "".join(f'<td class="{c.css}">{escape(c.text)}</td>' for c in row) + "</tr>"
            for row in t.rows
        )
        parts.append(
            f"<h4>{escape(t.title)}</h4><table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
        )
        if t.note:
            parts.append(f"<p>{escape(t.note)}</p>")
    return "\n".join(parts)
