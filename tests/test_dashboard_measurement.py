"""A stored ``modes-from-test`` run on the dashboard: its run page shows the model against the
measurement as its report does (the FRF overlay of the measured FRFs, the model before and after
updating, drawn by the report's own code from the files the run names) and the modes' pairing from
the stored outputs; a data file no longer where the run found it is said in words.

The run is made by the command line on a copy of ``examples/measured`` (the tap test of
``machine.toml``), as a user makes it.
"""

from __future__ import annotations

import html
import re
import urllib.error
import urllib.request
from html.parser import HTMLParser

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES, open_in_chromium, serving
from mechdyn.cells import table_cell
from mechdyn.cli.main import main

pytest.importorskip("pyuff")
pytestmark = pytest.mark.usefixtures("patient_browser_checks")

FILES = ("tap_test.toml", "tap_test.uff", "machine.toml")
PNG = b"\x89PNG\r\n\x1a\n"


def _copy(folder, names=FILES):
    """The example's files in ``folder``; the measurement file without its ``[predict]`` table (what
    the page shows does not depend on it, and it is most of the run's time)."""
    folder.mkdir()
    for name in names:
        text = (EXAMPLES / "measured" / name).read_bytes()
        if name == "tap_test.toml":
            text = text.split(b"\n[predict]")[0] + b"\n"
        (folder / name).write_bytes(text)
    return folder / "tap_test.toml"


def _record_moved(db, run, model_path, **changes):
    """Store run ``run`` again as if its measurement file were at ``model_path`` (as a run made
    elsewhere, its files since moved), with ``changes`` to its fields; returns the new run's id."""
    from mechdyn.store.store import ResultStore

    fields = {
        "analysis": run.analysis,
        "model_name": run.model_name,
        "model_path": str(model_path),
        "model_text": run.model_text,
        "model_sha256": run.model_sha256,
        "parameters": run.parameters,
        "scalars": run.scalars,
        "arrays": run.arrays,
    } | changes
    with ResultStore(db) as store:
        return store.record(**fields)


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    """A database with the tap test run by the command line (its updated model written, for
    reference), and the same run stored as if made where its files are no longer found."""
    from mechdyn.store.store import ResultStore

    d = tmp_path_factory.mktemp("dashboard_measurement")
    test = _copy(d / "kept")
    db, written = str(d / "results.db"), d / "machine_updated.toml"
    argv = ["modes-from-test", str(test), "--bootstrap", "0", "--starts", "0", "--db", db]
    assert main([*argv, "--write-updated", str(written)]) == 0
    with ResultStore(db, read_only=True) as store:
        run = store.get(1)
    # the measurement and model files moved away from their data file; and from their tested model
    no_data = _copy(d / "no_data", ("tap_test.toml", "machine.toml"))
    no_model = _copy(d / "no_model", ("tap_test.toml", "tap_test.uff"))
    ids = {
        "kept": 1,
        "no_data": _record_moved(db, run, no_data),
        "no_model": _record_moved(db, run, no_model),
        # a run that updated nothing (--no-update): no updated values, no "after" columns
        "not_updated": _record_moved(
            db,
            run,
            test,
            scalars={k: v for k, v in run.scalars.items() if not k.startswith("updated")},
            arrays={k: v for k, v in run.arrays.items() if not k.startswith("updated")},
        ),
    }
    return {"db": db, "run": run, "ids": ids, "test": test, "written": written}


@pytest.fixture(scope="module")
def server(made):
    from mechdyn.dashboard.app import create_app

    with serving(create_app(made["db"])) as address:
        yield address


def _get(url: str) -> tuple[int, bytes]:
    try:
        with urllib.request.urlopen(url) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        with e:
            return e.code, e.read()


class _Page(HTMLParser):
    """The overlay's <img> attributes and the pairing table's header and rows of a run page."""

    def __init__(self) -> None:
        super().__init__()
        self.images: list[dict[str, str | None]] = []
        self.headings: list[str] = []
        self.rows: list[list[str]] = []
        self._in_table = False
        self._cell: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img" and "overlay" in (a.get("class") or ""):
            self.images.append(a)
        if tag == "table" and a.get("id") == "pairing":
            self._in_table = True
        if self._in_table and tag == "tr":
            self.rows.append([])
        if self._in_table and tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag == "table":
            self._in_table = False
        if self._in_table and tag in ("td", "th") and self._cell is not None:
            text = "".join(self._cell)
            (self.headings if tag == "th" else self.rows[-1]).append(text)
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def _page(server, run_id) -> tuple[str, _Page]:
    status, body = _get(f"{server}/runs/{run_id}")
    assert status == 200
    text = body.decode()
    parsed = _Page()
    parsed.feed(text)
    return text, parsed


def test_a_stored_test_page_shows_the_overlay_and_the_paired_modes(server, made):
    text, page = _page(server, made["ids"]["kept"])
    assert "Model against the measurement" in text
    # the overlay: measured, the model before and after updating, in its caption
    (img,) = page.images
    assert img["alt"] == "FRF overlay: measured, model before updating, model after updating"
    assert f'<figcaption class="note">{img["alt"]}</figcaption>' in text
    status, png = _get(server + html.unescape(img["src"]))
    assert status == 200 and png.startswith(PNG)
    # the pairing: the paired frequencies, errors and MAC the run's summary holds, as the page
    # writes a number (one row per pair, in the summary's order)
    s = made["run"].scalars
    rows = [r for r in page.rows if r]
    assert len(rows) == s["paired_modes"] == 6
    column = {h: i for i, h in enumerate(page.headings)}
    for heading, key in [
        ("model before (Hz)", "model_frequencies_hz"),
        ("error before (%)", "frequency_error_percent"),
        ("MAC before", "mac"),
        ("model after (Hz)", "updated_model_frequencies_hz"),
        ("error after (%)", "updated_frequency_error_percent"),
        ("MAC after", "updated_mac"),
        ("damping error before (%)", "damping_error_percent"),
    ]:
        assert [r[column[heading]] for r in rows] == [table_cell(v).text for v in s[key]], heading
    # the measured frequencies of the pairs, from the stored pairs' table, are the identified ones
    measured = [float(r[column["measured (Hz)"]]) for r in rows]
    modes = [int(r[column["measured mode"]]) for r in rows]
    np.testing.assert_allclose(measured, [s["frequencies_hz"][m - 1] for m in modes], rtol=1e-4)


def test_the_page_gives_the_overlay_its_size_once_drawn_and_keeps_it(server, made):
    _text, page = _page(server, made["ids"]["kept"])
    status, png = _get(server + html.unescape(page.images[0]["src"]))
    assert status == 200
    _text, again = _page(server, made["ids"]["kept"])
    width, height = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
    assert (again.images[0]["width"], again.images[0]["height"]) == (str(width), str(height))


def test_the_overlay_is_recomputed_from_what_the_run_recorded(made):
    """The dashboard's FRFs, from the stored measurement file, the files it names and the stored
    updated values, are those of the measurement and of the model files: the tested one and the
    updated one the analysis itself wrote."""
    from mechdyn.dashboard.measured import overlay_frfs
    from mechdyn.measurement.correlation import model_frf

    o = overlay_frfs(made["run"])
    spec = mechdyn.load(made["test"]).model
    np.testing.assert_array_equal(o.measured.H, spec.measured.H)
    tested = mechdyn.load(made["test"].parent / "machine.toml").model
    np.testing.assert_allclose(o.model.H, model_frf(tested, spec.measured, spec.mapping).H, rtol=1e-12)
    updated = mechdyn.load(made["written"]).model
    reference = model_frf(updated, spec.measured, spec.mapping).H
    np.testing.assert_allclose(o.updated.H, reference, rtol=1e-9)
    assert not np.allclose(o.updated.H, o.model.H, rtol=1e-3)  # the update moved the model
    assert o.band_hz == (made["run"].scalars["band_min_hz"], made["run"].scalars["band_max_hz"])


def test_the_overlay_is_drawn_by_the_reports_own_code(made, monkeypatch):
    """One drawing function for the report's picture and the dashboard's (nothing copied)."""
    import mechdyn.measurement.plots as plots
    from mechdyn.dashboard.measured import overlay_figure

    calls = []
    draw = plots.plot_frf_overlay
    monkeypatch.setattr(plots, "plot_frf_overlay", lambda *a, **k: calls.append(a) or draw(*a, **k))
    figure = overlay_figure(made["run"])
    assert len(calls) == 1 and len(calls[0]) == 3 and calls[0][2] is not None
    from mechdyn.measurement import TestCorrelation

    # the report's picture (TestCorrelation.plots()["frf_overlay.png"]) is drawn by the same function
    assert "plot_frf_overlay" in TestCorrelation.plot_frf.__code__.co_names
    assert figure.caption.startswith("FRF overlay: measured")


def test_a_missing_data_file_gives_a_note_not_an_error(server, made):
    run_id = made["ids"]["no_data"]
    text, page = _page(server, run_id)
    assert page.images == [] and "Traceback" not in text
    note = html.unescape(re.search(r'<p class="note" id="overlay-note">(.*?)</p>', text, re.S)[1])
    assert "The FRF overlay is not drawn: the measured data file 'tap_test.uff' is not found" in note
    assert "no_data" in note and "put the data file back" in note
    assert [r for r in page.rows if r]  # the pairing, from the stored outputs, is still there
    status, body = _get(f"{server}/runs/{run_id}/overlay.png")
    assert status == 404 and b"tap_test.uff' is not found" in body


def test_a_run_that_updated_nothing_overlays_the_model_alone(server, made):
    _text, page = _page(server, made["ids"]["not_updated"])
    assert page.images[0]["alt"] == "FRF overlay: measured, model (the run updated nothing)"
    assert "model before (Hz)" in page.headings and "model after (Hz)" not in page.headings


def test_another_analysis_has_no_measurement_section_nor_overlay(tmp_path):
    from mechdyn.dashboard.app import create_app

    db = str(tmp_path / "r.db")
    assert main(["modal", str(EXAMPLES / "turret_indexing.toml"), "--db", db]) == 0
    with serving(create_app(db)) as address:
        status, body = _get(address + "/runs/1")
        assert status == 200 and b"Model against the measurement" not in body
        assert _get(address + "/runs/1/overlay.png")[0] == 404
        assert _get(address + "/runs/2/overlay.png")[0] == 404


def test_the_overlays_kept_are_bounded_and_follow_their_files(made, tmp_path):
    """At most the limit's overlays are kept; a data file that changes is drawn again."""
    import os

    from mechdyn.dashboard.measured import files_key
    from mechdyn.dashboard.state import CacheLimits, DashboardState

    state = DashboardState(made["db"], limits=CacheLimits(tests=1))
    try:
        run = state.store.get(made["ids"]["kept"])
        other = state.store.get(made["ids"]["not_updated"])
        first, why = state.overlay(run)
        assert why is None and state.overlay(run)[0] is first  # kept
        state.overlay(other)
        assert len(state.tests) == 1 and state.kept_overlay(run, files_key(run)) is None
        assert state.tests.nbytes == len(state.overlay(other)[0].data)
        data = made["test"].parent / "tap_test.uff"
        key = files_key(run)
        st = os.stat(data)
        os.utime(data, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000_000))
        assert files_key(run) != key  # another state of the files: drawn again, not the kept one
    finally:
        state.close()
        state.store.close()


@pytest.mark.slow  # the overlay and modes by HTTP by default (above); in Chromium in CI's heavy step
def test_the_overlay_is_visible_in_a_real_browser(server, made):
    from playwright.sync_api import expect, sync_playwright

    with sync_playwright() as p:
        browser, page, errors = open_in_chromium(p, f"{server}/runs/{made['ids']['kept']}")
        img = page.locator("img.overlay")
        expect(img).to_be_visible()
        expect(img).to_have_attribute("alt", re.compile("measured, model before updating, model after"))
        page.wait_for_function(
            "() => { const i = document.querySelector('img.overlay'); "
            "return i.complete && i.naturalWidth > 0; }"
        )
        assert img.bounding_box()["width"] > 400
        expect(page.locator("#pairing tbody tr")).to_have_count(6)
        # a picture that cannot be drawn (its tested model moved away): the reason, in its place
        page.goto(f"{server}/runs/{made['ids']['no_model']}")
        expect(page.locator("#overlay-note")).to_contain_text("the files the run names do not make its test")
        expect(page.locator("figure:has(img.overlay)")).to_be_hidden()
        assert errors == []
        browser.close()
