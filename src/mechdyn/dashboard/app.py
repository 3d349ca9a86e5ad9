"""The web dashboard over a results database (``mechdyn dashboard``).

Starlette (a small, maintained ASGI toolkit) with Jinja2 templates, served by uvicorn; interactive
plots by Plotly.js: the part of it that the pages draw with (scatter, bar, WebGL scatter, 2-D histogram
contour, parallel coordinates), built by ``scripts/build-plotly-bundle`` and shipped in the package
(never a CDN: the machines that run it may have no internet); a third of the full bundle, which a
browser takes seconds to read before it draws anything.

- The database is opened read-only, and checked at start (a mechdyn database of this schema).
- A request reaches it only as integer ids and filter values bound as SQL parameters, never as a
  file path; every value from the database is escaped by the templates; a missing run or study,
  or an id no database column can hold, is a 404 page.
- Requests are answered only for trusted host names (loopback by default), so a page that rebinds
  its DNS name to this machine cannot read it; pages name the database, never its location.
- The handlers are plain functions, run in Starlette's thread pool: a slow page never stalls the
  others; a study's findings and pictures are drawn once per stored state and kept.
"""

from __future__ import annotations

import base64
import json
import struct
import threading
from collections.abc import Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from concurrent.futures import TimeoutError as FuturesTimeout
from contextlib import asynccontextmanager
from datetime import date, datetime
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.dashboard.study_data import PAGE_SIZE, StudyData
from mechdyn.reports.html import table_cell, toml_text
from mechdyn.store.store import ResultStore, StoreError
from mechdyn.studies.storage import StudyStore

__all__ = ["create_app"]

RUNS_PER_PAGE = 100
FINDINGS_WAIT = 0.5  # seconds a study page waits for its findings before it fetches them when ready
Findings = tuple[list[Any], list[Any], str, dict[str, Any]]  # tables, pictures, a note, Sobol indices
MAX_ID = 2**31 - 1  # the largest id an integer column holds on every backend
LOOPBACK_HOSTS = ("127.0.0.1", "localhost", "::1", "[::1]")


def _plotly_js() -> Path:
    return Path(__file__).parent / "static" / "plotly-mechdyn.min.js"


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
    from mechdyn.reports.html import table_cell
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


def _loopback(host: str) -> bool:
    import ipaddress

    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return host == "localhost"


def create_app(url: str | None = None, allowed_hosts: Sequence[str] = (), keep_designs: bool = False) -> Any:
    """The dashboard application over the results database at ``url`` (opened read-only).

    Parameters
    ----------
    url : str, optional
        A SQLite file or a SQLAlchemy URL (default: ``MECHDYN_DB``, else ``mechdyn.db``).
    allowed_hosts : sequence of str
        Host names (``Host`` header) answered besides the loopback names; a request for any other
        host gets HTTP 400.
    keep_designs : bool
        Let a study's what-if form keep a design as a new variant of that study (the only write
        the dashboard can make, through a second connection opened for it); off by default.

    Returns
    -------
    starlette.applications.Starlette
    """
    from jinja2 import Environment, PackageLoader, select_autoescape
    from starlette.applications import Starlette
    from starlette.exceptions import HTTPException
    from starlette.middleware import Middleware
    from starlette.middleware.trustedhost import TrustedHostMiddleware
    from starlette.requests import Request
    from starlette.responses import FileResponse, HTMLResponse, JSONResponse, Response
    from starlette.routing import Route

    store = ResultStore(url, read_only=True)
    studies = StudyStore(store)
    env = Environment(
        loader=PackageLoader("mechdyn.dashboard", "templates"), autoescape=select_autoescape(default=True)
    )
    plotly_js = _plotly_js()

    def page(name: str, status: int = 200, **context: Any) -> HTMLResponse:
        html = env.get_template(name).render(database=store.label, **context)
        return HTMLResponse(html, status_code=status)

    def missing(message: str) -> HTMLResponse:
        return page("missing.html.j2", 404, message=message)

    # a study's findings (its kind's tables and pictures, from every stored variant) are worked out
    # in one background thread, once per number of stored variants (a running study adds variants);
    # a page asks and shows them at once if ready within FINDINGS_WAIT, else fetches them when ready
    findings_pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="mechdyn-findings")
    findings_lock = threading.Lock()
    kept: dict[tuple[int, int], Future[Findings]] = {}
    shown_as: dict[int, list[Any]] = {}

    def shown_columns(st: Any) -> list[Any]:
        """A study's parameters and outputs as its study file shows them (SI for a study built in
        Python, read from its first variants), rebuilt once per study (its definition does not
        change)."""
        from mechdyn.reports.columns import stored_columns

        if st.id not in shown_as:
            shown_as[st.id] = stored_columns(store, st.name, studies.variants(st.name, limit=10))
        return shown_as[st.id]

    def work_out_findings(st: Any) -> Findings:
        from mechdyn.errors import MechdynError
        from mechdyn.reports.html import figures_of, study_tables
        from mechdyn.studies.run import stored_result
        from mechdyn.studies.spec import StudyError

        try:
            study_data(st).warm()  # every value read once: the views over every variant then cost no query
            result = stored_result(store, st.name)
            indices = result.findings.get("indices", {}) if st.kind == "sobol" else {}
            return study_tables(result), figures_of(result.plots()), "", indices
        except (StudyError, StoreError, MechdynError) as exc:
            return [], [], f"The findings appear when every variant is stored: {exc}", {}

    def findings(st: Any, n_variants: int, wait: float | None) -> Findings | None:
        """The study's findings, or None if not ready within ``wait`` seconds (None: until ready)."""
        key = (st.id, n_variants)
        with findings_lock:
            if key not in kept:
                kept[key] = findings_pool.submit(work_out_findings, st)
            future = kept[key]
        try:
            return future.result(timeout=wait)
        except FuturesTimeout:
            return None

    def study_data(st: Any) -> StudyData:
        return StudyData(store.engine, st.id, shown_columns(st))

    def index(request: Request) -> HTMLResponse:
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
        total = store.count_runs(**matching)
        pages = max(1, -(-total // RUNS_PER_PAGE))
        try:
            number = min(max(1, int(q.get("page", "1"))), pages)
        except ValueError:
            number = 1
        runs = store.runs(**matching, limit=RUNS_PER_PAGE, offset=(number - 1) * RUNS_PER_PAGE)

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
                    "headline": study_headline(s),
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

        return page(
            "index.html.j2",
            filters=filters,
            analyses=list(analyses()),
            studies=rows,
            runs=[
                {
                    "id": r.id,
                    "headline": run_headline(r),
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

    def run_headline(r: Any) -> str:
        """The first figures of a run, as its report's headline says them."""
        from mechdyn.registry import analyses
        from mechdyn.reports.html import headline

        keys = analyses()[r.analysis].headline if r.analysis in analyses() else ()
        lines = headline(r.scalars, keys[:2])
        return lines[0] if lines else ""

    def study_headline(st: Any) -> str:
        """A study's figure in the list: its objective's best (an optimization) or range over the
        variants that succeeded, in the study file's unit."""
        from mechdyn.numbers import number_text

        data = study_data(st)
        views = study_views(st, data.columns)
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

    def run_page(request: Request) -> HTMLResponse:
        run_id = request.path_params["run_id"]
        if run_id > MAX_ID:
            return missing(f"There is no run {run_id} in this database.")
        try:
            run = store.get(run_id)
        except StoreError:
            return missing(f"There is no run {run_id} in this database.")
        from mechdyn.reports.html import table_cell
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
        return page(
            "run.html.j2",
            run=run,
            created=_utc(run.created_at),
            options=json.dumps(run.parameters, ensure_ascii=False),
            summary=summary,
            warnings=run.scalars.get("warnings") or [],
            figures=figures,
        )

    def compare(request: Request) -> HTMLResponse:
        q = request.query_params
        try:
            run_ids = [int(x) for x in q.getlist("run")]
            variant_ids = [int(x) for x in q.getlist("variant")]
        except ValueError:
            return missing("Runs and variants are given by their numbers.")
        if any(not 0 < i <= MAX_ID for i in (*run_ids, *variant_ids)):
            return missing("There is no run or variant of that number in this database.")
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
                for c in shown_columns(st):  # the first study that names a key gives its row's unit
                    shown.setdefault(c.key, c)
                # parameters as the study file wrote them ("25 mm"); outputs in SI, shown per row below
                values.append({**v.given, **dict(v.outputs), "status": v.status})
                kept = v.curves or recomputed(i)
                if kept:
                    curves.append((f"variant {i}", kept))
                    if not v.curves:
                        notes.append(f"variant {i}: curves not kept; recomputed from its stored inputs")
                elif i in failed_again:
                    notes.append(f"variant {i}: curves not kept, and not recomputed: {failed_again[i]}")
        except StoreError as exc:
            return missing(str(exc))
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
        return page(
            "compare.html.j2",
            heading=heading,
            what=what,
            columns=columns,
            tables=tables,
            notes=notes,
            figures=_line_figures(curves) if len(curves) == len(columns) else [],
        )

    again: dict[int, dict[str, Any]] = {}
    failed_again: dict[int, str] = {}
    again_lock = threading.Lock()

    def recomputed(variant_id: int) -> dict[str, Any]:
        """A variant's curves worked out again from its stored inputs (the study's definition, the
        model files as stored, its parameters), kept in memory; nothing is written. Empty where that
        cannot be done (the error is kept for the page)."""
        from mechdyn.errors import MechdynError
        from mechdyn.studies.run import recompute

        with again_lock:
            if variant_id not in again and variant_id not in failed_again:
                try:
                    found = recompute(store, variant_id, batch=False, curves=True)
                    again[variant_id] = dict(found.curves)
                    if not found.curves:
                        failed_again[variant_id] = found.error or "its analysis keeps no curve"
                except (MechdynError, StoreError) as exc:
                    failed_again[variant_id] = str(exc)
            return again.get(variant_id, {})

    def study_of(request: Request) -> Any:
        study_id = request.path_params["study_id"]
        return studies.study_by_id(study_id) if study_id <= MAX_ID else None

    def study_page(request: Request) -> HTMLResponse:
        st = study_of(request)
        if st is None:
            return missing(f"There is no study {request.path_params['study_id']} in this database.")
        data = study_data(st)
        counts = studies.counts(st.id)
        shown = data.columns
        ready = findings(st, counts["variants"], FINDINGS_WAIT)
        table = data.page(limit=PAGE_SIZE)
        return page(
            "study.html.j2",
            findings=ready[0] if ready else [],
            figures=figure_links(st, counts["variants"], ready[1]) if ready else [],
            findings_note=ready[2] if ready else "",
            findings_ready=ready is not None,
            study=st,
            counts=counts,
            created=_utc(st.created_at),
            axes=[c.label for c in shown],
            levels=[list(c.levels) for c in shown],
            roles=[c.role for c in shown],
            views=study_views(st, shown),
            sliders=(w.sliders() if (w := what_if_of(st)) is not None else []),
            keep_designs=keep_designs,
            table=[{**row, "cells": [table_cell(x) for x in row["values"]]} for row in table],
            page_size=PAGE_SIZE,
            definition=toml_text(st.definition),
            python="study" not in st.definition,
        )

    def study_findings(request: Request) -> HTMLResponse:
        """The findings section alone, once ready (HTTP 202 while they are worked out)."""
        st = study_of(request)
        if st is None:
            raise HTTPException(404)
        n_variants = studies.counts(st.id)["variants"]
        ready = findings(st, n_variants, FINDINGS_WAIT)
        if ready is None:
            return HTMLResponse("", status_code=202)
        tables, figures, note, _ = ready
        html = env.get_template("findings.html.j2").render(
            findings=tables, figures=figure_links(st, n_variants, figures), findings_note=note
        )
        return HTMLResponse(html)

    def figure_links(st: Any, n_variants: int, figures: Sequence[Any]) -> list[dict[str, Any]]:
        """The findings' pictures as links the browser loads when they come near the window (a page
        that carried them inline would be megabytes of text to read before anything is drawn), each
        with its size in pixels so that the page does not move as they arrive."""
        return [
            {
                "url": f"/studies/{st.id}/findings/{n}.png?variants={n_variants}",
                "caption": f.caption,
                "size": _png_size(base64.b64decode(f.data[:64])),
            }
            for n, f in enumerate(figures)
        ]

    def study_figure(request: Request) -> Response:
        """One picture of a study's findings for the number of variants its link names (the findings of
        that state, kept; no query), 404 if they are not worked out or there is no such picture."""
        st = study_of(request)
        if st is None:
            raise HTTPException(404)
        n_variants = _int(request.query_params, "variants", -1)
        with findings_lock:
            future = kept.get((st.id, n_variants))
        n = request.path_params["n"]
        if future is None or not future.done() or n >= len(future.result()[1]):
            raise HTTPException(404)
        figure = future.result()[1][n]
        return Response(
            base64.b64decode(figure.data),
            media_type=figure.mime,
            headers={"Cache-Control": "private, max-age=3600"},  # a state's pictures never change
        )

    def study_count(request: Request) -> JSONResponse:
        st = study_of(request)
        if st is None:
            raise HTTPException(404)
        return JSONResponse(study_data(st).counts())  # from the kept values where they are current

    def _int(q: Any, name: str, default: int) -> int:
        try:
            return int(q.get(name, default))
        except ValueError:
            return default

    def study_variants(request: Request) -> JSONResponse:
        """A page of the study's table, sorted by any column over the whole study (from the kept
        sorted order once the study is read whole, else by the database)."""
        st = study_of(request)
        if st is None:
            raise HTTPException(404)
        q = request.query_params
        data = study_data(st)
        number = max(1, _int(q, "page", 1))
        rows = data.page(
            sort=q.get("sort", "id"),
            descending=q.get("order") == "desc",
            offset=(number - 1) * PAGE_SIZE,
            limit=PAGE_SIZE,
        )
        return JSONResponse(
            {
                "page": number,
                "rows": [
                    {
                        "id": r["id"],
                        "status": r["status"],
                        "error": r["error"],
                        "cells": [vars(table_cell(x)) for x in r["values"]],
                    }
                    for r in rows
                ],
                **data.counts(),  # the same state as the page's rows
            }
        )

    def study_points(request: Request) -> Response:
        """Every column of an evenly spread sample of the succeeded variants (the scatter, slice,
        contour and parallel-coordinates views)."""
        st = study_of(request)
        if st is None:
            raise HTTPException(404)
        data = study_data(st)
        return Response(data.numbers_json(range(len(data.columns))), media_type="application/json")

    def asked_column(request: Request, outputs_only: bool) -> tuple[Any, StudyData, dict[str, Any], int]:
        """The study and the column a view asks for (``?column=``; the objective by default); 404
        for a study or a column it does not have, or a parameter where an output is asked for."""
        st = study_of(request)
        if st is None:
            raise HTTPException(404)
        data = study_data(st)
        views = study_views(st, data.columns)
        column = _int(request.query_params, "column", views["objective"])
        if not 0 <= column < len(data.columns) or (outputs_only and data.columns[column].role != "output"):
            raise HTTPException(404)
        return st, data, views, column

    def study_history(request: Request) -> JSONResponse:
        """The history of one output (the study's objective by default) with the best so far."""
        from mechdyn.dashboard.views import history

        _st, data, views, column = asked_column(request, outputs_only=False)
        ids, si = data.array(column)
        c = data.columns[column]
        shown = si if c.levels else c.shown_array(si)
        sense = views["senses"].get(str(column), "minimize")
        return JSONResponse({"label": c.label, **history(ids, shown, sense)})

    def study_pareto(request: Request) -> JSONResponse:
        """The Pareto front of two columns, from every succeeded variant."""
        from mechdyn.dashboard.views import pareto_mask

        st = study_of(request)
        if st is None:
            raise HTTPException(404)
        data = study_data(st)
        q = request.query_params
        x, y = _int(q, "x", 0), _int(q, "y", len(data.columns) - 1)
        if not (0 <= x < len(data.columns) and 0 <= y < len(data.columns)):
            raise HTTPException(404)
        senses = study_views(st, data.columns)["senses"]
        sx, sy = q.get("sx") or senses.get(str(x), "minimize"), q.get("sy") or senses.get(str(y), "minimize")
        ids, a = data.array(x)
        _, b = data.array(y)
        mask = pareto_mask(a, b, (sx, sy))
        order = np.flatnonzero(mask)[np.argsort(a[mask])]
        cx, cy = data.columns[x], data.columns[y]
        return JSONResponse(
            {
                "ids": ids[order].tolist(),
                "x": cx.shown_array(a[order]).tolist(),
                "y": cy.shown_array(b[order]).tolist(),
                "senses": [sx, sy],
                "of": int(np.isfinite(a).sum()),
            }
        )

    def study_importances(request: Request) -> JSONResponse:
        """How much each parameter matters to one output: the study's own Sobol indices (SALib) for
        a Sobol study, else Optuna's PED-ANOVA on a sample."""
        from mechdyn.dashboard.views import importances

        st, data, _views, column = asked_column(request, outputs_only=True)
        key = data.columns[column].key
        if st.kind == "sobol":
            ready = findings(st, studies.counts(st.id)["variants"], None)
            indices = (ready and ready[3]) or {}
            if key in indices:
                return JSONResponse(
                    {
                        "method": "Sobol total-order indices (SALib, Saltelli's estimator), every variant",
                        "values": {p: float(v["ST"]) for p, v in indices[key].items()},
                        "output": data.columns[column].label,
                    }
                )
        parameters = {c.key: data.array(i)[1] for i, c in enumerate(data.columns) if c.role == "parameter"}
        found = importances(parameters, data.array(column)[1])
        return JSONResponse({**found, "output": data.columns[column].label})

    what_ifs: dict[int, Any] = {}
    best_of: dict[tuple[int, int], dict[str, Any]] = {}

    def what_if_of(st: Any) -> Any:
        """The study's what-if evaluator (None for a study that cannot be rebuilt: built in Python)."""
        from mechdyn.dashboard.whatif import WhatIf
        from mechdyn.errors import MechdynError

        if st.id not in what_ifs:
            try:
                what_ifs[st.id] = WhatIf(store, st.name, shown_columns(st))
            except (MechdynError, StoreError):
                what_ifs[st.id] = None
        return what_ifs[st.id]

    def best_design(st: Any, w: Any) -> dict[str, Any] | None:
        """The study's best variant by its objective: its stored outputs and, for a mechanism, its
        linkage (evaluated once per number of variants)."""
        data = study_data(st)
        views = study_views(st, data.columns)
        column = views["objective"]
        ids, values = data.array(column)
        if not np.isfinite(values).any():
            return None
        sense = views["senses"].get(str(column), "minimize")
        best = int(ids[int(np.nanargmax(values) if sense == "maximize" else np.nanargmin(values))])
        key = (st.id, best)
        if key not in best_of:
            v = studies.variant(best)
            answer = w.evaluate([float(v.parameters[p.name]) for p in w.parameters])
            best_of[key] = {
                "id": best,
                "sense": sense,
                "objective": data.columns[column].label,
                "outputs": [{"key": c.key, "value": c.shown(v.outputs.get(c.key))} for c in w.outputs],
                "linkage": answer["linkage"],
            }
        return best_of[key]

    keeper: list[ResultStore] = []  # the writable connection, opened on the first design kept
    keep_lock = threading.Lock()

    def study_keep(request: Request) -> JSONResponse:
        """Keep the what-if design as a new variant of its study: only if the dashboard was started
        to keep designs, and only from the dashboard's own page (a header another site's page cannot
        send without this server's leave)."""
        from mechdyn.studies.storage import StudyStore, variant_key

        if not keep_designs:
            return JSONResponse(
                {"error": "the dashboard is read-only; start it with --keep-designs to keep designs"},
                status_code=403,
            )
        if request.headers.get("x-mechdyn") != "keep":
            return JSONResponse({"error": "designs are kept from the study's page only"}, status_code=403)
        asked = asked_design(request)
        if isinstance(asked, JSONResponse):
            return asked
        st, w, row = asked
        ev = w.evaluator.one(row)
        key = variant_key(row)
        with keep_lock:
            if not keeper:
                keeper.append(ResultStore(store.url))
            kept = StudyStore(keeper[0])
            position = kept.next_position(st.id)
            kept.add(
                st.id,
                [
                    {
                        "key": key,
                        "position": position,
                        "parameters": {p.name: x for p, x in zip(w.parameters, row, strict=True)},
                        "given": {},
                        "outputs": ev.outputs,
                        "status": ev.status,
                        "error": ev.error,
                        "model_sha256": st.model_sha256,
                        "warnings": ev.warnings,
                    }
                ],
            )
            variant = kept.ids(st.id, [key])[key]
        return JSONResponse({"variant": variant, "status": ev.status})

    def study_whatif(request: Request) -> JSONResponse:
        """One design of the study evaluated now from the form's values; nothing is written."""
        asked = asked_design(request)
        if isinstance(asked, JSONResponse):
            return asked
        st, w, row = asked
        return JSONResponse({**w.evaluate(row), "best": best_design(st, w)})

    def asked_design(request: Request) -> tuple[Any, Any, list[float]] | JSONResponse:
        """The study, its what-if evaluator and the design's SI values the request asks for; HTTP 404
        for a study the database does not have, 400 (with the reason) for values it does not take."""
        from mechdyn.dashboard.whatif import WhatIfError

        st = study_of(request)
        if st is None:
            raise HTTPException(404)
        w = what_if_of(st)
        if w is None:
            return JSONResponse({"error": "this study cannot be evaluated again here"}, status_code=400)
        try:
            return st, w, w.row(dict(request.query_params))
        except WhatIfError as exc:
            return JSONResponse({"error": str(exc)}, status_code=400)

    views_of: dict[int, dict[str, Any]] = {}

    def study_views(st: Any, shown: list[Any]) -> dict[str, Any]:
        """What the study's views start from: the objective's column (the first objective of an
        optimization, else the last output) and each column's better direction."""
        if st.id not in views_of:
            keys = [c.key for c in shown]
            senses: dict[str, str] = {}
            objective = len(shown) - 1
            for i, o in enumerate(reversed(st.definition.get("objectives") or [])):
                name = o.get("output") if isinstance(o, dict) else None
                goal = str(o.get("goal", o.get("sense", "minimize"))) if isinstance(o, dict) else "minimize"
                if name in keys:
                    senses[str(keys.index(name))] = "maximize" if goal.startswith("max") else "minimize"
                    objective = keys.index(name) if i == len(st.definition["objectives"]) - 1 else objective
            views_of[st.id] = {"objective": objective, "senses": senses}
        return views_of[st.id]

    def static_plotly(request: Request) -> FileResponse:
        return FileResponse(plotly_js, media_type="application/javascript")

    async def not_found(request: Request, exc: Exception) -> HTMLResponse:
        return missing(f"There is nothing at {request.url.path}.")

    hosts = [*LOOPBACK_HOSTS, *allowed_hosts]

    @asynccontextmanager
    async def lifespan(app: Any) -> Any:
        yield
        findings_pool.shutdown(wait=False, cancel_futures=True)  # a server that stops works out nothing more

    app = Starlette(
        lifespan=lifespan,
        middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=hosts)],
        routes=[
            Route("/", index),
            Route("/runs/{run_id:int}", run_page),
            Route("/compare", compare),
            Route("/studies/{study_id:int}", study_page),
            Route("/api/studies/{study_id:int}/count", study_count),
            Route("/studies/{study_id:int}/findings", study_findings),
            Route("/studies/{study_id:int}/findings/{n:int}.png", study_figure),
            Route("/api/studies/{study_id:int}/variants", study_variants),
            Route("/api/studies/{study_id:int}/points", study_points),
            Route("/api/studies/{study_id:int}/history", study_history),
            Route("/api/studies/{study_id:int}/pareto", study_pareto),
            Route("/api/studies/{study_id:int}/importances", study_importances),
            Route("/api/studies/{study_id:int}/whatif", study_whatif),
            Route("/api/studies/{study_id:int}/keep", study_keep, methods=["POST"]),
            Route("/static/plotly.min.js", static_plotly),
        ],
        exception_handlers={404: not_found},
    )
    app.state.store = store
    app.state.keeper = keeper
    app.state.allowed_hosts = hosts
    return app


def serve(
    url: str | None = None,
    host: str = "127.0.0.1",
    port: int = 8050,
    allowed_hosts: Sequence[str] = (),
    keep_designs: bool = False,
) -> None:
    """Serve the dashboard until interrupted (``mechdyn dashboard``).

    Parameters
    ----------
    url : str, optional
        The results database (default: ``MECHDYN_DB``, else ``mechdyn.db``).
    host : str
        The address to listen on; anything but a loopback address is announced with a warning.
    port : int
        The port.
    allowed_hosts : sequence of str
        Host names answered besides the loopback names (what a browser elsewhere calls this machine).
    keep_designs : bool
        Let the what-if form keep a design as a new variant of its study (:func:`create_app`).
    """
    import sys

    import uvicorn

    app = create_app(url, allowed_hosts, keep_designs=keep_designs)
    where = app.state.store.where
    if not _loopback(host):
        names = ", ".join(allowed_hosts) or "none but this machine's loopback names"
        print(
            f"WARNING: listening on {host}, beyond this machine: anyone who reaches {host}:{port} can "
            f"read every model and result in the database. Answered host names: {names} "
            "(--allowed-host NAME adds one).",
            file=sys.stderr,
        )
    mode = "read-only; designs kept from the what-if form" if keep_designs else "read-only"
    print(f"mechdyn dashboard on http://{host}:{port}/ over {where} ({mode}); Ctrl-C stops it")
    uvicorn.run(app, host=host, port=port, log_level="warning")
