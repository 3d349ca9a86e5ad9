"""The dashboard's HTML pages: the lists of runs and studies, a run's page, runs or variants compared
side by side, a study's page and its findings (each a plain function of the shared
:class:`~mechdyn.dashboard.state.DashboardState` and the request, run in Starlette's thread pool).

Every value from the database is escaped by the templates; a missing run or study, or an id no
database column can hold, is a 404 page.
"""

from __future__ import annotations

import base64
import json
import struct
from datetime import date, datetime
from typing import Any

from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import HTMLResponse

from mechdyn.dashboard.state import MAX_ID, DashboardState, Findings
from mechdyn.dashboard.study_data import PAGE_SIZE
from mechdyn.reports.html import table_cell, toml_text
from mechdyn.store.store import StoreError
from mechdyn.studies.storage import StoredStudy

__all__ = [
    "FINDINGS_WAIT",
    "RUNS_PER_PAGE",
    "compare",
    "index",
    "not_found",
    "run_page",
    "study_findings",
    "study_page",
]

RUNS_PER_PAGE = 100
FINDINGS_WAIT = 0.5  # seconds a study page waits for its findings before it fetches them when ready


def _date(text: str | None) -> date | None:
    try:
        return date.fromisoformat(text) if text else None
    except ValueError:
        return None


def _png_size(head: bytes) -> tuple[int, int] | None:
    """Width and height in pixels from the first bytes of a PNG (its IHDR chunk), None if not a PNG."""
    if head[:8] != b"\x89PNG\r\n\x1a\n" or len(head) < 24:
        return None
    width, height = struct.unpack(">II", head[16:24])
    return int(width), int(height)


def _utc(t: datetime) -> str:
    return t.strftime("%Y-%m-%d %H:%M:%S")


def _line_figures(
    curves: list[tuple[str, dict[str, tuple[Any, str]]]], limit: int = 4
) -> list[dict[str, Any]]:
    """Plotly figures of curves kept by one or several runs or variants, overlaid: the curves that
    differ most between them, against their time or angle (:func:`mechdyn.studies.plots.choose_curves`)."""
    import numpy as np

    from mechdyn.studies.plots import choose_curves

    x, names = choose_curves([c for _, c in curves], limit)
    if x is None or not names:  # no curve kept, or none that all of them keep
        return []
    from mechdyn.units import SHOWN_UNITS, convert, key_label, readable_unit

    def shown(key: str, unit: str, arrays: list[Any]) -> tuple[str, str, float]:
        """A curve's name in words, its unit as a designer reads it at its size, and the factor."""
        words = key_label(key)[0] if unit else key.replace("_", " ")
        pretty = SHOWN_UNITS.get(unit, unit)
        big = max((float(np.nanmax(np.abs(a))) for a in arrays if np.size(a)), default=0.0)
        display, label = readable_unit(big, pretty) if unit else (unit, unit)
        factor = float(convert(1.0, unit, display)) if unit and display != unit else 1.0
        return words, label, factor

    x_words, x_unit, x_factor = shown(x, curves[0][1][x][1], [c[x][0] for _, c in curves])
    x_title = f"{x_words} ({x_unit})" if x_unit else x_words
    figures = []
    for name in names:
        arrays = [np.asarray(c[name][0], dtype=np.float64) for _, c in curves]
        words, unit, factor = shown(name, curves[0][1][name][1], arrays)
        data = [
            {
                "x": (np.asarray(c[x][0], dtype=np.float64) * x_factor).tolist(),
                "y": (y * factor).tolist(),
                "name": label,
                "mode": "lines",
                "type": "scatter",
            }
            for (label, c), y in zip(curves, arrays, strict=True)
        ]
        layout = {
            "title": {"text": words},
            "xaxis": {"title": {"text": x_title}},
            "yaxis": {"title": {"text": f"{words} ({unit})" if unit else words}},
            "margin": {"t": 40},
        }
        figures.append({"data": data, "layout": layout})
    return figures


def _nested_rows(values: dict[str, Any], prefix: str = "") -> Any:
    """(label, value) of every value, a nested mapping's items as "name · item" rows."""
    for k, v in values.items():
        if isinstance(v, dict):
            yield from _nested_rows(v, f"{prefix}{k} · ")
        else:
            yield f"{prefix}{k}", v


def _is_value(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _compare_row(
    key: str, cells: list[Any], shown: dict[str, Any], given: bool
) -> tuple[str, str, list[Any]]:
    """One row of the compare page: the key in words, the one unit of the row, each column's value in it.

    ``cells`` are SI values as stored (a study's parameters as its file wrote them, when ``given``);
    ``shown`` maps a study's keys to their :class:`~mechdyn.reports.columns.Column`. A nested item
    (``"joint_force_peak_N · A"``) takes the unit its own name says, else its group's.
    """
    from mechdyn.units import SHOWN_UNITS, convert, key_label, key_unit, readable_unit

    if given:  # a parameter as its study file wrote it, with its unit ("25 mm")
        return key.replace("_", " "), "", [table_cell(c) for c in cells]
    parts = key.split(" · ")
    words = " · ".join(key_label(p)[0] if n == 0 or "_" in p else p for n, p in enumerate(parts))
    column = shown.get(key)
    if column is not None and column.role == "output":  # in its study file's unit
        unit = SHOWN_UNITS.get(column.unit.replace(" ", ""), column.unit)  # "N*m" as "N·m"
        return words, unit, [table_cell(column.shown(c) if _is_value(c) else c) for c in cells]
    named = [(key_unit(p), key_label(p)[1]) for p in reversed(parts)]
    si, unit = next(((u, label) for u, label in named if u not in (None, "1")), ("", ""))
    numbers = [abs(float(x)) for c in cells for x in _numbers(c)]
    if not si or not numbers:  # a number without unit, a count, a text
        return words, unit, [table_cell(c) for c in cells]
    display, label = readable_unit(max(numbers), unit)

    def shown_in(c: Any) -> Any:
        if _is_value(c):
            return float(convert(float(c), si, display))
        if _numbers(c):  # a vector (a force's x, y, z ranges) in the same unit
            return [float(convert(float(x), si, display)) for x in c]
        return c

    return words, label, [table_cell(shown_in(c)) for c in cells]


def _numbers(v: Any) -> list[Any]:
    """The numbers of a value that is a number (not a count) or a list of numbers, else none."""
    if _is_value(v) and not isinstance(v, int):
        return [v]
    if isinstance(v, (list, tuple)) and v and all(_is_value(x) for x in v):
        return list(v)
    return []


def _compare_tables(items: list[dict[str, Any]], rows: Any) -> list[tuple[str, list[Any]]]:
    """The compare page's tables: the values of the runs (or variants) themselves, then one table per
    nested value (the excitation's figures, a force per joint), titled in words, its rows the items.

    ``rows(keys)`` makes the rows of some keys (:func:`_compare_row` for each)."""
    from mechdyn.units import key_label

    keys = list(dict.fromkeys(k for row in items for k in row))
    groups: dict[str, list[str]] = {"": []}
    for k in keys:
        group = k.split(" · ")[0] if " · " in k else ""
        groups.setdefault(group, []).append(k)
    out = []
    for group, members in groups.items():
        made = rows(members)
        if group:
            title = key_label(group)[0]
            made = [(label.split(" · ", 1)[1], u, cells) for label, u, cells in made]
            title = title[:1].upper() + title[1:]
        else:
            title = ""
        if made:
            out.append((title, made))
    return out


def _page(state: DashboardState, name: str, status: int = 200, **context: Any) -> HTMLResponse:
    html = state.templates.get_template(name).render(database=state.store.label, **context)
    return HTMLResponse(html, status_code=status)


def _missing(state: DashboardState, message: str) -> HTMLResponse:
    return _page(state, "missing.html.j2", 404, message=message)


async def not_found(state: DashboardState, request: Request, exc: Exception) -> HTMLResponse:
    """The 404 page for an address the dashboard does not have."""
    return _missing(state, f"There is nothing at {request.url.path}.")


def _study_of(state: DashboardState, request: Request) -> StoredStudy | None:
    return state.study(request.path_params["study_id"])


def index(state: DashboardState, request: Request) -> HTMLResponse:
    """The lists of studies and runs, filtered (analysis, model, dates, study name), the runs
    paged by the database."""
    studies = state.studies
    q = request.query_params
    filters = {k: q.get(k, "") for k in ("analysis", "model", "since", "until", "study")}
    since, until = _date(filters["since"]), _date(filters["until"])
    # the runs are filtered and paged by the database query: the count is every match
    matching: dict[str, Any] = {
        "analysis": filters["analysis"] or None,
        "model": filters["model"] or None,
        "since": since,
        "until": until,
    }
    total = state.store.count_runs(**matching)
    pages = max(1, -(-total // RUNS_PER_PAGE))
    try:
        number = min(max(1, int(q.get("page", "1"))), pages)
    except ValueError:
        number = 1
    runs = state.store.runs(**matching, limit=RUNS_PER_PAGE, offset=(number - 1) * RUNS_PER_PAGE)

    def keep(created: datetime, model: str) -> bool:
        d = created.date()
        return (
            (since is None or d >= since)
            and (until is None or d <= until)
            and filters["model"].lower() in model.lower()
        )

    rows = []
    for s in studies.studies():
        if filters["study"].lower() not in s.name.lower():
            continue
        if filters["analysis"] and s.analysis != filters["analysis"]:
            continue
        if not keep(s.created_at, s.model_path):
            continue
        counts = studies.counts(s.id)
        rows.append(
            {
                "headline": _study_headline(state, s, counts["variants"]),
                "id": s.id,
                "name": s.name,
                "kind": s.kind,
                "analysis": s.analysis,
                "model": s.model_path,
                "variants": counts["variants"],
                "failed": counts["failed"],
                "created": _utc(s.created_at),
            }
        )
    from mechdyn.registry import analyses

    return _page(
        state,
        "index.html.j2",
        filters=filters,
        analyses=list(analyses()),
        studies=rows,
        runs=[
            {
                "id": r.id,
                "headline": _run_headline(r),
                "analysis": r.analysis,
                "model_name": r.model_name,
                "model_path": r.model_path,
                "created": _utc(r.created_at),
            }
            for r in runs
        ],
        total=total,
        first=(number - 1) * RUNS_PER_PAGE + 1,
        page=number,
        pages=pages,
        query={k: v for k, v in filters.items() if v},
    )


def _run_headline(r: Any) -> str:
    """The first figures of a run, as its report's headline says them."""
    from mechdyn.registry import analyses
    from mechdyn.reports.html import headline

    keys = analyses()[r.analysis].headline if r.analysis in analyses() else ()
    lines = headline(r.scalars, keys[:2])
    return lines[0] if lines else ""


def _study_headline(state: DashboardState, st: StoredStudy, variants: int | None = None) -> str:
    """A study's figure in the list: the first line its kind leads with where its findings for its
    ``variants`` stored variants are worked out and kept (a tolerance study: its first limit's
    probability), else its objective's best (an optimization) or range over the variants that
    succeeded, in the study file's unit."""
    from mechdyn.numbers import number_text

    kept = state.kept_findings(st, variants) if variants is not None else None
    if kept is not None and kept.views is not None and kept.views.headline:
        return str(kept.views.headline[0])

    data = state.study_data(st)
    views = state.study_views(st, data.columns)
    column = views["objective"]
    if not 0 <= column < len(data.columns) or data.columns[column].role != "output":
        return ""
    lo, hi = data.extremes(column)
    if lo is None or hi is None:
        return ""
    c = data.columns[column]
    unit = f" {c.unit}" if c.unit else ""
    sense = views["senses"].get(str(column))
    if sense:
        best = hi if sense == "maximize" else lo
        return f"best {c.key} {number_text(best)}{unit}"
    return f"{c.key} {number_text(lo)} to {number_text(hi)}{unit}"


def run_page(state: DashboardState, request: Request) -> HTMLResponse:
    """A run's page: its figures in words and units, its warnings, its curves; for a test
    (``modes-from-test``), the model against the measurement (:mod:`mechdyn.dashboard.measured`)."""
    run_id = request.path_params["run_id"]
    if run_id > MAX_ID:
        return _missing(state, f"There is no run {run_id} in this database.")
    try:
        run = state.store.get(run_id)
    except StoreError:
        return _missing(state, f"There is no run {run_id} in this database.")
    from mechdyn.results import nested_tables, summary_table
    from mechdyn.units import key_label

    # as the report shows it: in words and in the units a designer reads, nested values by name
    scalars = run.scalars
    summary = [
        (str(r[0]) if t.title == "summary" else f"{t.title} · {r[0]}", table_cell(r[1]), r[2])
        for t in [summary_table(scalars), *nested_tables(scalars)]
        for r in t.rows
    ]
    for k, v in scalars.items():  # lists of numbers (natural frequencies) in one row each
        if k != "warnings" and isinstance(v, list) and all(isinstance(x, (int, float)) for x in v):
            label, unit = key_label(k)
            summary.append((label, table_cell(v), unit))
    figures = _line_figures([(f"run {run.id}", run.arrays)])
    return _page(
        state,
        "run.html.j2",
        run=run,
        created=_utc(run.created_at),
        options=json.dumps(run.parameters, ensure_ascii=False),
        summary=summary,
        warnings=run.scalars.get("warnings") or [],
        figures=figures,
        measured=_measured(state, run),
    )


def _measured(state: DashboardState, run: Any) -> dict[str, Any] | None:
    """A stored test's model against its measurement as its page shows it: a link to the FRF overlay
    (drawn once the browser asks for it, :func:`mechdyn.dashboard.api.run_overlay`; its address
    names the state of the files it is drawn from, and its size in pixels is given once drawn), the
    note, and the pairing table's cells; None for a run of another analysis."""
    import hashlib

    from mechdyn.dashboard.measured import files_key

    view = state.measured_view(run)
    if view is None:
        return None
    key = files_key(run)
    kept = state.kept_overlay(run, key)
    stamp = hashlib.sha256(repr(key).encode()).hexdigest()[:16]
    return {
        "url": f"/runs/{run.id}/overlay.png?files={stamp}" if view.drawn else None,
        "caption": view.caption,
        "size": _png_size(base64.b64decode(kept.data[:64])) if kept is not None else None,
        "note": view.note,
        "columns": [f"{h} ({u})" if u else h for h, u in view.columns],
        "rows": [[table_cell(v) for v in row] for row in view.rows],
    }


def compare(state: DashboardState, request: Request) -> HTMLResponse:
    """Runs (``?run=``) or variants (``?variant=``) side by side: their values, each row in one
    unit, and their curves overlaid (a variant's recomputed where they were not kept)."""
    store, studies = state.store, state.studies
    q = request.query_params
    try:
        run_ids = [int(x) for x in q.getlist("run")]
        variant_ids = [int(x) for x in q.getlist("variant")]
    except ValueError:
        return _missing(state, "Runs and variants are given by their numbers.")
    if any(not 0 < i <= MAX_ID for i in (*run_ids, *variant_ids)):
        return _missing(state, "There is no run or variant of that number in this database.")
    columns: list[str] = []
    notes: list[str] = []
    values: list[dict[str, Any]] = []
    shown: dict[str, Any] = {}  # key -> the study's column that shows it (its unit and conversion)
    curves: list[tuple[str, dict[str, Any]]] = []
    try:
        for i in run_ids:
            r = store.get(i)
            columns.append(f"run {i} ({r.model_name})")
            values.append({k: v for k, v in r.scalars.items() if k != "warnings"})
            curves.append((f"run {i}", r.arrays))
        for i in variant_ids:
            v = studies.variant(i)
            columns.append(f"variant {i} ({v.study})")
            st = studies.study(v.study)
            for c in state.shown_columns(st):  # the first study that names a key gives its row's unit
                shown.setdefault(c.key, c)
            # parameters as the study file wrote them ("25 mm"); outputs in SI, shown per row below
            values.append({**v.given, **dict(v.outputs), "status": v.status})
            again, why = state.recomputed(i) if not v.curves else ({}, None)
            kept = v.curves or again
            if kept:
                curves.append((f"variant {i}", kept))
                if not v.curves:
                    notes.append(f"variant {i}: curves not kept; recomputed from its stored inputs")
            elif why is not None:
                notes.append(f"variant {i}: curves not kept, and not recomputed: {why}")
    except StoreError as exc:
        return _missing(state, str(exc))
    # a nested value (a force per joint, a gear pair's figures) is a row per item; every row is in
    # one unit for all columns: a study's output in its study file's unit, anything else in the
    # unit a designer reads its largest value in (a 530 kN force in kN, a stroke in mm)
    items = [dict(_nested_rows(row)) for row in values]
    given = {k for i in variant_ids for k in studies.variant(i).given} if variant_ids else set()
    tables = _compare_tables(
        items,
        lambda keys: [_compare_row(k, [row.get(k) for row in items], shown, k in given) for k in keys],
    )
    what = "runs" if run_ids else "variants"
    heading = f"{len(columns)} {what} side by side" if columns else "Compare"
    return _page(
        state,
        "compare.html.j2",
        heading=heading,
        what=what,
        columns=columns,
        tables=tables,
        notes=notes,
        figures=_line_figures(curves) if len(curves) == len(columns) else [],
    )


def study_page(state: DashboardState, request: Request) -> HTMLResponse:
    """A study's page: its counts, findings (once ready), views, what-if sliders, the first page
    of its table and its definition."""
    st = _study_of(state, request)
    if st is None:
        return _missing(state, f"There is no study {request.path_params['study_id']} in this database.")
    data = state.study_data(st)
    counts = state.studies.counts(st.id)
    shown = data.columns
    ready = state.findings(st, counts["variants"], FINDINGS_WAIT)
    table = data.page(limit=PAGE_SIZE)
    return _page(
        state,
        "study.html.j2",
        findings=ready.tables if ready else [],
        figures=_figure_links(st, ready) if ready else [],
        findings_note=ready.note if ready else "",
        findings_ready=ready is not None,
        kind_views=ready.views if ready else None,
        study=st,
        counts=counts,
        created=_utc(st.created_at),
        axes=[c.label for c in shown],
        levels=[list(c.levels) for c in shown],
        roles=[c.role for c in shown],
        views=state.study_views(st, shown),
        sliders=(w.sliders() if (w := state.what_if(st)) is not None else []),
        keep_designs=state.keep_designs,
        table=[{**row, "cells": [table_cell(x) for x in row["values"]]} for row in table],
        page_size=PAGE_SIZE,
        definition=toml_text(st.definition),
        python="study" not in st.definition,
    )


def study_findings(state: DashboardState, request: Request) -> HTMLResponse:
    """The findings section alone, once ready (HTTP 202 while they are worked out)."""
    st = _study_of(state, request)
    if st is None:
        raise HTTPException(404)
    n_variants = state.studies.counts(st.id)["variants"]
    ready = state.findings(st, n_variants, FINDINGS_WAIT)
    if ready is None:
        return HTMLResponse("", status_code=202)
    html = state.templates.get_template("findings.html.j2").render(
        findings=ready.tables,
        figures=_figure_links(st, ready),
        findings_note=ready.note,
        kind_views=ready.views,
    )
    return HTMLResponse(html)


def _figure_links(st: StoredStudy, ready: Findings) -> list[dict[str, Any]]:
    """The findings' pictures as links the browser loads when they come near the window (a page
    that carried them inline would be megabytes of text to read before anything is drawn), each
    with its size in pixels so that the page does not move as they arrive; a link names the number
    of variants its findings are of (:func:`mechdyn.dashboard.api.study_figure`)."""
    return [
        {
            "url": f"/studies/{st.id}/findings/{n}.png?variants={ready.variants}",
            "caption": f.caption,
            "size": _png_size(base64.b64decode(f.data[:64])),
        }
        for n, f in enumerate(ready.figures)
    ]
