"""What the processes of the concurrency tests run (spawned: a module the children can import).

Each worker waits at a barrier so that all start the racing step at the same moment: the race is
met on every run, not by luck, and the assertions must hold however it ends.
"""

from __future__ import annotations

import multiprocessing as mp
import traceback
from collections.abc import Callable
from typing import Any


def run_together(target: Callable[..., Any], n: int, *args: Any, timeout: float = 300) -> list[Any]:
    """Start ``n`` spawned processes of ``target(barrier, *args)`` and return what each returned
    (``("error", traceback)`` for one that raised)."""
    ctx = mp.get_context("spawn")
    # a worker that died leaves the others at the barrier: they give up after the timeout, not never
    barrier, queue = ctx.Barrier(n, timeout=timeout), ctx.Queue()
    procs = [ctx.Process(target=_worker, args=(target, queue, barrier, *args)) for _ in range(n)]
    for p in procs:
        p.start()
    out = [queue.get(timeout=timeout) for _ in procs]
    for p in procs:
        p.join(timeout)
    return out


def _worker(target: Callable[..., Any], queue: Any, barrier: Any, *args: Any) -> None:
    try:
        queue.put(target(barrier, *args))
    except BaseException:  # the test shows it
        queue.put(("error", traceback.format_exc()))


def open_record_and_open_study(barrier: Any, url: str) -> Any:
    """Open a (new) database and store a run, all at once; then open a (new) study, all at once."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    barrier.wait()
    with ResultStore(url) as store:
        run = store.record(
            analysis="modal",
            model_name="m",
            model_path="m.toml",
            model_text="[model]",
            model_sha256="a" * 64,
            parameters={},
            scalars={"x_m": 1.0},
        )
        barrier.wait()  # and all open the new study at once
        _, existed = StudyStore(store).open(
            "shared",
            kind="oat",
            analysis="modal",
            definition={"study": {"name": "shared"}},
            model_path="m.toml",
            model_sha256="b" * 64,
            model_files={},
            parameters=["p"],
            outputs=["y"],
        )
    return ("ok", run, existed)


def run_study_file(
    barrier: Any,
    path: str,
    url: str,
    block_seconds: float = 0.0,
    grace: int | None = None,
    elsewhere: bool = False,
) -> Any:
    """Run a study file into a database; each block takes at least ``block_seconds``; with
    ``elsewhere`` the process owns its trials as if it ran on another host (only its heartbeats
    then tell the others that it is alive)."""
    import os
    import time

    from mechdyn.studies import evaluate, kinds, load_study, run_study

    if grace is not None:
        kinds.HEARTBEAT, kinds.HEARTBEAT_GRACE = 1, grace
    if elsewhere:
        kinds._owner = lambda: f"host-{os.getpid()}:{os.getpid()}"
    if block_seconds:
        call = evaluate.Evaluator.__call__

        def slow(self: Any, X: Any, curves: bool = False) -> Any:
            time.sleep(block_seconds)
            return call(self, X, curves)

        evaluate.Evaluator.__call__ = slow  # type: ignore[method-assign]
    barrier.wait()
    result = run_study(load_study(path), url)
    return ("ok", result.evaluated, result.reused)
