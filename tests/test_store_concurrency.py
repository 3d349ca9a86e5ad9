"""Processes that share a results database: creating it, a study, and an optimization together;
killed at the worst moments; slower than the heartbeat's grace. On SQLite and PostgreSQL.

The processes that race wait at a barrier first (tests/store_workers.py), so every run meets the
race; a process that could hang is run under a timeout, so a hang fails the test instead of
stalling the suite.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import optuna
import pytest

from conftest import EXAMPLES, _fresh_postgres_database
from mechdyn.cli.main import main
from mechdyn.store import ResultStore, resolve_url
from mechdyn.studies.storage import StudyStore, optuna_name
from store_workers import open_record_and_open_study, run_study_file, run_together

OPTIMIZATION = """
[study]
name = "shared-opt"
kind = "optimize"
model = "press_on_support.toml"
analysis = "support"
samples = {samples}
batch = {batch}
seed = 5

[[parameters]]
path = "support.stiffness"
range = "±30 %"

[[objectives]]
output = "displacement_max_m"
"""


def _study_file(tmp_path, samples=40, batch=4):
    for f in ("press_on_support.toml", "press_link_drive.toml"):
        (tmp_path / f).write_text((EXAMPLES / f).read_text())
    path = tmp_path / "opt.toml"
    path.write_text(OPTIMIZATION.format(samples=samples, batch=batch))
    return path


def _trials(url, name="shared-opt"):
    storage = optuna.storages.RDBStorage(resolve_url(url), skip_table_creation=True)
    try:
        return optuna.load_study(study_name=optuna_name(name), storage=storage).trials
    finally:
        storage.remove_session()
        storage.engine.dispose()


@pytest.fixture(params=["sqlite", pytest.param("postgresql", marks=pytest.mark.slow)])
def store_url(request, tmp_path):
    """A fresh results database: SQLite in the test command; the same multi-process tests on
    PostgreSQL (5 to 80 s each, mostly waiting on other processes) in .ci/run's heavy step."""
    if request.param == "sqlite":
        yield str(tmp_path / "results.db")
        return
    with _fresh_postgres_database() as url:
        yield url


def _abandoned(trials):
    """Trials failed because their process died: each asked again (``mechdyn:retry_of``)."""
    retried = {t.system_attrs["mechdyn:retry_of"] for t in trials if "mechdyn:retry_of" in t.system_attrs}
    return [t for t in trials if t.number in retried]


def _evaluated(trials):
    gone = {t.number for t in _abandoned(trials)}
    return [t for t in trials if t.state.is_finished() and "variant" in t.user_attrs and t.number not in gone]


def test_processes_opening_one_new_database_and_one_new_study_together(store_url):
    results = run_together(open_record_and_open_study, 8, store_url)
    assert [r[0] for r in results] == ["ok"] * 8, results
    assert sorted(r[2] for r in results) == [False] + [True] * 7  # one created the study, once
    assert len({r[1] for r in results}) == 8  # eight runs, none lost
    with ResultStore(store_url, read_only=True) as store:
        assert len(store.runs()) == 8 and len(StudyStore(store).studies()) == 1


@pytest.mark.slow  # two processes and an Optuna study between them: 8 s
def test_two_processes_share_one_optimization(store_url, tmp_path):
    path = _study_file(tmp_path)
    results = run_together(run_study_file, 2, str(path), store_url)
    assert [r[0] for r in results] == ["ok", "ok"], results
    trials = _trials(store_url)
    evaluated = _evaluated(trials)
    assert 40 <= len(evaluated) <= 40 + 4  # the two may each ask one last batch at the same time
    assert len({t.number for t in trials}) == len(trials)
    with ResultStore(store_url) as store:
        vs = StudyStore(store).variants("shared-opt")
    assert len(vs) == len({v.key for v in vs})
    assert {t.user_attrs["variant"] for t in evaluated} <= {v.id for v in vs}


@pytest.mark.slow  # two processes through blocks of 3.5 s: timing, not work (.ci/run's heavy step)
def test_shared_optimization_with_blocks_slower_than_the_heartbeat_grace(store_url, tmp_path):
    path = _study_file(tmp_path, samples=8, batch=2)
    # grace 2 s, every block 3.5 s, on one host: a process that still runs is never taken for dead,
    # however late its heartbeat on a loaded machine (the two once failed each other's trials until
    # the test's 300 s ran out)
    results = run_together(run_study_file, 2, str(path), store_url, 3.5, 2)
    assert [r[0] for r in results] == ["ok", "ok"], results
    trials = _trials(store_url)
    assert _abandoned(trials) == []
    assert 8 <= len(_evaluated(trials)) <= 8 + 2


@pytest.mark.slow  # two processes through blocks of 8 s: timing, not work (.ci/run's heavy step)
def test_processes_on_other_hosts_stay_alive_through_their_heartbeats(store_url, tmp_path):
    # as if on two hosts (no process can look at the other's): grace 6 s, heartbeat 1 s, every block
    # 8 s: alive only through the heartbeat thread
    path = _study_file(tmp_path, samples=8, batch=2)
    results = run_together(run_study_file, 2, str(path), store_url, 8.0, 6, True)
    assert [r[0] for r in results] == ["ok", "ok"], results
    trials = _trials(store_url)
    assert _abandoned(trials) == []
    assert 8 <= len(_evaluated(trials)) <= 8 + 2


def test_a_trial_owner_that_exited_or_whose_pid_was_reused_is_gone():
    # a zombie (exited, not yet reaped) and a pid now held by another process are not the owner
    import socket
    import subprocess
    import sys

    from mechdyn.studies.kinds import liveness

    host = socket.gethostname()
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        start = liveness.started(child.pid)
        assert liveness.running_here(f"{host}:{child.pid}@{start}") is True
        assert liveness.running_here(f"{host}:{child.pid}@{int(start) + 1}") is False  # a reused pid
        assert liveness.running_here(f"elsewhere:{child.pid}@{start}") is None  # another host: unknown
        assert liveness.running_here(liveness.owner()) is None  # this process
    finally:
        child.kill()
    deadline = time.monotonic() + 60
    while liveness.started(child.pid) != "gone" and time.monotonic() < deadline:  # killed, not reaped
        time.sleep(0.01)
    assert liveness.dead(f"{host}:{child.pid}@{start}")
    child.wait()
    assert liveness.dead(f"{host}:{child.pid}@{start}")


_KILL = {
    # killed right after Optuna handed out the trial: no owner, no heartbeat (waits out the grace)
    "after ask": "import optuna\n"
    "ask = optuna.study.Study.ask\n"
    "def ask_and_die(self, *a, **k):\n"
    "    t = ask(self, *a, **k)\n"
    "    if len(self.get_trials(deepcopy=False)) > {after}: os.kill(os.getpid(), signal.SIGKILL)\n"
    "    return t\n"
    "optuna.study.Study.ask = ask_and_die\n",
    # killed between ask and the first heartbeat (the owner is known to be gone: failed at once)
    "before the heartbeat": "from mechdyn.studies.kinds import liveness\n"
    "calls = []\n"
    "def die(self):\n"
    "    calls.append(1)\n"
    "    if len(calls) > {blocks}: os.kill(os.getpid(), signal.SIGKILL)\n"
    "    return enter(self)\n"
    "enter = liveness.Heartbeat.__enter__\n"
    "liveness.Heartbeat.__enter__ = die\n",
    # killed after evaluating and storing a block, before telling Optuna
    "before tell": "from mechdyn.studies.kinds import liveness\n"
    "calls = []\n"
    "def die(self, *exc):\n"
    "    leave(self, *exc)\n"
    "    calls.append(1)\n"
    "    if len(calls) > {blocks}: os.kill(os.getpid(), signal.SIGKILL)\n"
    "leave = liveness.Heartbeat.__exit__\n"
    "liveness.Heartbeat.__exit__ = die\n",
}


def _run(code: str, tmp_path, timeout: float = 180) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code], cwd=tmp_path, timeout=timeout, capture_output=True, text=True
    )


@pytest.mark.parametrize(
    "moment",  # 9 s each: in CI's heavy step (tests/test_studies.py kills a study in the test command)
    [pytest.param(m, marks=pytest.mark.slow) for m in _KILL],
)
def test_an_optimization_killed_at_any_moment_resumes_and_counts_only_its_evaluations(
    store_url, tmp_path, moment
):
    path = _study_file(tmp_path, samples=12, batch=4)
    kill = _KILL[moment].format(after=5, blocks=1)
    killed = _run(
        "import os, signal\n" + kill + "from mechdyn.studies import load_study, run_study\n"
        f"run_study(load_study({str(path)!r}), {store_url!r})\n",
        tmp_path,
    )
    assert killed.returncode == -signal.SIGKILL, killed.stderr
    before = _trials(store_url)
    assert any(t.state == optuna.trial.TrialState.RUNNING for t in before)  # left in flight
    # resumed in a fresh process, with a short grace for the trial that never got a heartbeat;
    # a hang fails the test through the timeout
    resumed = _run(
        "from mechdyn.studies import load_study, run_study\n"
        "from mechdyn.studies.kinds import liveness\n"
        "liveness.HEARTBEAT, liveness.HEARTBEAT_GRACE = 1, 2\n"
        f"r = run_study(load_study({str(path)!r}), {store_url!r})\n"
        "print(r.evaluated, r.reused, r.findings['trials'])\n",
        tmp_path,
    )
    assert resumed.returncode == 0, resumed.stderr
    _, reused, counted = map(int, resumed.stdout.split())
    trials = _trials(store_url)
    assert len(_evaluated(trials)) == counted == 12  # exactly the samples asked for
    abandoned = _abandoned(trials)
    assert abandoned and all(t.state == optuna.trial.TrialState.FAIL for t in abandoned)
    retried = {t.system_attrs.get("mechdyn:retry_of"): t for t in trials}
    for t in abandoned:  # each asked again with its parameters
        assert retried[t.number].params == t.params
    if moment == "before tell":  # the block was stored: reused, not computed again
        assert reused >= 4
    with ResultStore(store_url, read_only=True) as store:
        vs = StudyStore(store).variants("shared-opt")
    assert len(vs) == len({v.key for v in vs})


@pytest.mark.slow  # CI's heavy step (issue 48: the test command's minutes)
def test_deleting_an_optimization_deletes_its_trials(store_url, tmp_path, capsys):
    path = _study_file(tmp_path, samples=6, batch=3)
    assert main(["study", str(path), "--db", store_url, "--json"]) == 0
    first = json.loads(capsys.readouterr().out)
    assert len(_evaluated(_trials(store_url))) == 6
    assert main(["results", "delete", "--study", "shared-opt", "--db", store_url]) == 0
    capsys.readouterr()
    with pytest.raises(KeyError):
        _trials(store_url)
    assert main(["study", str(path), "--db", store_url, "--json"]) == 0  # runs again in full
    again = json.loads(capsys.readouterr().out)
    assert (again["evaluated"], again["reused"]) == (first["evaluated"], first["reused"])
    assert again["trials"] == first["trials"] == 6
    assert again["best"]["parameters"] == first["best"]["parameters"]  # the same seeded optimum
