"""What the dashboard's pages and API share: the database (opened read-only), the templates, the
connection that keeps designs, and what is kept between requests, every cache bounded.

Kept, per study: its columns as shown and what its views start from (from its definition, which does
not change), its what-if evaluator and its best design (evaluated again when another variant becomes
the best), and its findings (its kind's tables and pictures, worked out in one background thread for
the number of variants stored when asked, and worked out again once that number changes); per
variant: its curves recomputed from its stored inputs; per stored test (a ``modes-from-test`` run): its
model against the measurement, the FRF overlay drawn again from the files it names. Each is a
least-recently-used cache of a few entries (:class:`CacheLimits`), the pictures and curves bounded in
bytes as well.
"""

from __future__ import annotations

import threading
import time
from concurrent.futures import CancelledError, Future, ThreadPoolExecutor
from concurrent.futures import TimeoutError as FuturesTimeout
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from jinja2 import Environment, PackageLoader, select_autoescape

from mechdyn.dashboard.caches import BoundedCache
from mechdyn.dashboard.study_data import StudyData
from mechdyn.store.store import ResultStore, StoreError
from mechdyn.studies.storage import StoredStudy, StudyStore

__all__ = ["CacheLimits", "DashboardState", "Findings"]

MAX_ID = 2**31 - 1  # the largest id an integer column holds on every backend
MiB = 2**20


class Findings(NamedTuple):
    """A study's findings as its page shows them, worked out for one number of stored variants."""

    tables: list[Any]  # its kind's tables (HtmlTable)
    figures: list[Any]  # its pictures (Figure: caption, base64 data, mime type)
    note: str  # why there are none yet, or ""
    indices: dict[str, Any]  # a Sobol study's indices, a tolerance study's rankings, by output; else {}
    variants: int  # the number of stored variants they were worked out for
    views: Any = None  # what its kind leads with (mechdyn.reports.html.StudyViews), if any


@dataclass(frozen=True)
class CacheLimits:
    """How much the dashboard keeps in memory between requests: entries (counts) and bytes.

    Parameters
    ----------
    studies : int
        Studies whose columns as shown and whose views' starting points are kept (a few kB each).
    what_ifs : int
        Studies whose what-if evaluator (the model built) and best design are kept.
    findings : int
        Studies whose findings (tables and pictures) are kept, each for its number of variants now.
    findings_bytes : int
        Bytes of the findings' pictures (base64 PNG) kept at most, over every study.
    curves : int
        Variants whose curves, recomputed from their stored inputs, are kept.
    curves_bytes : int
        Bytes of recomputed curves (their arrays) kept at most, over every variant.
    tests : int
        Stored tests (``modes-from-test`` runs) whose FRF overlay, recomputed from the files they
        name, is kept.
    tests_bytes : int
        Bytes of those overlays (base64 PNG) kept at most, over every run.
    """

    studies: int = 1024
    what_ifs: int = 16
    findings: int = 16
    findings_bytes: int = 64 * MiB
    curves: int = 64
    curves_bytes: int = 64 * MiB
    tests: int = 16
    tests_bytes: int = 16 * MiB


def _findings_bytes(entry: tuple[int, Future[Findings]]) -> int:
    """The bytes of a kept findings' pictures (0 until they are worked out)."""
    future = entry[1]
    if not future.done() or future.cancelled() or future.exception() is not None:
        return 0
    return sum(len(f.data) for f in future.result().figures)


def _curves_bytes(entry: tuple[dict[str, Any], str | None]) -> int:
    """The bytes of a variant's recomputed curves (their arrays)."""
    return sum(np.asarray(curve[0]).nbytes for curve in entry[0].values())


def _overlay_bytes(entry: tuple[Any, str | None]) -> int:
    """The bytes of a kept test's overlay (its base64 PNG; 0 for none)."""
    return len(entry[0].data) if entry[0] is not None else 0


class DashboardState:
    """The dashboard over one results database: what its handlers share.

    Parameters
    ----------
    url : str, optional
        A SQLite file or a SQLAlchemy URL (default: ``MECHDYN_DB``, else ``mechdyn.db``), opened
        read-only and checked (a mechdyn database of this schema).
    keep_designs : bool
        Let a study's what-if form keep a design as a new variant of that study
        (:meth:`keep_design`, through a second connection opened for it).
    limits : CacheLimits, optional
        The bounds of what is kept between requests (default: :class:`CacheLimits`).

    Attributes
    ----------
    store : ResultStore
        The read-only connection every page reads through.
    studies : StudyStore
        Its studies.
    templates : jinja2.Environment
        The pages' templates, every value escaped.
    keeper : list of ResultStore
        The writable connection, once a design has been kept (empty before).
    """

    def __init__(
        self, url: str | None = None, *, keep_designs: bool = False, limits: CacheLimits | None = None
    ):
        self.store = ResultStore(url, read_only=True)
        self.studies = StudyStore(self.store)
        self.templates = Environment(
            loader=PackageLoader("mechdyn.dashboard", "templates"), autoescape=select_autoescape(default=True)
        )
        self.plotly_js = Path(__file__).parent / "static" / "plotly-mechdyn.min.js"
        self.keep_designs = keep_designs
        self.limits = limits or CacheLimits()
        self.keeper: list[ResultStore] = []
        self._keep_lock = threading.Lock()
        lim = self.limits
        self.columns: BoundedCache[int, list[Any]] = BoundedCache(lim.studies)
        self.views: BoundedCache[int, dict[str, Any]] = BoundedCache(lim.studies)
        self.what_ifs: BoundedCache[int, tuple[Any]] = BoundedCache(lim.what_ifs)  # (None,): cannot
        self.best: BoundedCache[int, tuple[int, dict[str, Any]]] = BoundedCache(lim.what_ifs)
        self.findings_kept: BoundedCache[int, tuple[int, Future[Findings]]] = BoundedCache(
            lim.findings, lim.findings_bytes, _findings_bytes
        )
        self.curves: BoundedCache[int, tuple[dict[str, Any], str | None]] = BoundedCache(
            lim.curves, lim.curves_bytes, _curves_bytes
        )
        self.tests: BoundedCache[tuple[int, tuple[Any, ...]], tuple[Any, str | None]] = BoundedCache(
            lim.tests, lim.tests_bytes, _overlay_bytes
        )
        self._findings_pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="mechdyn-findings")
        self._findings_lock = threading.Lock()
        self._curves_lock = threading.Lock()  # one recomputation at a time, each variant's once
        self._tests_lock = threading.Lock()  # one overlay drawn at a time, each test's once

    def close(self, wait: bool = False) -> None:
        """Stop working out findings (a server that stops works out nothing more).

        Parameters
        ----------
        wait : bool
            Also wait for the findings being worked out now to finish (a process that goes on after
            the server, such as a test run, then has no thread of the dashboard left running).
        """
        self._findings_pool.shutdown(wait=wait, cancel_futures=True)

    # -- a study and what is kept of it ----------------------------------------------------------
    def study(self, study_id: int) -> StoredStudy | None:
        """The study with this id, or None (also for an id no database column can hold).

        Parameters
        ----------
        study_id : int
            As the study's page's address names it.
        """
        return self.studies.study_by_id(study_id) if study_id <= MAX_ID else None

    def shown_columns(self, st: StoredStudy) -> list[Any]:
        """A study's parameters and outputs as its study file shows them (SI for a study built in
        Python, read from its first variants), built once per study (its definition does not change).

        Parameters
        ----------
        st : StoredStudy
            The study.
        """
        from mechdyn.reports.columns import stored_columns

        columns = self.columns.get(st.id)
        if columns is None:
            columns = stored_columns(self.store, st.name, self.studies.variants(st.name, limit=10))
            self.columns.put(st.id, columns)
        return columns

    def study_data(self, st: StoredStudy) -> StudyData:
        """The study's variants as this request reads them (:class:`StudyData`).

        Parameters
        ----------
        st : StoredStudy
            The study.
        """
        return StudyData(self.store.engine, st.id, self.shown_columns(st))

    def study_views(self, st: StoredStudy, shown: list[Any]) -> dict[str, Any]:
        """What the study's views start from: the objective's column (``objective``: the first
        objective of an optimization, else the last output) and each column's better direction
        (``senses``: column index as text → ``"minimize"`` or ``"maximize"``).

        Parameters
        ----------
        st : StoredStudy
            The study.
        shown : list of Column
            Its columns as shown (:meth:`shown_columns`).
        """
        views = self.views.get(st.id)
        if views is None:
            keys = [c.key for c in shown]
            senses: dict[str, str] = {}
            objective = len(shown) - 1
            for i, o in enumerate(reversed(st.definition.get("objectives") or [])):
                name = o.get("output") if isinstance(o, dict) else None
                goal = str(o.get("goal", o.get("sense", "minimize"))) if isinstance(o, dict) else "minimize"
                if name in keys:
                    senses[str(keys.index(name))] = "maximize" if goal.startswith("max") else "minimize"
                    objective = keys.index(name) if i == len(st.definition["objectives"]) - 1 else objective
            views = {"objective": objective, "senses": senses}
            self.views.put(st.id, views)
        return views

    # -- findings ----------------------------------------------------------------------------------
    def findings(self, st: StoredStudy, n_variants: int, wait: float | None) -> Findings | None:
        """The study's findings for ``n_variants`` stored variants, or None if not ready within
        ``wait`` seconds (None: until ready).

        They are worked out in one background thread, once per number of stored variants: a number
        other than the one kept starts them again (and drops the kept ones, or cancels them if not
        started). Where a later number has replaced the one asked for before it started, the findings
        of that later number are given.

        Parameters
        ----------
        st : StoredStudy
            The study.
        n_variants : int
            How many variants it holds now (count).
        wait : float or None
            Seconds to wait at most (s).
        """
        deadline = None if wait is None else time.monotonic() + wait
        future = self._findings_future(st, n_variants, latest=False)
        while True:
            left = None if deadline is None else max(0.0, deadline - time.monotonic())
            try:
                return future.result(timeout=left)
            except FuturesTimeout:
                return None
            except CancelledError:  # replaced before it started: wait for what replaced it
                now = self._findings_future(st, n_variants, latest=True)
                if now is future:  # cancelled as the server stops
                    return None
                future = now

    def kept_findings(self, st: StoredStudy, n_variants: int) -> Findings | None:
        """The study's findings for ``n_variants`` variants if they are worked out and kept, else
        None; starts nothing.

        Parameters
        ----------
        st : StoredStudy
            The study.
        n_variants : int
            The number of variants they were worked out for (count).
        """
        entry = self.findings_kept.get(st.id)
        if entry is None or entry[0] != n_variants:
            return None
        future = entry[1]
        return future.result() if future.done() and not future.cancelled() else None

    def _findings_future(self, st: StoredStudy, n_variants: int, *, latest: bool) -> Future[Findings]:
        """The findings being worked out for the study: those kept for ``n_variants`` (for any
        number if ``latest``), else started now for ``n_variants``."""
        with self._findings_lock:
            entry = self.findings_kept.get(st.id)
            if entry is not None and (latest or entry[0] == n_variants):
                return entry[1]
            if entry is not None:
                entry[1].cancel()  # a state of the study nobody asks for any more, unless started
            future = self._findings_pool.submit(self._work_out_findings, st, n_variants)
            self.findings_kept.put(st.id, (n_variants, future))
        # weighed again once its pictures are drawn (outside the lock: it may run at once)
        future.add_done_callback(lambda _done: self.findings_kept.reweigh(st.id))
        return future

    def _work_out_findings(self, st: StoredStudy, n_variants: int) -> Findings:
        from mechdyn.errors import MechdynError
        from mechdyn.reports.html import figures_of, study_tables, study_views
        from mechdyn.studies.run import stored_result
        from mechdyn.studies.spec import StudyError

        try:
            # every value read once: the views over every variant then cost no query
            self.study_data(st).warm()
            result = stored_result(self.store, st.name)
            indices = result.findings.get("indices", {}) if st.kind == "sobol" else {}
            if st.kind == "tolerance":  # each output's ranking of the tolerances, for its importances
                outputs = result.findings.get("outputs", {})
                indices = {k: d["ranking"] for k, d in outputs.items() if "ranking" in d}
            views = study_views(result)  # its figures first, then the plots they do not show
            rest = {k: draw for k, draw in result.plots().items() if k not in views.shown}
            figures = [*views.figures, *figures_of(rest)]
            return Findings(study_tables(result), figures, "", indices, n_variants, views)
        except (StudyError, StoreError, MechdynError) as exc:
            note = f"The findings appear when every variant is stored: {exc}"
            return Findings([], [], note, {}, n_variants)

    # -- a variant's curves ------------------------------------------------------------------------
    def recomputed(self, variant_id: int) -> tuple[dict[str, Any], str | None]:
        """A variant's curves worked out again from its stored inputs (the study's definition, the
        model files as stored, its parameters), kept in memory; nothing is written.

        Parameters
        ----------
        variant_id : int
            The variant's id.

        Returns
        -------
        (dict, str or None)
            Its curves (name → (array, unit); empty where that cannot be done), and why there are
            none (None where there are).
        """
        from mechdyn.errors import MechdynError
        from mechdyn.studies.run import recompute

        with self._curves_lock:
            kept = self.curves.get(variant_id)
            if kept is None:
                try:
                    found = recompute(self.store, variant_id, batch=False, curves=True)
                    why = None if found.curves else (found.error or "its analysis keeps no curve")
                    kept = (dict(found.curves), why)
                except (MechdynError, StoreError) as exc:
                    kept = ({}, str(exc))
                self.curves.put(variant_id, kept)
            return kept

    # -- a stored test's model against its measurement -------------------------------------------
    def measured_view(self, run: Any) -> Any:
        """A stored ``modes-from-test`` run's model against its measurement as its page shows it,
        found without drawing (:func:`mechdyn.dashboard.measured.measured_view`); None for a run of
        another analysis.

        Parameters
        ----------
        run : StoredRun
            The stored run, with its arrays.
        """
        from mechdyn.dashboard import measured

        return measured.measured_view(run) if run.analysis == measured.ANALYSIS else None

    def overlay(self, run: Any) -> tuple[Any, str | None]:
        """A stored test's FRF overlay (:func:`mechdyn.dashboard.measured.overlay_figure`), drawn once
        and kept until the files it is drawn from change (:func:`~mechdyn.dashboard.measured.files_key`).

        Parameters
        ----------
        run : StoredRun
            A stored ``modes-from-test`` run.

        Returns
        -------
        (Figure or None, str or None)
            The picture (caption, base64 PNG), and why there is none (None where there is).
        """
        from mechdyn.dashboard import measured

        key = (run.id, measured.files_key(run))
        with self._tests_lock:
            kept = self.tests.get(key)
            if kept is None:
                try:
                    kept = (measured.overlay_figure(run), None)
                except measured.OverlayError as exc:
                    kept = (None, str(exc))
                self.tests.put(key, kept)
            return kept

    def kept_overlay(self, run: Any, files: tuple[Any, ...]) -> Any:
        """A stored test's FRF overlay if it is drawn and kept for this state of its files, else
        None; draws nothing.

        Parameters
        ----------
        run : StoredRun
            A stored ``modes-from-test`` run.
        files : tuple
            The state of the files it is drawn from (:func:`mechdyn.dashboard.measured.files_key`).
        """
        kept = self.tests.get((run.id, files))
        return kept[0] if kept is not None else None

    # -- what if -----------------------------------------------------------------------------------
    def what_if(self, st: StoredStudy) -> Any:
        """The study's what-if evaluator (:class:`~mechdyn.dashboard.whatif.WhatIf`), None for a
        study that cannot be rebuilt (built in Python).

        Parameters
        ----------
        st : StoredStudy
            The study.
        """
        from mechdyn.dashboard.whatif import WhatIf
        from mechdyn.errors import MechdynError

        kept = self.what_ifs.get(st.id)
        if kept is None:
            try:
                kept = (WhatIf(self.store, st.name, self.shown_columns(st)),)
            except (MechdynError, StoreError):
                kept = (None,)
            self.what_ifs.put(st.id, kept)
        return kept[0]

    def best_design(self, st: StoredStudy, w: Any) -> dict[str, Any] | None:
        """The study's best variant by its objective: its stored outputs and, for a mechanism, its
        linkage (evaluated again only when another variant becomes the best); None where no variant
        has a value of the objective.

        Parameters
        ----------
        st : StoredStudy
            The study.
        w : WhatIf
            Its what-if evaluator (:meth:`what_if`).
        """
        data = self.study_data(st)
        views = self.study_views(st, data.columns)
        column = views["objective"]
        ids, values = data.array(column)
        if not np.isfinite(values).any():
            return None
        sense = views["senses"].get(str(column), "minimize")
        best = int(ids[int(np.nanargmax(values) if sense == "maximize" else np.nanargmin(values))])
        kept = self.best.get(st.id)
        if kept is not None and kept[0] == best:
            return kept[1]
        v = self.studies.variant(best)
        answer = w.evaluate([float(v.parameters[p.name]) for p in w.parameters])
        design = {
            "id": best,
            "sense": sense,
            "objective": data.columns[column].label,
            "outputs": [{"key": c.key, "value": c.shown(v.outputs.get(c.key))} for c in w.outputs],
            "linkage": answer["linkage"],
        }
        self.best.put(st.id, (best, design))
        return design

    def keep_design(self, st: StoredStudy, w: Any, row: list[float]) -> tuple[int, str]:
        """Store a what-if design as a new variant of its study, through a writable connection
        opened for the first one (the only write the dashboard makes).

        Parameters
        ----------
        st : StoredStudy
            The study.
        w : WhatIf
            Its what-if evaluator (:meth:`what_if`).
        row : list of float
            The design's parameter values, SI, in the study's order.

        Returns
        -------
        (int, str)
            The new variant's id and its status (``"ok"`` or ``"failed"``).
        """
        from mechdyn.studies.storage import variant_key

        ev = w.evaluator.one(row)
        key = variant_key(row)
        with self._keep_lock:
            if not self.keeper:
                self.keeper.append(ResultStore(self.store.url))
            kept = StudyStore(self.keeper[0])
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
            return kept.ids(st.id, [key])[key], ev.status
