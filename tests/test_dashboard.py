"""The web dashboard, driven in headless Chromium by Playwright over a database filled by real runs
and a real study: list → open a run → open a study → pick variants → compare them."""

from __future__ import annotations

import json
import re
import socket
import threading
import urllib.error
import urllib.request
from datetime import UTC, datetime, timedelta

import pytest

from conftest import EXAMPLES, chromium, serving
from mechdyn.cli.main import main

pytestmark = pytest.mark.usefixtures("patient_browser_checks")


@pytest.fixture(scope="module")
def database(tmp_path_factory):
    """Real runs and a real study, as a user makes them."""
    d = tmp_path_factory.mktemp("dashboard")
    db = str(d / "results.db")
    evil = (
        (EXAMPLES / "fourbar.toml")
        .read_text()
        .replace('name = "crank-rocker four-bar"', 'name = "<script>alert(1)</script>"')
    )
    (d / "evil.toml").write_text(evil)
    for argv in (
        ["support", str(EXAMPLES / "press_on_support.toml"), "--cycles", "1"],
        ["modal", str(EXAMPLES / "turret_indexing.toml")],
        ["mechanism", str(d / "evil.toml"), "--angles", "36"],
        ["study", str(EXAMPLES / "studies" / "press_support_influence.toml")],
    ):
        assert main([*argv, "--db", db]) == 0
    return db


def _write_refused(url: str, message: str) -> None:
    from mechdyn.store.store import ResultStore

    store = ResultStore(url, read_only=True)
    try:
        with pytest.raises(Exception, match=message):
            store.record(
                analysis="x",
                model_name="x",
                model_path="x",
                model_text="",
                model_sha256="x",
                parameters={},
                scalars={},
            )
    finally:
        store.close()


@pytest.fixture(scope="module")
def server(database):
    from mechdyn.dashboard.app import create_app

    with serving(create_app(database)) as address:
        yield address


def _get(url: str, headers: dict[str, str] | None = None) -> tuple[int, str]:
    try:
        with urllib.request.urlopen(urllib.request.Request(url, headers=headers or {})) as r:
            return r.status, r.read().decode()
    except urllib.error.HTTPError as e:
        with e:  # an error left open warns when collected, in whichever test that happens
            return e.code, e.read().decode()


def test_only_trusted_host_names_are_answered(database):
    from mechdyn.dashboard.app import create_app

    with serving(create_app(database, allowed_hosts=["lab-pc.example.org"])) as address:
        port = address.rsplit(":", 1)[1]
        assert _get(address + "/")[0] == 200
        assert _get(address + "/", {"Host": f"localhost:{port}"})[0] == 200
        assert _get(address + "/", {"Host": f"lab-pc.example.org:{port}"})[0] == 200
        # a page whose DNS name was rebound to 127.0.0.1 sends its own name: refused
        status, body = _get(address + "/runs/1", {"Host": f"attacker.example.com:{port}"})
        assert status == 400 and "turret" not in body.lower()


@pytest.mark.parametrize(
    "path", ["/runs/99999999999999999999", "/studies/2147483648", "/api/studies/99999999999999/count",
             "/compare?run=99999999999999999999", "/compare?variant=-3"]
)  # fmt: skip
def test_ids_that_no_database_holds_are_404(server, path):
    status, body = _get(server + path)
    assert status == 404 and "Traceback" not in body


def test_a_file_that_is_no_mechdyn_database_is_refused_at_start(tmp_path, capsys):
    notes = tmp_path / "notes.db"
    notes.write_text("my notes\n" * 50)
    assert main(["dashboard", "--db", str(notes), "--port", "1"]) == 2
    err = capsys.readouterr().err
    assert "is not a results database" in err and err.count("\n") == 1
    assert main(["dashboard", "--db", str(tmp_path / "typo.db"), "--port", "1"]) == 2
    assert "no results database at" in capsys.readouterr().err and not (tmp_path / "typo.db").exists()


def test_listening_beyond_this_machine_is_announced_loudly(database):
    import subprocess
    import sys

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    argv = ["dashboard", "--db", database, "--host", "0.0.0.0", "--port", str(port)]
    proc = subprocess.Popen(
        [sys.executable, "-m", "mechdyn", *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        warning = proc.stderr.readline()  # the first line, before it serves
    finally:
        proc.terminate()
        proc.wait(30)
        proc.stdout.close()
        proc.stderr.close()
    assert warning.startswith("WARNING: listening on 0.0.0.0, beyond this machine")
    assert "--allowed-host" in warning


def test_a_slow_study_page_does_not_hold_up_a_run_page(database, monkeypatch):
    """20 study pages at once, each waiting for the study's findings, which are not worked out until
    the run page asked for next has been answered: the run page is answered while every study page
    still waits (the handlers do their blocking work in a thread pool, not in the event loop; were it
    otherwise, the run page would never come and the test would fail at its timeout). Nothing is left
    to the machine's speed."""
    from concurrent.futures import ThreadPoolExecutor

    from mechdyn.dashboard import pages
    from mechdyn.dashboard.app import create_app
    from mechdyn.dashboard.state import DashboardState

    release = threading.Event()
    work_out = DashboardState._work_out_findings

    def held(self, st, n_variants):  # the findings take until the run page is answered
        release.wait(120)
        return work_out(self, st, n_variants)

    monkeypatch.setattr(DashboardState, "_work_out_findings", held)
    monkeypatch.setattr(pages, "FINDINGS_WAIT", None)  # each study page waits for its findings
    finished: list[str] = []
    lock = threading.Lock()

    def get(address: str, path: str, tag: str) -> None:
        assert _get(address + path)[0] == 200
        with lock:
            finished.append(tag)

    with serving(create_app(database)) as address, ThreadPoolExecutor(24) as pool:
        studies = [pool.submit(get, address, "/studies/1", "study") for _ in range(20)]
        try:
            pool.submit(get, address, "/runs/2", "run").result(timeout=120)
        finally:
            release.set()
        for f in studies:
            f.result(timeout=120)
    assert finished[0] == "run" and finished.count("study") == 20, finished


def test_missing_pages_are_404_pages_and_user_text_is_escaped(server):
    status, body = _get(server + "/runs/999")
    assert status == 404 and "There is no run 999" in body and "Traceback" not in body
    assert _get(server + "/studies/999")[0] == 404
    assert _get(server + "/compare?run=x")[0] == 404
    assert _get(server + "/../../etc/passwd")[0] == 404
    status, body = _get(server + "/")
    assert status == 200 and "<script>alert(1)</script>" not in body and "&lt;script&gt;" in body
    status, js = _get(server + "/static/plotly.min.js")  # shipped in the package, no CDN
    assert status == 200 and js.startswith("/* plotly.js v") and "Plotly" in js[:1000]


def test_pages_name_the_database_without_its_location(postgres_url):
    from mechdyn.dashboard.app import create_app

    assert main(["modal", str(EXAMPLES / "turret_indexing.toml"), "--db", postgres_url, "--json"]) == 0
    with serving(create_app(postgres_url)) as address:
        status, body = _get(address + "/")
    host = postgres_url.split("@")[1].split("/")[0]
    assert status == 200 and host not in body and "mechdyn@" not in body and "postgresql://" not in body
    assert "postgresql database mechdyn_test_" in body


def test_the_database_is_opened_read_only(database):
    _write_refused(database, r"readonly|read-only|read only")


def test_the_dashboard_binds_this_machine_only_by_default():
    from mechdyn.cli.main import build_parser

    args = build_parser().parse_args(["dashboard"])
    assert args.host == "127.0.0.1"


def test_a_designer_goes_from_the_list_to_a_comparison_in_a_real_browser(server):
    from playwright.sync_api import expect, sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        # the list: runs and the study, filtered by analysis
        page.goto(server + "/")
        expect(page.locator("h1")).to_have_text("Runs and studies")
        expect(page.locator("#runs tbody tr")).to_have_count(3)
        expect(page.locator("#studies")).to_contain_text("press-support-influence")
        page.select_option("select[name=analysis]", "modal")
        page.click("button[type=submit]")
        expect(page.locator("#runs tbody tr")).to_have_count(1)
        page.goto(server + "/")
        # open a run: its summary with units, its curves drawn by Plotly, its model file
        page.locator("#runs a", has_text="1").first.click()
        expect(page.locator("h1")).to_contain_text("support of press A on its support")
        expect(page.locator("#summary")).to_contain_text("transmitted force range")
        expect(page.locator(".plot .main-svg").first).to_be_visible()
        expect(page.locator("pre")).to_contain_text("[excitation]")
        # open the study; pick one variant by clicking its point in the scatter plot
        page.goto(server + "/")
        page.locator("#studies a", has_text="press-support-influence").click()
        expect(page.locator("h1")).to_contain_text("press-support-influence")
        expect(page.locator("#variants tbody tr")).to_have_count(7)
        page.select_option("#xaxis", index=0)
        # parameters and outputs in the study file's units (tonf, mm), the unit in each title
        page.select_option("#yaxis", label="displacement_max_m [mm]")
        expect(page.locator("#variants thead")).to_contain_text("transmitted_force_range_N [tonf]")
        expect(page.locator("#variants thead")).to_contain_text("support.stiffness [N/m]")
        expect(page.locator("table.findings").first).to_contain_text("support.stiffness")  # the OAT table
        page.locator("#scatter").scroll_into_view_if_needed()
        expect(page.locator("#scatter .main-svg").first).to_be_attached()  # drawn as it comes near
        expect(page.locator("#scatter .xtitle")).to_have_text(re.compile("support.stiffness"))
        expect(page.locator("#scatter .ytitle")).to_have_text("displacement_max_m [mm]")
        expect(page.locator("#scatter-points")).to_be_hidden()  # a few variants: no choice to make
        x, y = page.evaluate(
            """() => {
              const gd = document.getElementById('scatter'), fl = gd._fullLayout, xs = gd.data[0].x;
              const i = xs.indexOf(Math.min(...xs));  // the softest support
              const box = gd.querySelector('.nsewdrag').getBoundingClientRect();
              return [box.left + fl.xaxis.l2p(xs[i]), box.top + fl.yaxis.l2p(gd.data[0].y[i])];
            }"""
        )
        page.mouse.click(x, y)
        expect(page.locator("#selected")).not_to_have_text("none")
        picked = page.locator("#selected").inner_text()
        # select several with the box tool: drag over the whole plot
        page.locator("#scatter").scroll_into_view_if_needed()
        box = page.locator("#scatter .nsewdrag").bounding_box()
        page.mouse.move(box["x"] + 2, box["y"] + 2)
        page.mouse.down()
        page.mouse.move(box["x"] + box["width"] - 2, box["y"] + box["height"] - 2, steps=8)
        page.mouse.up()
        expect(page.locator("#selected")).to_contain_text(",")
        assert len(page.locator("#selected").inner_text().split(",")) >= 4
        # compare them: scalars side by side with units, curves overlaid with zoom
        page.click("#compare")
        expect(page.locator("h1")).to_contain_text("variants side by side")
        expect(page.locator("#side-by-side")).to_contain_text("transmitted force range")
        expect(page.locator("#side-by-side")).to_contain_text("N/m")
        expect(page.locator(".plot .main-svg").first).to_be_visible()
        expect(page.locator(".modebar").first).to_be_attached()  # Plotly's zoom tools
        # one variant alone, from the click above
        page.goto(server + "/compare?variant=" + picked.split(",")[0].strip())
        expect(page.locator("#side-by-side thead th")).to_have_count(3)
        browser.close()


def test_a_study_page_reloads_while_the_study_adds_variants(server, database):
    from playwright.sync_api import expect, sync_playwright

    from mechdyn.store.store import ResultStore
    from mechdyn.studies.storage import StudyStore, variant_key

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
        page = browser.new_page()
        page.goto(server + "/")
        page.locator("#studies a", has_text="press-support-influence").click()
        expect(page.locator("#count")).to_contain_text("7 (0 failed)")
        with ResultStore(database) as store:  # another process adding a variant, as a running study does
            studies = StudyStore(store)
            st = studies.study("press-support-influence")
            row = {
                "key": variant_key([1.0, 2.0]),
                "position": 7,
                "parameters": {"support.stiffness": 3e8, "support.damping_ratio": 0.05},
                "given": {},
                "outputs": {},
                "status": "failed",
                "error": "added by the test",
                "model_sha256": st.model_sha256,
            }
            studies.add(st.id, [row])
        expect(page.locator("#count")).to_contain_text("8 (1 failed)")
        browser.close()


@pytest.mark.postgres
def test_the_dashboard_serves_a_postgresql_database_read_only(postgres_url):
    from mechdyn.dashboard.app import create_app

    assert main(["modal", str(EXAMPLES / "turret_indexing.toml"), "--db", postgres_url, "--json"]) == 0
    _write_refused(postgres_url, r"read-only transaction")
    with serving(create_app(postgres_url)) as address:
        status, body = _get(address + "/runs/1")
    assert status == 200 and "turret" in body.lower() and "frequencies" in body


def test_compare_overlays_runs_of_different_periods_and_sample_counts(tmp_path):
    """`/compare` answered HTTP 500 for two support models of different periods and for one slider-crank
    at 360 and at 180 angles (the curves were stacked as one array); each curve is now drawn on its own
    abscissa and the curves that differ most are chosen on the first run's grid."""
    from mechdyn.dashboard.app import create_app

    db = str(tmp_path / "r.db")
    for argv in (
        ["support", str(EXAMPLES / "press_on_support.toml"), "--cycles", "1"],
        ["support", str(EXAMPLES / "pump_set_unbalance.toml"), "--cycles", "1"],
        ["mechanism", str(EXAMPLES / "slider_crank.toml"), "--angles", "360"],
        ["mechanism", str(EXAMPLES / "slider_crank.toml"), "--angles", "180"],
    ):
        assert main([*argv, "--db", db]) == 0
    with serving(create_app(db)) as address:
        for a, b, lengths in ((1, 2, None), (3, 4, {360, 180})):
            status, body = _get(f"{address}/compare?run={a}&run={b}")
            assert status == 200, body[-2000:]
            plots = re.findall(r'Plotly\.newPlot\("plot1", (\[.*?\]), \{"', body, re.S)
            assert plots, "no curve overlaid"
            traces = json.loads(plots[0])
            assert [t["name"] for t in traces] == [f"run {a}", f"run {b}"]
            assert all(len(t["x"]) == len(t["y"]) for t in traces)
            if lengths:
                assert {len(t["x"]) for t in traces} == lengths


def test_the_run_list_filters_in_the_database_and_counts_every_match(tmp_path):
    """The list took the newest runs first and filtered them after: 120 matching runs older than 150
    others showed as "Runs (0)". The filter is now the query's, the count true, the list paged."""
    from mechdyn.dashboard.app import RUNS_PER_PAGE, create_app
    from mechdyn.store.store import ResultStore

    db = str(tmp_path / "r.db")
    store = ResultStore(db)
    try:
        for i in range(270):  # the 120 oldest are the turret's, the rest a press's
            name, path = ("turret", "turret_milling.toml") if i < 120 else ("press", "press.toml")
            store.record(
                analysis="modal" if i < 120 else "mechanism",
                model_name=f"{name} {i}",
                model_path=path,
                model_text="",
                model_sha256=f"{i:064x}",
                parameters={},
                scalars={},
            )
        assert store.count_runs(model="TURRET") == 120 and store.count_runs(analysis="mechanism") == 150
        assert [r.model_name for r in store.runs(model="turret", limit=2)] == ["turret 119", "turret 118"]
        assert store.count_runs(model="milling", analysis="modal") == 120
        assert store.count_runs(model="100%_") == 0  # wildcards are text
        today = datetime.now(UTC).date()
        assert store.count_runs(since=today, until=today) == 270
        assert store.count_runs(until=today - timedelta(days=1)) == 0
    finally:
        store.close()
    with serving(create_app(db)) as address:
        status, body = _get(address + "/?model=turret")
        assert status == 200 and "Runs (120)" in body
        assert f"Runs 1–{RUNS_PER_PAGE} of 120" in body and "page=2" in body
        status, body = _get(address + "/?model=turret&page=2")
        assert f"Runs {RUNS_PER_PAGE + 1}–120 of 120" in body and ">turret 0<" in body
        assert "Runs (270)" in _get(address + "/")[1]
