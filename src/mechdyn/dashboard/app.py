"""The web dashboard over a results database (``mechdyn dashboard``).

Starlette (a small, maintained ASGI toolkit) with Jinja2 templates, served by uvicorn; interactive
plots by Plotly.js, served from the installed ``plotly`` package (never a CDN: the machines that run
it may have no internet).

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

import json
import threading
from collections.abc import Sequence
from datetime import date, datetime
from pathlib import Path
from typing import Any

from mechdyn.reports.html import _cell, toml_text
from mechdyn.store.store import ResultStore, StoreError
from mechdyn.studies.storage import StudyStore

__all__ = ["create_app"]

MAX_POINTS = 20_000  # variants drawn in a study's plots
MAX_ROWS = 200  # variants listed in a study's table
RUNS_PER_PAGE = 100
MAX_ID = 2**31 - 1  # the largest id an integer column holds on every backend
LOOPBACK_HOSTS = ("127.0.0.1", "localhost", "::1", "[::1]")


def _plotly_js() -> Path:
    import plotly

    return Path(plotly.__file__).parent / "package_data" / "plotly.min.js"


def _date(text: str | None) -> date | None:
    try:
        return date.fromisoformat(text) if text else None
    except ValueError:
        return None


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
    if x is None:  # no curve kept
        return []
    figures = []
    for name in names:
        unit = curves[0][1][name][1]
        data = [
            {
                "x": np.asarray(c[x][0], dtype=np.float64).tolist(),
                "y": np.asarray(c[name][0], dtype=np.float64).tolist(),
                "name": label,
                "mode": "lines",
                "type": "scatter",
            }
            for label, c in curves
        ]
        layout = {
            "title": {"text": name},
            "xaxis": {"title": {"text": x}},
            "yaxis": {"title": {"text": f"{name} [{unit}]" if unit else name}},
            "margin": {"t": 40},
        }
        figures.append({"data": data, "layout": layout})
    return figures


def _loopback(host: str) -> bool:
    import ipaddress

    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return host == "localhost"


def create_app(url: str | None = None, allowed_hosts: Sequence[str] = ()) -> Any:
    """The dashboard application over the results database at ``url`` (opened read-only).

    Parameters
    ----------
    url : str, optional
        A SQLite file or a SQLAlchemy URL (default: ``MECHDYN_DB``, else ``mechdyn.db``).
    allowed_hosts : sequence of str
        Host names (``Host`` header) answered besides the loopback names; a request for any other
        host gets HTTP 400.

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
    from starlette.responses import FileResponse, HTMLResponse, JSONResponse
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

    drawing = threading.Lock()  # matplotlib's figures are drawn one at a time
    kept: dict[tuple[int, int], tuple[list[Any], list[Any], str]] = {}
    shown_as: dict[tuple[int, bool], list[Any]] = {}

    def shown_columns(st: Any, variants: Sequence[Any]) -> list[Any]:
        """A study's parameters and outputs as its study file shows them (SI for a study built in
        Python), rebuilt once per study (a stored study's definition does not change)."""
        from mechdyn.reports.columns import stored_columns

        key = (st.id, bool(variants))  # a Python study's units are read from its variants
        if key not in shown_as:
            shown_as[key] = stored_columns(store, st.name, variants[:10])
        return shown_as[key]

    def drawn(st: Any, n_variants: int) -> tuple[list[Any], list[Any], str]:
        """A study's findings tables and pictures, drawn once for each number of stored variants
        (a running study adds variants; a finished one is drawn once)."""
        from mechdyn.reports.html import _figures, study_tables
        from mechdyn.studies.run import stored_result
        from mechdyn.studies.spec import StudyError

        key = (st.id, n_variants)
        with drawing:
            if key not in kept:
                try:
                    result = stored_result(store, st.name)
                    kept[key] = (study_tables(result), _figures(result.plots()), "")
                except (StudyError, StoreError) as exc:
                    kept[key] = ([], [], f"The findings appear when every variant is stored: {exc}")
            return kept[key]

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

    def run_page(request: Request) -> HTMLResponse:
        run_id = request.path_params["run_id"]
        if run_id > MAX_ID:
            return missing(f"There is no run {run_id} in this database.")
        try:
            run = store.get(run_id)
        except StoreError:
            return missing(f"There is no run {run_id} in this database.")
        from mechdyn.reports.html import _cell
        from mechdyn.results import nested_tables, summary_table
        from mechdyn.units import key_label

        # as the report shows it: in words and in the units a designer reads, nested values by name
        scalars = run.scalars
        summary = [
            (str(r[0]) if t.title == "summary" else f"{t.title} · {r[0]}", _cell(r[1]), r[2])
            for t in [summary_table(scalars), *nested_tables(scalars)]
            for r in t.rows
        ]
        for k, v in scalars.items():  # lists of numbers (natural frequencies) in one row each
            if k != "warnings" and isinstance(v, list) and all(isinstance(x, (int, float)) for x in v):
                label, unit = key_label(k)
                summary.append((label, _cell(v), unit))
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
        from mechdyn.units import key_unit

        columns: list[str] = []
        values: list[dict[str, Any]] = []
        units: dict[str, str] = {}
        curves: list[tuple[str, dict[str, Any]]] = []
        try:
            for i in run_ids:
                r = store.get(i)
                columns.append(f"run {i} ({r.model_name})")
                flat = {k: v for k, v in r.scalars.items() if k != "warnings"}
                values.append(flat)
                curves.append((f"run {i}", r.arrays))
            for i in variant_ids:
                v = studies.variant(i)
                columns.append(f"variant {i} ({v.study})")
                outputs: dict[str, Any] = dict(v.outputs)
                if not run_ids:  # variants alone: each output in its study's unit (with runs: SI)
                    st = studies.study(v.study)
                    shown = {c.key: c for c in shown_columns(st, [v]) if c.role == "output"}
                    for k in [k for k in outputs if k in shown]:
                        outputs[k] = shown[k].shown(outputs[k])
                        units[k] = shown[k].unit
                values.append({**v.given, **outputs, "status": v.status})
                units.update({k: "" for k in v.given})
                if v.curves:
                    curves.append((f"variant {i}", v.curves))
        except StoreError as exc:
            return missing(str(exc))
        keys = list(dict.fromkeys(k for row in values for k in row))
        rows = []
        for k in keys:
            unit = units.get(k, key_unit(k.split(".")[-1]) or "")
            rows.append((k, "" if unit == "1" else unit, [_cell(row.get(k)) for row in values]))
        what = "runs" if run_ids else "variants"
        heading = f"{len(columns)} {what} side by side" if columns else "Compare"
        return page(
            "compare.html.j2",
            heading=heading,
            what=what,
            columns=columns,
            rows=rows,
            figures=_line_figures(curves) if len(curves) == len(columns) else [],
        )

    def study_page(request: Request) -> HTMLResponse:
        study_id = request.path_params["study_id"]
        st = studies.study_by_id(study_id) if study_id <= MAX_ID else None
        if st is None:
            return missing(f"There is no study {study_id} in this database.")
        variants = studies.variants(st.name)
        # parameters and outputs in the study file's units, the unit in each axis title and header
        shown = shown_columns(st, variants)
        axes = [c.label for c in shown]
        ok = [v for v in variants if v.status == "ok"][:MAX_POINTS]
        points = {
            "ids": [v.id for v in ok],
            "values": [[c.number(v) for c in shown] for v in ok],
            "levels": [list(c.levels) for c in shown],  # a choice's axis: its index, labelled by name
        }
        table = [
            {
                "id": v.id,
                "status": v.status,
                "cells": [_cell(c.of(v)) for c in shown],
                "error": v.error or "",
            }
            for v in variants[:MAX_ROWS]
        ]
        findings, figures, note = drawn(st, len(variants))
        return page(
            "study.html.j2",
            findings=findings,
            figures=figures,
            findings_note=note,
            study=st,
            variants=variants,
            failed=sum(1 for v in variants if v.status != "ok"),
            created=_utc(st.created_at),
            axes=axes,
            points=points,
            table=table,
            definition=toml_text(st.definition),
            python="study" not in st.definition,
        )

    def study_count(request: Request) -> JSONResponse:
        study_id = request.path_params["study_id"]
        st = studies.study_by_id(study_id) if study_id <= MAX_ID else None
        if st is None:
            raise HTTPException(404)
        return JSONResponse(studies.counts(st.id))

    def static_plotly(request: Request) -> FileResponse:
        return FileResponse(plotly_js, media_type="application/javascript")

    async def not_found(request: Request, exc: Exception) -> HTMLResponse:
        return missing(f"There is nothing at {request.url.path}.")

    hosts = [*LOOPBACK_HOSTS, *allowed_hosts]
    app = Starlette(
        middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=hosts)],
        routes=[
            Route("/", index),
            Route("/runs/{run_id:int}", run_page),
            Route("/compare", compare),
            Route("/studies/{study_id:int}", study_page),
            Route("/api/studies/{study_id:int}/count", study_count),
            Route("/static/plotly.min.js", static_plotly),
        ],
        exception_handlers={404: not_found},
    )
    app.state.store = store
    app.state.allowed_hosts = hosts
    return app


def serve(
    url: str | None = None, host: str = "127.0.0.1", port: int = 8050, allowed_hosts: Sequence[str] = ()
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
    """
    import sys

    import uvicorn

    app = create_app(url, allowed_hosts)
    where = app.state.store.where
    if not _loopback(host):
        names = ", ".join(allowed_hosts) or "none but this machine's loopback names"
        print(
            f"WARNING: listening on {host}, beyond this machine: anyone who reaches {host}:{port} can "
            f"read every model and result in the database. Answered host names: {names} "
            "(--allowed-host NAME adds one).",
            file=sys.stderr,
        )
    print(f"mechdyn dashboard on http://{host}:{port}/ over {where} (read-only); Ctrl-C stops it")
    uvicorn.run(app, host=host, port=port, log_level="warning")
