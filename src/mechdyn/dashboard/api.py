"""The dashboard's JSON and picture API, which a study's page reads: its count, a page of its table,
the sample of points its plots draw, its history, Pareto front and importances, the findings'
pictures, a what-if design evaluated (and, where the dashboard was started to keep designs, kept),
and the Plotly.js bundle shipped in the package; and a stored test's FRF overlay, which its run page
shows.

Each is a plain function of the shared :class:`~mechdyn.dashboard.state.DashboardState` and the
request, run in Starlette's thread pool. A request reaches the database only as integer ids and
values bound as SQL parameters; a study, a column or a picture it does not have is HTTP 404, a
what-if value it does not take HTTP 400 with the reason.
"""

from __future__ import annotations

import base64
from typing import Any

import numpy as np
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, PlainTextResponse, Response

from mechdyn.dashboard.state import DashboardState
from mechdyn.dashboard.study_data import PAGE_SIZE, StudyData
from mechdyn.reports.html import table_cell
from mechdyn.studies.storage import StoredStudy

__all__ = [
    "run_overlay",
    "static_plotly",
    "study_count",
    "study_figure",
    "study_history",
    "study_importances",
    "study_keep",
    "study_pareto",
    "study_points",
    "study_variants",
    "study_whatif",
]


def _study_of(state: DashboardState, request: Request) -> StoredStudy:
    """The study the address names; HTTP 404 where there is none."""
    st = state.study(request.path_params["study_id"])
    if st is None:
        raise HTTPException(404)
    return st


def _int(q: Any, name: str, default: int) -> int:
    try:
        return int(q.get(name, default))
    except ValueError:
        return default


def study_count(state: DashboardState, request: Request) -> JSONResponse:
    """How many variants the study holds and how many failed (its page polls it while it runs)."""
    st = _study_of(state, request)
    return JSONResponse(state.study_data(st).counts())  # from the kept values where they are current


def study_variants(state: DashboardState, request: Request) -> JSONResponse:
    """A page of the study's table, sorted by any column over the whole study (from the kept
    sorted order once the study is read whole, else by the database)."""
    st = _study_of(state, request)
    q = request.query_params
    data = state.study_data(st)
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


def study_points(state: DashboardState, request: Request) -> Response:
    """Every column of an evenly spread sample of the succeeded variants (the scatter, slice,
    contour and parallel-coordinates views)."""
    data = state.study_data(_study_of(state, request))
    return Response(data.numbers_json(range(len(data.columns))), media_type="application/json")


def _asked_column(
    state: DashboardState, request: Request, outputs_only: bool
) -> tuple[StoredStudy, StudyData, dict[str, Any], int]:
    """The study and the column a view asks for (``?column=``; the objective by default); 404
    for a study or a column it does not have, or a parameter where an output is asked for."""
    st = _study_of(state, request)
    data = state.study_data(st)
    views = state.study_views(st, data.columns)
    column = _int(request.query_params, "column", views["objective"])
    if not 0 <= column < len(data.columns) or (outputs_only and data.columns[column].role != "output"):
        raise HTTPException(404)
    return st, data, views, column


def study_history(state: DashboardState, request: Request) -> JSONResponse:
    """The history of one output (the study's objective by default) with the best so far."""
    from mechdyn.dashboard.views import history

    _st, data, views, column = _asked_column(state, request, outputs_only=False)
    ids, si = data.array(column)
    c = data.columns[column]
    shown = si if c.levels else c.shown_array(si)
    sense = views["senses"].get(str(column), "minimize")
    return JSONResponse({"label": c.label, **history(ids, shown, sense)})


def study_pareto(state: DashboardState, request: Request) -> JSONResponse:
    """The Pareto front of two columns, from every succeeded variant."""
    from mechdyn.dashboard.views import pareto_mask

    st = _study_of(state, request)
    data = state.study_data(st)
    q = request.query_params
    x, y = _int(q, "x", 0), _int(q, "y", len(data.columns) - 1)
    if not (0 <= x < len(data.columns) and 0 <= y < len(data.columns)):
        raise HTTPException(404)
    senses = state.study_views(st, data.columns)["senses"]
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


def study_importances(state: DashboardState, request: Request) -> JSONResponse:
    """How much each parameter matters to one output: the study's own Sobol indices (SALib) for
    a Sobol study, a tolerance study's own ranking of its tolerances (a Sobol index from the
    samples, or a signed rank correlation, as its findings say), else Optuna's PED-ANOVA on a
    sample."""
    from mechdyn.dashboard.views import importances

    st, data, _views, column = _asked_column(state, request, outputs_only=True)
    key = data.columns[column].key
    if st.kind in ("sobol", "tolerance"):
        ready = state.findings(st, state.studies.counts(st.id)["variants"], None)
        indices = (ready and ready.indices) or {}
        if st.kind == "sobol" and key in indices:
            return JSONResponse(
                {
                    "method": "Sobol total-order indices (SALib, Saltelli's estimator), every variant",
                    "values": {p: float(v["ST"]) for p, v in indices[key].items()},
                    "output": data.columns[column].label,
                }
            )
        if st.kind == "tolerance" and indices.get(key, {}).get("measures"):
            return JSONResponse(
                {
                    "method": f"the study's own ranking: {indices[key]['method']}",
                    "values": {p: float(v) for p, v in indices[key]["measures"].items()},
                    "output": data.columns[column].label,
                }
            )
    parameters = {c.key: data.array(i)[1] for i, c in enumerate(data.columns) if c.role == "parameter"}
    found = importances(parameters, data.array(column)[1])
    return JSONResponse({**found, "output": data.columns[column].label})


def study_figure(state: DashboardState, request: Request) -> Response:
    """One picture of a study's findings for the number of variants its link names (the findings of
    that state, kept; no query), 404 if they are not worked out, no longer kept (the study has
    gained variants since) or there is no such picture."""
    st = _study_of(state, request)
    ready = state.kept_findings(st, _int(request.query_params, "variants", -1))
    n = request.path_params["n"]
    if ready is None or n >= len(ready.figures):
        raise HTTPException(404)
    figure = ready.figures[n]
    return Response(
        base64.b64decode(figure.data),
        media_type=figure.mime,
        headers={"Cache-Control": "private, max-age=3600"},  # a state's pictures never change
    )


def _asked_design(
    state: DashboardState, request: Request
) -> tuple[StoredStudy, Any, list[float]] | JSONResponse:
    """The study, its what-if evaluator and the design's SI values the request asks for; HTTP 404
    for a study the database does not have, 400 (with the reason) for values it does not take."""
    from mechdyn.dashboard.whatif import WhatIfError

    st = _study_of(state, request)
    w = state.what_if(st)
    if w is None:
        return JSONResponse({"error": "this study cannot be evaluated again here"}, status_code=400)
    try:
        return st, w, w.row(dict(request.query_params))
    except WhatIfError as exc:
        return JSONResponse({"error": str(exc)}, status_code=400)


def study_whatif(state: DashboardState, request: Request) -> JSONResponse:
    """One design of the study evaluated now from the form's values; nothing is written."""
    asked = _asked_design(state, request)
    if isinstance(asked, JSONResponse):
        return asked
    st, w, row = asked
    return JSONResponse({**w.evaluate(row), "best": state.best_design(st, w)})


def study_keep(state: DashboardState, request: Request) -> JSONResponse:
    """Keep the what-if design as a new variant of its study: only if the dashboard was started
    to keep designs, and only from the dashboard's own page (a header another site's page cannot
    send without this server's leave)."""
    if not state.keep_designs:
        return JSONResponse(
            {"error": "the dashboard is read-only; start it with --keep-designs to keep designs"},
            status_code=403,
        )
    if request.headers.get("x-mechdyn") != "keep":
        return JSONResponse({"error": "designs are kept from the study's page only"}, status_code=403)
    asked = _asked_design(state, request)
    if isinstance(asked, JSONResponse):
        return asked
    st, w, row = asked
    variant, status = state.keep_design(st, w, row)
    return JSONResponse({"variant": variant, "status": status})


def run_overlay(state: DashboardState, request: Request) -> Response:
    """A stored test's FRF overlay (measured, the model before and after updating), drawn from the
    files the run names and kept (:meth:`DashboardState.overlay`); 404 for a run that is not a
    ``modes-from-test`` run, and 404 with the reason in words where it cannot be drawn (its data file
    is not found)."""
    from mechdyn.dashboard.measured import ANALYSIS
    from mechdyn.dashboard.state import MAX_ID
    from mechdyn.store.store import StoreError

    run_id = request.path_params["run_id"]
    try:
        run = state.store.get(run_id) if run_id <= MAX_ID else None
    except StoreError:
        run = None
    if run is None or run.analysis != ANALYSIS:
        raise HTTPException(404)
    figure, why = state.overlay(run)
    if figure is None:
        return PlainTextResponse(f"The FRF overlay is not drawn: {why}.", status_code=404)
    return Response(
        base64.b64decode(figure.data),
        media_type=figure.mime,
        # its address names the files' state it was drawn from: a picture at one address never changes
        headers={"Cache-Control": "private, max-age=3600"},
    )


def static_plotly(state: DashboardState, request: Request) -> FileResponse:
    """The part of Plotly.js the pages draw with, shipped in the package (never a CDN)."""
    return FileResponse(state.plotly_js, media_type="application/javascript")
