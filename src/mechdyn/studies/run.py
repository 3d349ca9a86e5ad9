"""Running a study: the design of each kind, evaluation in blocks (in-process or on Dask), every
variant stored as it is finished, and what each kind finds.

What each kind designs and finds is its own (:mod:`mechdyn.studies.kinds`).

Resuming: a variant's key is a hash of its parameter values, unique within its study; a run looks
up every key before it evaluates, so running a study again reuses what is stored (the designs and
the optimizers are seeded, so the second run asks for the same variants).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from contextlib import nullcontext
from datetime import UTC, datetime
from typing import Any

import numpy as np

from mechdyn import __version__
from mechdyn.store.store import StoreError
from mechdyn.studies.errors import StudyError
from mechdyn.studies.evaluate import Evaluation, Evaluator
from mechdyn.studies.storage import StoredVariant, StudyStore, variant_key
from mechdyn.studies.study import Study

__all__ = ["Runner", "recompute", "run_study", "stored_result", "stored_study"]


class Runner:
    """Evaluates a study's variants through its results database (reusing what is stored).

    Parameters
    ----------
    study : Study
    store : StudyStore
    dask : str, optional
        ``"local"`` for a LocalCluster, or a scheduler address ``tcp://HOST:PORT``.
    progress : bool
        A progress bar with ETA (rich).
    """

    def __init__(self, study: Study, store: StudyStore, dask: str | None = None, progress: bool = True):
        from mechdyn.studies.study import check

        check(study)  # a study built in Python gets the study file's checks
        self.study = study
        self.store = store
        self.evaluator: Any = Evaluator(
            study.source, study.analysis, study.parameters, [w.key for w in study.watched], study.options
        )
        if study.robust:  # robust design: each design's statistics over its samples of the scatter
            from mechdyn.studies.kinds.robust import RobustEvaluator

            self.evaluator = RobustEvaluator(study)
        self._check_outputs()
        tree = study.tree
        self.stored, _ = store.open(
            study.name,
            kind=study.kind,
            analysis=study.analysis,
            definition=study.definition or {"parameters": [p.name for p in study.parameters]},
            model_path=study.source.path,
            model_sha256=tree.sha256,
            model_files=tree.texts,
            parameters=[p.name for p in study.parameters],
            outputs=[w.key for w in study.watched],
        )
        self.model_sha256 = tree.sha256
        self.cache: dict[str, StoredVariant] = store.stored(self.stored.id)
        self.stored_before = frozenset(self.cache)  # keys stored before this run: what it reuses
        self.position = len(self.cache)
        self.evaluated = 0
        self.reused_keys: set[str] = set()
        self.dask = dask
        self._client: Any = None
        self.progress = progress
        self._bar: Any = None

    def _check_outputs(self) -> None:
        """Refuse, before any work, an output that names no number in the base design's result
        (a list without its entry, ``natural_frequencies_hz.0``, a table's name it does not hold):
        every variant would store nothing for it."""
        from mechdyn.studies.errors import StudyError
        from mechdyn.studies.outputs import output_problem

        summary = self.evaluator.base_summary()
        if summary is None:
            return
        problems = [p for w in self.study.watched if (p := output_problem(summary, w.key)) is not None]
        if problems:
            raise StudyError(
                f"{self.study.path or self.study.name}: [[outputs]] (or an objective, constraint or target) "
                + "; ".join(problems)
            )

    # -- evaluation ---------------------------------------------------------------------------
    def evaluate(
        self, X: Any, objective: Callable[[dict[str, Any]], float] | None = None
    ) -> list[StoredVariant]:
        """The stored variants of the rows of ``X`` (SI), evaluating and storing those not yet stored."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        keys = [variant_key(row) for row in X]
        missing: dict[str, np.ndarray] = {}
        for k, row in zip(keys, X, strict=True):
            if k in self.cache:
                self.reused_keys.add(k)
            elif k not in missing:
                missing[k] = row
        if missing:
            todo = list(missing.items())
            chunk = self.study.chunk
            blocks = [todo[i : i + chunk] for i in range(0, len(todo), chunk)]
            for block, results in self._blocks(blocks):
                self._store(block, results, objective)
        return [self.cache[k] for k in keys]

    def _blocks(self, blocks: list[list[tuple[str, np.ndarray]]]) -> Any:
        total = sum(len(b) for b in blocks)
        task = self._bar.add_task(self.study.name, total=total) if self._bar is not None else None
        if self.dask is None:
            for b in blocks:
                out = self.evaluator(np.array([row for _, row in b]))
                if task is not None:
                    self._bar.advance(task, len(b))
                yield b, out
        else:
            from distributed import as_completed

            client = self.client()
            ev = client.scatter(self.evaluator, broadcast=True)
            futures = {
                client.submit(_evaluate_block, ev, np.array([row for _, row in b]), pure=False): b
                for b in blocks
            }
            for fut in as_completed(futures):
                b = futures[fut]
                out = fut.result()
                if task is not None:
                    self._bar.advance(task, len(b))
                yield b, out
        if task is not None:
            self._bar.remove_task(task)

    def _store(
        self,
        block: list[tuple[str, np.ndarray]],
        results: Sequence[Evaluation],
        objective: Callable[[dict[str, Any]], float] | None,
    ) -> None:
        rows: list[dict[str, Any]] = []
        for (key, x), ev in zip(block, results, strict=True):
            rows.append(
                {
                    "key": key,
                    "position": self.position,
                    "parameters": {p.name: float(v) for p, v in zip(self.study.parameters, x, strict=True)},
                    "given": {
                        p.name: p.shown(float(v)) for p, v in zip(self.study.parameters, x, strict=True)
                    },
                    "outputs": ev.outputs,
                    "status": ev.status,
                    "error": ev.error,
                    "objective": objective(ev.outputs)
                    if objective is not None and ev.status == "ok"
                    else None,
                    "model_sha256": self.model_sha256,
                    "warnings": list(ev.warnings),
                }
            )
            self.position += 1
        try:
            self.store.add(self.stored.id, rows)
        except StoreError as exc:  # the block is computed: keep it in a file, say how to import it
            from mechdyn.store.unsaved import keep_unsaved

            kept = keep_unsaved(self.store.url, "variants", {"study": self.study.name, "rows": rows})
            raise StoreError(
                f"{exc}; the {len(rows)} variants just computed are kept in {kept} "
                f"(`mechdyn results import {kept}` stores them; the variants stored before are safe, "
                "and running the study again goes on from there)"
            ) from None
        self.evaluated += len(rows)
        ids = self.store.ids(self.stored.id, [r["key"] for r in rows])
        now = datetime.now(UTC)
        for r in rows:  # as stored (outputs and parameters are plain floats; the ids from the database)
            self.cache[r["key"]] = StoredVariant(
                ids[r["key"]], self.study.name, r["key"], r["position"], r["parameters"], r["given"],
                {k: (v if v is None or math.isfinite(v) else None) for k, v in r["outputs"].items()},
                r["status"], r["error"], r["objective"], r["model_sha256"], __version__, now,
                warnings=tuple(r["warnings"]),
            )  # fmt: skip

    def all_variants(self) -> list[StoredVariant]:
        """Every stored variant of this study, in the order stored."""
        return sorted(self.store.stored(self.stored.id).values(), key=lambda v: v.id)

    def client(self) -> Any:
        if self._client is None:
            from distributed import Client, LocalCluster

            if self.dask == "local":
                cluster = LocalCluster(
                    n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
                )
                self._client = Client(cluster)
            else:
                self._client = Client(self.dask)
        return self._client

    def close(self) -> None:
        if self._client is not None:
            cluster = getattr(self._client, "cluster", None)
            self._client.close()
            if cluster is not None and self.dask == "local":
                cluster.close()
            self._client = None

    def keep_curves(self, variants: Sequence[StoredVariant]) -> None:
        """Recompute the given variants with their curves and keep the curves (those that have
        them already are left)."""
        have = self.store.with_curves(self.stored.id)
        for v in variants:
            if v.status != "ok" or v.id in have:
                continue
            x = [v.parameters[p.name] for p in self.study.parameters]
            ev = self.evaluator.one(x, curves=True)
            if ev.curves:
                self.store.add_curves(v.id, ev.curves)

    # -- the kinds ----------------------------------------------------------------------------
    def base_row(self) -> np.ndarray:
        return np.array([p.base for p in self.study.parameters])

    def run(self) -> Any:
        """Run the study's kind (:mod:`mechdyn.studies.kinds`): evaluate its variants, state its
        findings from them (the function a stored study's findings come from too), keep the curves
        of the base and the best, and count what was evaluated now and what was reused."""
        from mechdyn.studies.kinds import kind
        from mechdyn.studies.result import StudyResult

        k = kind(self.study.kind)
        bar: Any = nullcontext()
        if self.progress:
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeRemainingColumn

            bar = Progress(
                TextColumn("{task.description}"), BarColumn(), TaskProgressColumn(), TimeRemainingColumn(),
                transient=True, console=Console(stderr=True),  # the tables and JSON go to stdout
            )  # fmt: skip
        try:
            with bar as b:
                self._bar = b
                ran = k.run(self)
                found = k.findings(self.study, ran.variants)
                findings = {**ran.extra, **found.findings}
                findings.update(k.confirm(self, found))
        finally:
            self._bar = None
            self.close()
        variants = ran.variants
        kept = _kept(variants, found.best, self.study.curves)
        self.keep_curves(kept)
        with_curves = tuple(
            self.store.variant(v.id) for v in kept[: self.study.curves or 2] if v.status == "ok"
        )
        # the counts add up: each variant of the result (once, though a design may list one twice:
        # a factorial's base that is also a point of its grid) was stored before this run, or since
        distinct = {v.key: v for v in variants}
        reused = sum(1 for k in distinct if k in self.stored_before)
        return StudyResult(
            self.study,
            self.stored,
            tuple(variants),
            len(distinct) - reused,
            reused,
            sum(1 for v in distinct.values() if v.status != "ok"),
            findings,
            with_curves,
        )


def _evaluate_block(evaluator: Evaluator, X: np.ndarray) -> list[Evaluation]:
    """A Dask task: one block of variants."""
    return evaluator(X)


def run_study(study: Study, store: Any = None, *, dask: str | None = None, progress: bool = False) -> Any:
    """Run a study (or resume it), storing every variant.

    Parameters
    ----------
    study : Study
        :func:`mechdyn.studies.load_study` or built in Python.
    store : ResultStore or str, optional
        The results database (default: ``MECHDYN_DB`` or ``mechdyn.db``).
    dask : str, optional
        ``"local"`` or a scheduler address (``tcp://HOST:PORT``): evaluate the blocks on Dask (only
        this process writes the database).
    progress : bool
        Show a progress bar with ETA.

    Returns
    -------
    StudyResult
    """
    from mechdyn.store.store import ResultStore

    own = not isinstance(store, ResultStore)
    rs = ResultStore(store) if own else store
    try:
        return Runner(study, StudyStore(rs), dask=dask, progress=progress).run()
    finally:
        if own:
            rs.close()


def run_studies(
    studies: Sequence[Study], store: Any = None, *, dask: str | None = None, progress: bool = False
) -> list[Any]:
    """Run the studies of one study file in order (:func:`mechdyn.studies.load_studies`: one, or one
    per box of ``[study] boxes``), each box's optimization starting from the optimum of the box before
    it (a wider box contains it, so a box's optimum is never worse than the smaller box's).

    Parameters
    ----------
    studies : sequence of Study
        In order of increasing box.
    store : ResultStore or str, optional
        The results database (default: ``MECHDYN_DB`` or ``mechdyn.db``).
    dask : str, optional
        As :func:`run_study`.
    progress : bool
        Show a progress bar with ETA.

    Returns
    -------
    list of StudyResult
    """
    from mechdyn.store.store import ResultStore

    own = not isinstance(store, ResultStore)
    rs = ResultStore(store) if own else store
    results: list[Any] = []
    try:
        for study in studies:
            if results and results[-1].findings.get("best"):
                best = results[-1].findings["best"]["parameters"]
                study = study.starting_from([[best[p.name] for p in study.parameters]])
            results.append(run_study(study, rs, dask=dask, progress=progress))
    finally:
        if own:
            rs.close()
    return results


def recompute(store: Any, variant_id: int, *, batch: bool = True, curves: bool = False) -> Evaluation:
    """Evaluate a stored variant again from what is stored: the study's definition, the model files
    as they were, and the variant's parameter values.

    Parameters
    ----------
    store : ResultStore or str
        The results database.
    variant_id : int
        As ``mechdyn results list --study NAME`` shows it.
    batch : bool
        The evaluation path: the batch (as a study evaluates) or one by one (the analysis itself).
    curves : bool
        Also compute the result's arrays (one by one), e.g. to keep them for a selected variant.

    Returns
    -------
    Evaluation
        Its outputs equal the stored ones (exactly, on the path the study took).
    """
    from mechdyn.store.store import ResultStore

    rs = store if isinstance(store, ResultStore) else ResultStore(store)
    v = StudyStore(rs).variant(variant_id)
    study = stored_study(rs, v.study)
    row = [[v.parameters[p.name] for p in study.parameters]]
    if study.robust:  # a design's statistics over its samples (curves: its nominal's)
        from mechdyn.studies.kinds.robust import RobustEvaluator

        robust = RobustEvaluator(study, batch=batch)
        return robust.one(row[0], curves=True) if curves else robust(row)[0]
    ev = Evaluator(
        study.source, study.analysis, study.parameters, list(v.outputs), study.options, batch=batch
    )
    return ev(row, curves=curves)[0]


def display_units(store: Any, name: str) -> dict[str, Any]:
    """The outputs of a stored study as its file asked to show them: ``{key: Watched}`` (with the
    display unit); empty for a study built in Python, whose values are then shown in SI.

    Parameters
    ----------
    store : ResultStore or str
    name : str
        The study's name.
    """
    try:
        return {w.key: w for w in stored_study(store, name).watched}
    except StudyError:
        return {}


def stored_study(store: Any, name: str) -> Study:
    """A stored study as it ran: its stored definition on the model files as they were stored (the
    files on disk may have changed since).

    Parameters
    ----------
    store : ResultStore or str
    name : str
        The study's name.
    """
    import tomllib
    from dataclasses import replace

    from mechdyn.io.modelfile import ModelSource
    from mechdyn.store.store import ResultStore
    from mechdyn.studies.study import study_from_data

    rs = store if isinstance(store, ResultStore) else ResultStore(store)
    stored = StudyStore(rs).study(name)
    if "study" not in stored.definition:
        raise StudyError(
            f"study {name!r} was built in Python, not read from a study file: the database holds its "
            "variants (`mechdyn results list --study`), but not a definition to rebuild it from"
        )
    files = {p: ModelSource(p, t, "", tomllib.loads(t)) for p, t in stored.model_files.items()}
    base = files.pop(stored.model_path)
    base = ModelSource(base.path, base.text, "", base.data, files)
    study = study_from_data(f"the stored study {name!r}", stored.definition, base)
    return replace(study, name=stored.name)  # a box of a file with boxes, a quick form: as stored


def stored_result(store: Any, name: str) -> Any:
    """A stored study's result from the database alone, without evaluating or writing anything (a
    read-only dashboard): the kind's findings (:meth:`mechdyn.studies.kinds.Kind.findings`) of its
    stored variants, as a run states them (less what only a run knows: Optuna's trial count, the
    polish, the single-design check).

    Parameters
    ----------
    store : ResultStore or str
    name : str

    Returns
    -------
    StudyResult
        ``evaluated`` is 0 and ``reused`` the number of variants (nothing ran); ``kept`` holds the
        base and the best with their curves where stored.

    Raises
    ------
    StudyError
        When a fixed design's variants are not all stored yet (the study is still running).
    """
    from mechdyn.store.store import ResultStore
    from mechdyn.studies.kinds import kind
    from mechdyn.studies.result import StudyResult

    rs = store if isinstance(store, ResultStore) else ResultStore(store, read_only=True)
    studies = StudyStore(rs)
    study = stored_study(rs, name)
    k = kind(study.kind)
    variants = k.order(study, studies.variants(name))
    found = k.findings(study, variants)
    with_curves = tuple(studies.variant(v.id) for v in _kept(variants, found.best, 0)[:4])
    distinct = {v.key: v for v in variants}
    failed = sum(1 for v in distinct.values() if v.status != "ok")
    return StudyResult(
        study, studies.study(name), tuple(variants), 0, len(distinct), failed, found.findings, with_curves
    )


def _kept(variants: Sequence[StoredVariant], best: frozenset[int], curves: int) -> list[StoredVariant]:
    """The variants whose curves a result keeps: all of a study of up to ``curves`` variants, else the
    first stored (the base design, where the kind has one) and the best."""
    if len(variants) <= curves:
        return list(variants)
    return [v for v in variants if v.position == 0 or v.id in best]
