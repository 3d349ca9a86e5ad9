"""Which trials of a shared optimization are still being evaluated, and by whom.

Several processes (on one host or many) may run one optimization on one database: each asks Optuna
for a batch of trials, evaluates it, and tells the results. A process that dies (``kill -9``, a lost
node) leaves its trials running; they are failed and asked again (:func:`retry`), so the variants it
stored are reused and the study counts exactly its ``samples``. A trial is gone when its heartbeat is
stale (Optuna's heartbeat, every :data:`HEARTBEAT` s, missed for :data:`HEARTBEAT_GRACE` s), when it
never got one within the grace, or when its owner (``host:pid@start``, :func:`owner`) was a process
on this host that no longer runs; a process on this host that still runs is never taken for dead,
however late its heartbeat.
"""

from __future__ import annotations

import os
import threading
from datetime import datetime
from typing import Any

__all__ = [
    "HEARTBEAT",
    "HEARTBEAT_GRACE",
    "OWNER",
    "Heartbeat",
    "abandoned",
    "dead",
    "fail_abandoned",
    "owner",
    "retry",
    "running_here",
    "started",
]

HEARTBEAT, HEARTBEAT_GRACE = 2, 20  # s: an optimization trial's heartbeat, and how long it may miss it

RETRY_OF = "mechdyn:retry_of"  # a trial asked again for one whose process died
OWNER = "mechdyn:owner"  # host:pid of the process that asked a trial


def retry(study: Any, trial: Any) -> None:
    """A trial whose process died is asked again with the same parameters (a variant that process
    stored is then reused, not recomputed); the failed one counts for nothing (:func:`abandoned`)."""
    import optuna

    study.add_trial(
        optuna.create_trial(
            state=optuna.trial.TrialState.WAITING,
            params=trial.params,
            distributions=trial.distributions,
            system_attrs={RETRY_OF: trial.number},
        )
    )


def abandoned(trials: list[Any]) -> set[int]:
    """The numbers of the trials that were failed because their process died (asked again since)."""
    return {t.system_attrs[RETRY_OF] for t in trials if RETRY_OF in t.system_attrs}


def owner() -> str:
    """This process as a trial's owner: ``host:pid@start`` (the start time tells a reused pid apart)."""
    import socket

    start = started(os.getpid())
    return f"{socket.gethostname()}:{os.getpid()}" + (f"@{start}" if start else "")


def started(pid: int) -> str | None:
    """When a process started, in clock ticks since boot (Linux's /proc), or None where unknown;
    ``"gone"`` for a process that has exited and waits to be reaped (a zombie)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rpartition(")")[2].split()
    except OSError:
        return None
    if len(fields) < 20:
        return None
    return "gone" if fields[0] in ("Z", "X") else fields[19]


def running_here(owner: str | None) -> bool | None:
    """Whether the process that asked a trial still runs, when it is another process on this host
    (True or False); None when it is this process, on another host or not known."""
    import socket

    who, _, start = (owner or "").partition("@")
    host, _, pid = who.rpartition(":")
    if host != socket.gethostname() or not pid.isdigit() or int(pid) == os.getpid():
        return None
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    now = started(int(pid))
    if now == "gone":
        return False
    return not start or now in (start, None)  # a reused pid is another process


def dead(owner: str | None) -> bool:
    """Whether the process that asked a trial is known to be gone (on this host)."""
    return running_here(owner) is False


def fail_abandoned(study: Any, storage: Any) -> None:
    """Fail (and ask again) the running trials whose process is gone: those whose heartbeat is stale
    (Optuna), those asked on this host by a process that no longer runs, and those that never got a
    heartbeat within the grace period (killed between ``ask`` and the first heartbeat)."""
    import optuna
    from sqlalchemy import text

    running = study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.RUNNING,))
    if not running:
        return
    # Optuna's own test of a stale heartbeat (against the database server's clock)
    stale = set(storage._get_stale_trial_ids(study._study_id))
    with storage.engine.connect() as conn:
        beating = {tid for (tid,) in conn.execute(text("SELECT trial_id FROM trial_heartbeats"))}
    now = datetime.now()
    for t in running:
        owner = t.system_attrs.get(OWNER)
        if running_here(owner):
            # another process on this host that still runs: never taken for dead, however late its
            # heartbeat (a loaded machine delayed one past the grace period, and two processes then
            # failed each other's trials without end)
            continue
        silent = (
            t._trial_id not in beating
            and t.datetime_start is not None
            and ((now - t.datetime_start).total_seconds() > HEARTBEAT_GRACE)
        )
        if t._trial_id in stale or silent or dead(owner):
            try:
                if storage.set_trial_state_values(t._trial_id, state=optuna.trial.TrialState.FAIL):
                    retry(study, storage.get_trial(t._trial_id))
            except optuna.exceptions.UpdateFinishedTrialError:  # another process was first
                pass


class Heartbeat:
    """Record the heartbeats of a batch's trials every ``HEARTBEAT`` s while it is evaluated, so a
    block that takes longer than the grace period is not taken for a dead process's."""

    def __init__(self, storage: Any, trial_ids: list[int]):
        self.storage, self.trial_ids = storage, trial_ids
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._beat, daemon=True)

    def _beat(self) -> None:
        while not self.stop.wait(HEARTBEAT):
            for tid in self.trial_ids:
                self.storage.record_heartbeat(tid)

    def __enter__(self) -> Heartbeat:
        for tid in self.trial_ids:
            self.storage.record_heartbeat(tid)
        self.thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.thread.join()
