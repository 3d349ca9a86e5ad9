"""Shared fixtures: the reference machines, and results stores on SQLite and PostgreSQL."""

from __future__ import annotations

import os
import sys
import uuid
import warnings
from contextlib import contextmanager
from pathlib import Path

import pytest
from hypothesis import settings

import mechdyn
from mechdyn.errors import ModelWarning

# The property tests draw the same cases on every run of the test command, so a clean clone passes or
# fails for a reason, never for a lucky draw (hypothesis's advice for CI). New cases are searched with
# `pytest --hypothesis-profile=explore` (a fresh draw on each run); a failure found there
# becomes a named test.
settings.register_profile("ci", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

# Python's bytecode caches (and pytest's of the rewritten test modules) are written for the run even
# where the shell asks for none (PYTHONDONTWRITEBYTECODE, as some containers set it): without them each
# worker and each command-line subprocess compiles every module from source again. They go where
# Python puts them, __pycache__ folders the checkout ignores.
if os.environ.pop("PYTHONDONTWRITEBYTECODE", None) is not None:
    sys.dont_write_bytecode = False

# The xdist workers are the run's parallelism: each keeps its linear algebra to one thread, as the
# command line does beside its figure workers (mechdyn.figure_workers.one_blas_thread). With a BLAS
# pool in each of three workers on two cores, a pool thread spins after each call, taking turns with
# the other workers' tests (a run took about 15 % more CPU time). Set here, before the workers and
# the command-line subprocesses start, they inherit it; a value the shell sets is kept.
for _name in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


def load_quiet(path: Path):
    """Load a model file, ignoring the ratio warnings that the published turret data raise."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return mechdyn.load(path).model


@pytest.fixture(scope="session")
def turret_b():
    """Reference machine B: the indexing path, flexible meshes (published data)."""
    return load_quiet(EXAMPLES / "turret_indexing.toml")


@pytest.fixture(scope="session")
def turret_c():
    """Reference machine C: the mill driving path, flexible meshes (published data)."""
    return load_quiet(EXAMPLES / "turret_milling.toml")


@pytest.fixture(scope="session")
def turret_startup():
    """Reference machine C in time (``examples/turret_milling_startup.toml``): the loaded file, its
    gear system with the teeth held in contact (the file's sweep), and its motor on disk 1."""
    from mechdyn.gear_dynamics import GearSystem

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        loaded = mechdyn.load(EXAMPLES / "turret_milling_startup.toml")
    dynamics = loaded.settings.dynamics
    system = GearSystem.from_drivetrain(loaded.model, **{**dynamics.system_options(), "backlash": {}})
    return loaded, system, dynamics.inputs()[0]


def _postgres_url() -> str:
    url = os.environ.get("MECHDYN_TEST_POSTGRES_URL")
    if url:
        return url
    if os.environ.get("CI"):
        pytest.fail("MECHDYN_TEST_POSTGRES_URL is not set in CI: run the tests through scripts/with-postgres")
    pytest.skip("no PostgreSQL server: run the tests through scripts/with-postgres")


@contextmanager
def _fresh_postgres_database():
    import psycopg

    base = _postgres_url()
    name = f"mechdyn_test_{uuid.uuid4().hex[:12]}"
    with psycopg.connect(base, autocommit=True) as conn:
        conn.execute(f'CREATE DATABASE "{name}"')
    try:
        yield base.rsplit("/", 1)[0] + "/" + name
    finally:
        with psycopg.connect(base, autocommit=True) as conn:
            conn.execute(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')


@pytest.fixture(params=["sqlite", "postgresql"])
def store_url(request, tmp_path):
    """A fresh, empty results database of each backend."""
    if request.param == "sqlite":
        yield str(tmp_path / "results.db")
        return
    with _fresh_postgres_database() as url:
        yield url


@pytest.fixture
def postgres_url():
    """A fresh, empty database on the PostgreSQL server of the test command."""
    with _fresh_postgres_database() as url:
        yield url


@contextmanager
def serving(app):
    """A real uvicorn server for ``app`` on a free local port, in a thread; yields its address."""
    import socket
    import threading
    import time

    import uvicorn

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    srv = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=srv.run, daemon=True)
    thread.start()
    deadline = time.time() + 30
    while not srv.started and time.time() < deadline:
        time.sleep(0.05)
    try:
        yield f"http://127.0.0.1:{port}"
    finally:
        srv.should_exit = True
        thread.join(60)  # uvicorn lets the requests in flight finish first
        # no thread of the dashboard outlives the test: the warnings filters are one per process,
        # and a findings job still drawing would change them under the next test
        app.state.dashboard.close(wait=True)
        app.state.store.close()
        for kept in getattr(app.state, "keeper", ()):  # the connection that keeps designs, if opened
            kept.close()


def chromium() -> str:
    """The Chromium that browser tests drive (scripts/with-chromium installs it and names it in
    MECHDYN_TEST_CHROMIUM); without one a test is skipped, and in CI it fails."""
    import shutil

    path = os.environ.get("MECHDYN_TEST_CHROMIUM") or shutil.which("chromium")
    if path:
        return path
    if os.environ.get("CI"):
        pytest.fail("no Chromium in CI: run the tests through scripts/with-chromium")
    pytest.skip("no Chromium: run the tests through scripts/with-chromium")


def open_in_chromium(playwright, url: str):
    """A new headless Chromium (:func:`chromium`) with one 1280 × 900 page at ``url``; returns the
    browser (to close), the page and the list the page's uncaught JavaScript errors are added to."""
    browser = playwright.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(url)
    return browser, page, errors


@pytest.fixture(scope="module")
def patient_browser_checks():
    """Playwright's checks wait for the page to show what they expect; on a loaded two-core machine
    that can take longer than its 5 s default, so the ceiling is a minute (a passing check returns
    as soon as the page shows it: no fixed wait). Use in a module: ``pytestmark =
    pytest.mark.usefixtures("patient_browser_checks")``."""
    from playwright.sync_api import expect

    expect.set_options(timeout=60_000)
    yield
    expect.set_options(timeout=5_000)


_KERNELS_READY = "MECHDYN_TEST_KERNELS_READY"
"""The environment variable that names a file the test command writes once numba's kernels are
compiled (:func:`pytest_configure`); each worker waits for it before its first test."""
_WARMING = pytest.StashKey()  # the controller's thread that waits for the compiling processes


def pytest_configure(config):
    """Before the xdist workers start, start compiling numba's kernels in two processes (one per
    family, ``tests/warm_kernels.py``): on a clean clone the cache is empty, and each worker, and each
    command-line subprocess of a test, would compile the same kernels at once. With a warm cache
    each process finds them cached and exits. The workers collect the tests meanwhile (a core is
    idle while the largest family compiles) and wait for the kernels before their first test
    (:func:`pytest_collection_finish`)."""
    if hasattr(config, "workerinput") or not config.pluginmanager.hasplugin("xdist"):
        return
    if not config.getoption("numprocesses", None) or config.getoption("collectonly"):
        return
    import subprocess
    import tempfile
    import threading

    script = str(Path(__file__).with_name("warm_kernels.py"))
    jobs = [subprocess.Popen([sys.executable, script, family]) for family in ("dyads", "gears")]
    ready = Path(tempfile.mkdtemp(prefix="mechdyn-kernels-")) / "ready"
    os.environ[_KERNELS_READY] = str(ready)  # the workers, started after this hook, inherit it

    def wait_for_them() -> None:
        for job in jobs:
            job.wait()
        ready.touch()

    config.stash[_WARMING] = threading.Thread(target=wait_for_them, daemon=True)
    config.stash[_WARMING].start()


def pytest_collection_finish(session):
    """In an xdist worker, after collecting: wait until the kernels are compiled (the file named by
    :data:`_KERNELS_READY` exists), however long that takes within the run's own timeout."""
    import time

    ready = os.environ.get(_KERNELS_READY)
    if not ready or not hasattr(session.config, "workerinput"):
        return
    deadline = time.monotonic() + 900
    while not os.path.exists(ready) and time.monotonic() < deadline:
        time.sleep(0.05)


def pytest_unconfigure(config):
    """The controller waits for the compiling processes (a short run may end first) and removes the
    file that said the kernels were ready, and its folder."""
    warming = config.stash.get(_WARMING, None)
    if warming is not None:
        import shutil

        warming.join()
        shutil.rmtree(Path(os.environ[_KERNELS_READY]).parent, ignore_errors=True)


def pytest_xdist_auto_num_workers(config):
    """``-n auto``: one worker more than the cores. A good part of the suite waits (on subprocesses
    of the command line and the store, a browser, a database server), so a third worker on a
    two-core machine keeps both cores busy: the test command in 271 s against about 290 s."""
    return (os.cpu_count() or 1) + 1
