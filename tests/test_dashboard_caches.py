"""What the dashboard keeps between requests stays within its bounds: entries and bytes, after three
times as many distinct studies and variants as it keeps; and a kept answer (a study's findings and
their pictures, its best design) is worked out again once the study gains variants."""

from __future__ import annotations

import json
import re
import shutil
import threading
import time
import urllib.error
import urllib.request
from concurrent.futures import ThreadPoolExecutor

import pytest
from hypothesis import given
from hypothesis import strategies as st

from conftest import EXAMPLES, serving
from mechdyn.cli.main import main
from mechdyn.dashboard.caches import BoundedCache
from mechdyn.dashboard.state import CacheLimits

STUDIES = 6  # three times the smallest bound below
SMALL = CacheLimits(studies=2, what_ifs=2, findings=2, curves=2)


def _study(name: str, samples: int, seed: int) -> str:
    return f"""
[study]
name = "{name}"
kind = "lhs"
model = "{(EXAMPLES / "fourbar.toml").as_posix()}"
analysis = "mechanism"
samples = {samples}
seed = {seed}
options = {{ angles = 36 }}
curves = 0  # the curves of the base design and the best only

[[parameters]]
path = "bodies.coupler.mass"
range = "±20 %"

[[outputs]]
output = "driving_torque_max_Nm"
"""


@pytest.fixture(scope="module")
def database(tmp_path_factory):
    """Six small four-bar studies (ids 1 to 6); the first has variants whose curves were not kept."""
    d = tmp_path_factory.mktemp("caches")
    db = str(d / "results.db")
    for i in range(STUDIES):
        (d / f"s{i}.toml").write_text(_study(f"fourbar-{i}", 12 if i == 0 else 3, i))
        assert main(["study", str(d / f"s{i}.toml"), "--db", db]) == 0
    return db


def _get(url: str) -> tuple[int, bytes]:
    try:
        with urllib.request.urlopen(url) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        with e:
            return e.code, e.read()


def _json(url: str):
    status, body = _get(url)
    assert status == 200, body[:500]
    return json.loads(body)


def _findings(address: str, study: int) -> str:
    """A study's findings section, once worked out in the background."""
    for _ in range(600):
        status, body = _get(f"{address}/studies/{study}/findings")
        if status == 200:
            return body.decode()
        time.sleep(0.1)
    pytest.fail(f"the findings of study {study} never came")


def _pictures(html: str) -> list[str]:
    return [u.replace("&amp;", "&") for u in re.findall(r'<img [^>]*src="([^"]+)"', html)]


def _caches(app) -> dict[str, BoundedCache]:
    state = app.state.dashboard
    names = ("columns", "views", "what_ifs", "best", "findings_kept", "curves")
    return {name: getattr(state, name) for name in names}


def _assert_within(app) -> None:
    for name, cache in _caches(app).items():
        assert len(cache) <= cache.max_entries, name
        assert cache.max_bytes is None or cache.nbytes <= cache.max_bytes, name


def _without_curves(database: str) -> list[int]:
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(database, read_only=True) as store:
        studies = StudyStore(store)
        kept = studies.with_curves(1)
        return [v.id for v in studies.variants("fourbar-0") if v.id not in kept]


# -- the cache itself --------------------------------------------------------------------------------


def test_a_cache_keeps_its_most_recently_used_entries_up_to_its_bound():
    cache: BoundedCache[int, str] = BoundedCache(3)
    for k in range(3):
        cache.put(k, str(k))
    assert cache.get(0) == "0"  # used: 1 is now the least recently used
    cache.put(3, "3")
    assert len(cache) == 3 and 1 not in cache and 0 in cache and cache.get(1) is None
    for k in range(4, 4 + 3 * 3):
        cache.put(k, str(k))
        assert len(cache) == 3
    assert [k for k in range(13) if k in cache] == [10, 11, 12]
    cache.pop(12)
    assert len(cache) == 2 and 12 not in cache
    with pytest.raises(ValueError):
        BoundedCache(0)


@given(st.lists(st.tuples(st.integers(0, 30), st.integers(0, 400)), max_size=60))
def test_a_cache_of_payloads_stays_within_its_entries_and_bytes(puts):
    cache: BoundedCache[int, bytes] = BoundedCache(5, max_bytes=1000, weigh=len)
    for key, size in puts:
        cache.put(key, b"x" * size)
        kept = [k for k in range(31) if k in cache]
        assert len(kept) == len(cache) <= 5
        assert cache.nbytes == sum(len(cache.get(k) or b"") for k in kept) <= 1000
        assert key in cache  # the newest is kept: alone, it is within the bound


def test_an_entry_heavier_than_the_bound_is_not_kept_and_a_filled_in_one_is_weighed_again():
    cache: BoundedCache[str, list[bytes]] = BoundedCache(10, max_bytes=100, weigh=lambda v: sum(map(len, v)))
    cache.put("a", [b"x" * 60])
    cache.put("big", [b"x" * 101])
    assert "big" not in cache and "a" in cache and cache.nbytes == 60
    later: list[bytes] = []  # a value that fills in after it is kept (a future's result)
    cache.put("later", later)
    assert cache.nbytes == 60
    later.append(b"x" * 50)
    cache.reweigh("later")  # 110 bytes: the least recently used goes
    assert "a" not in cache and "later" in cache and cache.nbytes == 50
    cache.reweigh("gone")  # nothing kept under that key: nothing happens
    assert len(cache) == 1


# -- the dashboard's caches ---------------------------------------------------------------------------


@pytest.mark.slow  # six real studies through every cache (over 10 s): CI's heavy step
def test_every_cache_stays_within_its_bounds_after_three_times_as_many_studies_and_variants(database):
    from mechdyn.dashboard.app import create_app

    app = create_app(database, limits=SMALL)
    with serving(app) as address:
        first = None
        for study in range(1, STUDIES + 1):
            status, _ = _get(f"{address}/studies/{study}")
            assert status == 200
            _assert_within(app)
            assert _json(f"{address}/api/studies/{study}/whatif")["best"]["id"] > 0
            _assert_within(app)
            findings = _findings(address, study)
            assert len(_pictures(findings)) > 0
            _assert_within(app)
            if first is None:
                first = findings
        variants = _without_curves(database)[: 3 * SMALL.curves]
        assert len(variants) == 3 * SMALL.curves
        for v in variants:
            status, html = _get(f"{address}/compare?variant={v}")
            assert status == 200 and b"recomputed from its stored inputs" in html
            _assert_within(app)
        # each filled up, then dropped its least recently used entries
        assert all(len(c) == c.max_entries for c in _caches(app).values())
        # a study dropped from every cache is answered as before, its findings worked out again
        assert 1 not in app.state.dashboard.findings_kept
        assert _findings(address, 1) == first
        assert all(_get(address + url)[0] == 200 for url in _pictures(first))
        _assert_within(app)


@pytest.mark.slow  # findings with pictures, computed twice (over 10 s): CI's heavy step
def test_pictures_and_curves_are_kept_within_their_bytes(database):
    from mechdyn.dashboard.app import create_app

    app = create_app(database)  # to weigh one study's pictures and one variant's curves
    variants = _without_curves(database)
    with serving(app) as address:
        _findings(address, 1)
        assert _get(f"{address}/compare?variant={variants[0]}")[0] == 200
        pictures, curves = app.state.dashboard.findings_kept.nbytes, app.state.dashboard.curves.nbytes
    assert pictures > 10_000 and curves > 1_000  # PNG pictures; arrays of 36 angles
    # room for one study's pictures and one variant's curves (those of another are as heavy, give or
    # take a few per cent), many entries
    limits = CacheLimits(
        findings=16, findings_bytes=3 * pictures // 2, curves=16, curves_bytes=3 * curves // 2
    )
    app = create_app(database, limits=limits)
    with serving(app) as address:
        for study in range(1, STUDIES + 1):
            latest = _pictures(_findings(address, study))
            _assert_within(app)
        assert len(app.state.dashboard.findings_kept) == 1
        assert all(_get(address + url)[0] == 200 for url in latest)  # the last study's, still kept
        for v in variants[:STUDIES]:
            assert _get(f"{address}/compare?variant={v}")[0] == 200
            _assert_within(app)
        assert len(app.state.dashboard.curves) == 1


def test_a_study_that_gains_variants_has_its_findings_and_best_design_worked_out_again(database, tmp_path):
    from mechdyn.dashboard.app import create_app
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore, variant_key

    db = str(tmp_path / "growing.db")
    shutil.copy(database, db)
    app = create_app(db)
    with serving(app) as address:
        n = _json(f"{address}/api/studies/2/count")["variants"]
        before = _pictures(_findings(address, 2))
        assert before and all(url.endswith(f"?variants={n}") for url in before)
        assert all(_get(address + url)[0] == 200 for url in before)
        best = _json(f"{address}/api/studies/2/whatif")["best"]
        with ResultStore(db) as store:  # another process adding a variant, as a running study does
            studies = StudyStore(store)
            stored = studies.study("fourbar-1")
            key = variant_key([1.0, 0.1])
            row = {
                "key": key,
                "position": studies.next_position(stored.id),
                "parameters": {"bodies.coupler.mass": 1.0},
                "given": {},
                "outputs": {"driving_torque_max_Nm": 0.1},  # the best of the study now
                "status": "ok",
                "error": None,
                "model_sha256": stored.model_sha256,
            }
            studies.add(stored.id, [row])
            added = studies.ids(stored.id, [key])[key]
        assert _json(f"{address}/api/studies/2/count")["variants"] == n + 1
        now = _json(f"{address}/api/studies/2/whatif")["best"]
        assert best["id"] != added and now["id"] == added
        assert now["outputs"][0]["value"] == pytest.approx(0.1)
        after = _pictures(_findings(address, 2))
        assert after and all(url.endswith(f"?variants={n + 1}") for url in after)
        assert all(_get(address + url)[0] == 200 for url in after)
        assert all(_get(address + url)[0] == 404 for url in before)  # that state is no longer kept
        kept = app.state.dashboard.findings_kept
        assert len(kept) == 1 and kept.get(2)[0] == n + 1


def test_findings_of_a_number_of_variants_no_longer_stored_are_not_worked_out(database):
    """The one background worker busy, a study's findings asked for 4 variants, then for 5 (it
    gained one): those of 4 are cancelled before they start, and whoever waits for them gets those
    of 5."""
    from mechdyn.dashboard.state import DashboardState, Findings

    state = DashboardState(database)
    release, asked = threading.Event(), threading.Event()
    worked: list[tuple[int, int]] = []

    def work_out(st, n_variants):
        release.wait(60)
        worked.append((st.id, n_variants))
        return Findings([], [], "", {}, n_variants)

    future_of = state._findings_future

    def asked_for(st, n_variants, *, latest):
        future = future_of(st, n_variants, latest=latest)
        if threading.current_thread() is not threading.main_thread():
            asked.set()  # the waiter below holds the future of 4 variants
        return future

    state._work_out_findings = work_out
    state._findings_future = asked_for
    first, second = state.study(1), state.study(2)
    try:
        with ThreadPoolExecutor(1) as pool:
            assert state.findings(first, 13, wait=0) is None  # the worker is busy with it
            waiter = pool.submit(state.findings, second, 4, None)
            assert asked.wait(60)
            assert state.findings(second, 5, wait=0) is None
            release.set()
            assert waiter.result(60).variants == 5
        assert state.findings(second, 5, None).variants == 5
        assert worked == [(1, 13), (2, 5)]  # those of 4 variants never were
        assert state.kept_findings(second, 4) is None and state.kept_findings(second, 5).variants == 5
    finally:
        release.set()
        state.close()
        state.store.close()
