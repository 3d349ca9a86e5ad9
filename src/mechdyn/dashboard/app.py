"""The web dashboard over a results database (``mechdyn dashboard``).

Starlette (a small, maintained ASGI toolkit) with Jinja2 templates, served by uvicorn; interactive
plots by Plotly.js: the part of it that the pages draw with (scatter, bar, WebGL scatter, 2-D histogram
contour, parallel coordinates), built by ``scripts/build-plotly-bundle`` and shipped in the package
(never a CDN: the machines that run it may have no internet); a third of the full bundle, which a
browser takes seconds to read before it draws anything.

- The database is opened read-only, and checked at start (a mechdyn database of this schema).
- A request reaches it only as integer ids and filter values bound as SQL parameters, never as a
  file path; every value from the database is escaped by the templates; a missing run or study,
  or an id no database column can hold, is a 404 page. The only files read besides the database
  are those a stored test's measurement file names (its data and tested model, for its FRF
  overlay), found from the path the run recorded.
- Requests are answered only for trusted host names (loopback by default), so a page that rebinds
  its DNS name to this machine cannot read it; pages name the database, never its location.
- The handlers are plain functions, run in Starlette's thread pool: a slow page never stalls the
  others; a study's findings and pictures are drawn once per stored state and kept, within bounds
  (:class:`~mechdyn.dashboard.state.CacheLimits`).

This module builds the application: the shared state (:mod:`mechdyn.dashboard.state`) and the
routes to the HTML pages (:mod:`mechdyn.dashboard.pages`) and to the JSON and picture API
(:mod:`mechdyn.dashboard.api`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from contextlib import asynccontextmanager
from functools import partial
from typing import Any

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.routing import Route

from mechdyn.dashboard import api, pages
from mechdyn.dashboard.pages import RUNS_PER_PAGE as RUNS_PER_PAGE  # the run list's page, by its old name
from mechdyn.dashboard.pages import _compare_row as _compare_row  # by its old name (the tests')
from mechdyn.dashboard.state import CacheLimits, DashboardState

__all__ = ["create_app", "serve"]

LOOPBACK_HOSTS = ("127.0.0.1", "localhost", "::1", "[::1]")


def _loopback(host: str) -> bool:
    import ipaddress

    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return host == "localhost"


def create_app(
    url: str | None = None,
    allowed_hosts: Sequence[str] = (),
    keep_designs: bool = False,
    *,
    limits: CacheLimits | None = None,
) -> Starlette:
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
    limits : CacheLimits, optional
        How much is kept in memory between requests (default: :class:`CacheLimits`' defaults).

    Returns
    -------
    starlette.applications.Starlette
        Its ``state`` holds ``dashboard`` (the :class:`DashboardState`), ``store`` (the read-only
        connection), ``keeper`` (the writable one, once opened) and ``allowed_hosts``.
    """
    state = DashboardState(url, keep_designs=keep_designs, limits=limits)

    def route(path: str, handler: Callable[..., Any], **options: Any) -> Route:
        # bound to the state, a plain function still: Starlette runs it in its thread pool
        return Route(path, partial(handler, state), name=handler.__name__, **options)

    @asynccontextmanager
    async def lifespan(app: Any) -> Any:
        yield
        state.close()

    hosts = [*LOOPBACK_HOSTS, *allowed_hosts]
    app = Starlette(
        lifespan=lifespan,
        middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=hosts)],
        routes=[
            route("/", pages.index),
            route("/runs/{run_id:int}", pages.run_page),
            route("/runs/{run_id:int}/overlay.png", api.run_overlay),
            route("/compare", pages.compare),
            route("/studies/{study_id:int}", pages.study_page),
            route("/api/studies/{study_id:int}/count", api.study_count),
            route("/studies/{study_id:int}/findings", pages.study_findings),
            route("/studies/{study_id:int}/findings/{n:int}.png", api.study_figure),
            route("/api/studies/{study_id:int}/variants", api.study_variants),
            route("/api/studies/{study_id:int}/points", api.study_points),
            route("/api/studies/{study_id:int}/history", api.study_history),
            route("/api/studies/{study_id:int}/pareto", api.study_pareto),
            route("/api/studies/{study_id:int}/importances", api.study_importances),
            route("/api/studies/{study_id:int}/whatif", api.study_whatif),
            route("/api/studies/{study_id:int}/keep", api.study_keep, methods=["POST"]),
            route("/static/plotly.min.js", api.static_plotly),
        ],
        exception_handlers={404: partial(pages.not_found, state)},
    )
    app.state.dashboard = state
    app.state.store = state.store
    app.state.keeper = state.keeper
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
