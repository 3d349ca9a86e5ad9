"""A study's page at size: its table sorted and paged by the database, its views (history with the
best so far, importances with their method, Pareto front, slice, contour, parallel coordinates) from
every variant or an evenly spread sample, checked against the same numbers worked out here from
every stored variant, and drawn in Chromium."""

from __future__ import annotations

import json
import re
import struct
import urllib.request

import numpy as np
import pytest

from conftest import EXAMPLES, open_in_chromium, serving
from mechdyn.cli.main import main
from mechdyn.dashboard.views import best_so_far, pareto_mask, thin

STUDY = f"""
[study]
name = "support-lhs"
kind = "lhs"
model = "{(EXAMPLES / "press_on_support.toml").as_posix()}"
analysis = "support"
samples = 250
seed = 3

[[parameters]]
path = "support.stiffness"
range = "±30 %"

[[parameters]]
path = "support.damping_ratio"
range = "±30 %"

[[outputs]]
output = "displacement_max_m"
unit = "mm"

[[outputs]]
output = "transmitted_force_range_N"
unit = "tonf"
"""


pytestmark = pytest.mark.usefixtures("patient_browser_checks")


@pytest.fixture(scope="module")
def database(tmp_path_factory):
    d = tmp_path_factory.mktemp("study_views")
    (d / "lhs.toml").write_text(STUDY)
    db = str(d / "results.db")
    assert main(["study", str(d / "lhs.toml"), "--db", db]) == 0
    for angles in ("36", "72"):  # two runs of a four-bar: nested values (a force per joint) to compare
        assert main(["mechanism", str(EXAMPLES / "fourbar.toml"), "--angles", angles, "--db", db]) == 0
    return db


@pytest.fixture(scope="module")
def server(database):
    from mechdyn.dashboard.app import create_app

    with serving(create_app(database)) as address:
        yield address


@pytest.fixture(scope="module")
def stored(database):
    """Every variant as stored, and the study's columns as shown."""
    from mechdyn.reports.columns import stored_columns
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(database, read_only=True) as store:
        variants = StudyStore(store).variants("support-lhs")
        columns = stored_columns(store, "support-lhs", variants[:10])
    return variants, columns


def _json(url: str):
    with urllib.request.urlopen(url) as r:
        return json.loads(r.read())


def test_best_so_far_keeps_the_best_of_what_came_before_either_way():
    v = np.array([np.nan, 5.0, 7.0, 3.0, np.nan, 4.0, 1.0])
    assert np.array_equal(best_so_far(v, "minimize"), [np.nan, 5, 5, 3, 3, 3, 1], equal_nan=True)
    assert np.array_equal(best_so_far(v, "maximize"), [np.nan, 5, 7, 7, 7, 7, 7], equal_nan=True)
    assert thin(10, 20).tolist() == list(range(10))
    kept = thin(1000, 7)
    assert kept[0] == 0 and kept[-1] == 999 and len(kept) == 7


@pytest.mark.parametrize(
    "senses", [("minimize", "minimize"), ("minimize", "maximize"), ("maximize", "maximize")]
)
def test_the_pareto_front_is_the_set_no_point_dominates(senses):
    rng = np.random.default_rng(1)
    x, y = rng.random(400), rng.random(400)
    x[5], y[7] = np.nan, np.nan
    sign = np.array([-1.0 if s == "maximize" else 1.0 for s in senses])
    a, b = x * sign[0], y * sign[1]
    brute = np.array(
        [
            np.isfinite(a[i])
            and np.isfinite(b[i])
            and not np.any((a <= a[i]) & (b <= b[i]) & ((a < a[i]) | (b < b[i])))
            for i in range(a.size)
        ]
    )
    assert np.array_equal(pareto_mask(x, y, senses), brute) and brute.sum() >= 3


def test_the_table_is_sorted_and_paged_by_the_database_over_the_whole_study(server, stored):
    variants, columns = stored
    force = next(i for i, c in enumerate(columns) if c.key == "transmitted_force_range_N")
    expected = sorted(variants, key=lambda v: (-v.outputs["transmitted_force_range_N"], v.id))
    page2 = _json(server + f"/api/studies/1/variants?sort={force}&order=desc&page=2")
    assert page2["variants"] == 251  # the base design and 250 samples and len(page2["rows"]) == 100
    assert [r["id"] for r in page2["rows"]] == [v.id for v in expected[100:200]]
    # each value in the study file's unit, as the page writes it
    shown = columns[force].of(expected[100])
    assert page2["rows"][0]["cells"][force]["text"] == f"{shown:.5g}" or float(
        page2["rows"][0]["cells"][force]["text"]
    ) == pytest.approx(shown, rel=1e-4)
    last = _json(server + "/api/studies/1/variants?sort=0&page=3")
    ids = [v.id for v in sorted(variants, key=lambda v: (v.parameters["support.stiffness"], v.id))][200:]
    assert [r["id"] for r in last["rows"]] == ids
    # a column no study has, or a word, sorts by id
    assert [r["id"] for r in _json(server + "/api/studies/1/variants?sort=99")["rows"]][:3] == [1, 2, 3]


def test_the_views_read_every_variant_or_an_even_sample_in_the_study_file_s_units(server, stored, database):
    variants, columns = stored
    from mechdyn.dashboard.study_data import StudyData
    from mechdyn.store import ResultStore

    force = next(i for i, c in enumerate(columns) if c.key == "transmitted_force_range_N")
    tonf = np.array([columns[force].of(v) for v in variants])
    # the points: every variant, in tonf
    points = _json(server + "/api/studies/1/points")
    assert points["ids"] == [v.id for v in variants] and not points["sampled"]
    assert np.allclose(points["values"][force], tonf, rtol=1e-6)
    # an evenly spread sample of a larger study
    with ResultStore(database, read_only=True) as store:
        sample = StudyData(store.engine, 1, columns).numbers([force], sample=60)
    assert sample["sampled"] and 40 <= len(sample["ids"]) <= 60 and sample["total"] == 251
    by_id = dict(zip([v.id for v in variants], tonf, strict=True))
    assert np.allclose(sample["values"][0], [by_id[i] for i in sample["ids"]])
    # the history: the best so far over every variant, exact
    h = _json(server + f"/api/studies/1/history?column={force}")
    assert h["best"] == pytest.approx(tonf.min()) and h["best_id"] == variants[int(np.argmin(tonf))].id
    assert h["best_y"][-1] == pytest.approx(tonf.min()) and h["label"] == "transmitted_force_range_N [tonf]"
    # the Pareto front of displacement and force, both smaller
    disp = next(i for i, c in enumerate(columns) if c.key == "displacement_max_m")
    front = _json(server + f"/api/studies/1/pareto?x={disp}&y={force}")
    mm = np.array([columns[disp].of(v) for v in variants])
    mask = pareto_mask(mm, tonf)
    assert sorted(front["ids"]) == sorted(v.id for v, m in zip(variants, mask, strict=True) if m)
    # the importances: their method named, summing to one
    imp = _json(server + f"/api/studies/1/importances?column={force}")
    assert "PED-ANOVA" in imp["method"] and sum(imp["values"].values()) == pytest.approx(1.0)
    assert set(imp["values"]) <= {"support.stiffness", "support.damping_ratio"}


@pytest.mark.parametrize(
    "path",
    [
        "/api/studies/9/points",
        "/api/studies/1/history?column=99",
        "/api/studies/1/pareto?x=0&y=99",
        "/api/studies/1/importances?column=0",  # a parameter is not an output
        "/studies/9/findings",
    ],
)
def test_views_of_what_the_study_does_not_have_are_404(server, path):
    import urllib.error

    with pytest.raises(urllib.error.HTTPError) as e:
        urllib.request.urlopen(server + path)
    e.value.close()
    assert e.value.code == 404


def test_the_findings_carry_their_pictures(server):
    import time

    for _ in range(600):  # the findings are worked out in the background; ask until they are ready
        with urllib.request.urlopen(server + "/studies/1/findings") as r:
            if r.status == 200:
                html = r.read().decode()
                break
        time.sleep(0.1)
    else:
        pytest.fail("the findings never came")
    # the pictures are links (a page carrying them inline is megabytes of text read before anything
    # is drawn), loaded as they come near the window, each with its size so the page does not move
    images = re.findall(r'<img [^>]*src="([^"]+)" loading="lazy"[^>]* width="(\d+)" height="(\d+)"', html)
    assert images and "base64" not in html
    for url, width, height in images:
        with urllib.request.urlopen(server + url.replace("&amp;", "&")) as r:
            png = r.read()
            assert r.headers["content-type"] == "image/png"
        assert png[:8] == b"\x89PNG\r\n\x1a\n"
        assert struct.unpack(">II", png[16:24]) == (int(width), int(height))
    state = images[0][0].split("?")[1]  # the number of variants whose findings these are
    for wrong in (f"/studies/1/findings/{len(images)}.png?{state}", "/studies/1/findings/0.png?variants=1"):
        with pytest.raises(urllib.error.HTTPError) as missing:  # no such picture, no such state
            urllib.request.urlopen(server + wrong)
        missing.value.close()
        assert missing.value.code == 404


def test_every_view_of_a_study_is_drawn_in_a_real_browser(server):
    from playwright.sync_api import expect, sync_playwright

    with sync_playwright() as p:
        browser, page, errors = open_in_chromium(p, server + "/studies/1")
        expect(page.locator("h1")).to_contain_text("support-lhs")
        expect(page.locator("#findings")).to_have_attribute("data-ready", "yes")
        expect(page.locator("#findings img").first).to_be_visible()
        # the history, with the best so far (each view is drawn as it comes near the window)
        page.locator("#history").scroll_into_view_if_needed()
        expect(page.locator("#history .main-svg").first).to_be_attached()
        assert page.evaluate("document.getElementById('history').data[1].name") == "best so far"
        expect(page.locator("#history-best")).to_contain_text("best (smallest)")
        # the importances, their method named
        page.locator("#importances").scroll_into_view_if_needed()
        expect(page.locator("#importance-method")).to_contain_text("PED-ANOVA")
        expect(page.locator("#importances .main-svg").first).to_be_attached()
        # the scatter, then its Pareto front
        page.locator("#scatter").scroll_into_view_if_needed()
        expect(page.locator("#scatter .main-svg").first).to_be_attached()
        page.select_option("#pareto", "minimize,minimize")
        expect(page.locator("#scatter .legend")).to_contain_text("Pareto front")
        # slice, contour and parallel coordinates
        for view in ("slice", "contour", "parcoords"):
            page.locator("#" + view).scroll_into_view_if_needed()
            expect(page.locator(f"#{view} .main-svg").first).to_be_attached()
        assert page.evaluate("document.getElementById('contour').data[0].type") == "histogram2dcontour"
        # the table: 100 rows a page, sorted by the database when a title is clicked
        page.locator("#variants").scroll_into_view_if_needed()
        expect(page.locator("#rows")).to_have_text("variants 1–100 of 251")
        page.click("#next")
        expect(page.locator("#rows")).to_have_text("variants 101–200 of 251")
        header = page.locator("#variants th", has_text="transmitted_force_range_N")
        header.click()
        expect(page.locator("#rows")).to_have_text("variants 1–100 of 251")
        expect(header).to_have_attribute("data-order", "asc")
        header.click()
        expect(header).to_have_attribute("data-order", "desc")
        first = page.locator("#variants tbody tr").first.locator("td").nth(5)
        expect(first).not_to_have_text("")
        top = float(first.inner_text())
        cells = page.locator("#variants tbody tr td:nth-child(6)").all_inner_texts()
        assert top == max(float(c) for c in cells)
        assert not errors, errors
        browser.close()


@pytest.mark.postgres
def test_a_study_is_sorted_paged_and_sampled_by_postgresql_as_by_sqlite(postgres_url, database, tmp_path):
    """The JSON values are taken out by the database itself: PostgreSQL's ``->>`` sorts as SQLite's
    ``json_extract`` does."""
    from mechdyn.dashboard.study_data import StudyData
    from mechdyn.reports.columns import stored_columns
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    (tmp_path / "lhs.toml").write_text(STUDY.replace("samples = 250", "samples = 40"))
    assert main(["study", str(tmp_path / "lhs.toml"), "--db", postgres_url]) == 0
    with ResultStore(postgres_url, read_only=True) as store:
        st = StudyStore(store).study("support-lhs")
        variants = StudyStore(store).variants("support-lhs")
        columns = stored_columns(store, st.name, variants[:10])
        data = StudyData(store.engine, st.id, columns)
        force = next(i for i, c in enumerate(columns) if c.key == "transmitted_force_range_N")
        rows = data.page(sort=str(force), descending=True, offset=5, limit=10)
        sample = data.numbers([force], sample=10)
    expected = sorted(variants, key=lambda v: (-v.outputs["transmitted_force_range_N"], v.id))[5:15]
    assert [r["id"] for r in rows] == [v.id for v in expected]
    assert sample["sampled"] and len(sample["ids"]) <= 10 and sample["total"] == 41


def _text(url: str) -> str:
    with urllib.request.urlopen(url) as r:
        return r.read().decode()


def test_nested_values_are_compared_as_tables_with_their_units(server):
    """A nested value (a peak force per joint) is a table of its own, titled in words, one row per item
    in one unit; lists of names read as names, vectors in one readable unit; no JSON anywhere."""
    html = _text(server + "/compare?run=1&run=2")
    rows = _compare_rows(html)
    nested = [(label, unit) for label, unit, _ in rows if label.startswith("joint force peak · ")]
    assert len(nested) >= 4 and len({unit for _, unit in nested}) == 1 and nested[0][1] in ("N", "kN")
    assert "<h3>Joint force peak</h3>" in html
    tables = re.findall(r'<table class="side-by-side".*?</table>', html, re.S)
    assert len(tables) >= 2 and not any("{&#34;" in t or "[&#34;" in t for t in tables)
    assert not any("_" in label for label, _, _ in rows), rows  # every key in words


def test_a_vector_is_compared_in_one_readable_unit():
    from mechdyn.dashboard.app import _compare_row

    label, unit, cells = _compare_row("floor_force_range_N", [[22284.0, 0.0, 843206.0], None], {}, False)
    assert (label, unit) == ("floor force range", "kN") and cells[0].text == "22.284, 0, 843.21"
    assert cells[1].text == "—"
    assert _compare_row("frame_velocity_rms_m_per_s", [1.6737e-4], {}, False)[1] in ("mm/s",)


def test_runs_and_variants_compared_together_keep_each_row_in_one_unit(server, stored):
    """A study's output is shown in its study file's unit beside runs too (it was SI with a run), and a
    run's value in the unit a designer reads it in, the same for every column of its row."""
    variants, columns = stored
    v = next(v for v in variants if v.status == "ok")
    html = _text(server + f"/compare?run=1&run=2&variant={v.id}")
    rows = {label: (unit, cells) for label, unit, cells in _compare_rows(html)}
    force = next(c for c in columns if c.key == "transmitted_force_range_N")
    unit, cells = rows["transmitted force range"]
    assert unit == force.unit == "tonf"
    from mechdyn.numbers import number_text

    assert cells[2] == number_text(force.of(v))
    unit, cells = rows["driving torque rms"]  # the four-bar's runs: one readable unit for both
    assert unit in ("N·m", "kN·m") and cells[0] and cells[1] and cells[2] == "—"  # not a variant's output


def _compare_rows(html: str) -> list[tuple[str, str, list[str]]]:
    """(label, unit, cells) of every row of the compare page's tables, a nested table's rows labelled
    "its title · item" as they read."""
    out = []
    for title, body in re.findall(
        r'(?:<h3>([^<]*)</h3>\s*)?<div class="tablewrap"><table class="side-by-side".*?>(.*?)</table>',
        html,
        re.S,
    ):
        prefix = title[:1].lower() + title[1:] + " · " if title else ""
        for row in re.findall(r"<tr>(.*?)</tr>", body, re.S):
            cells = [re.sub(r"<[^>]+>", "", c).strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)]
            if len(cells) >= 2:
                out.append((prefix + cells[0], cells[1], cells[2:]))
    return out


def test_a_variant_whose_curves_were_not_kept_has_them_recomputed_and_says_so(server, stored, database):
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    variants, _ = stored
    with ResultStore(database, read_only=True) as store:
        kept = StudyStore(store).with_curves(1)
    without = next(v.id for v in variants if v.id not in kept)
    html = _text(server + f"/compare?variant={without}")
    assert f"variant {without}: curves not kept; recomputed from its stored inputs" in html
    assert 'class="plot"' in html and "Plotly.newPlot" in html


def test_the_lists_give_a_headline_per_run_and_per_study(server, stored):
    variants, columns = stored
    html = _text(server + "/")
    force = next(c for c in columns if c.key == "transmitted_force_range_N")
    tonf = [force.of(v) for v in variants]
    from mechdyn.numbers import number_text

    assert f"transmitted_force_range_N {number_text(min(tonf))} to {number_text(max(tonf))} tonf" in html
    cells = re.findall(r'<td class="headline">([^<]*)</td>', html)
    assert len(cells) == 3 and all(cells), cells  # the study and the two runs


@pytest.fixture(scope="module")
def large(tmp_path_factory):
    """A study of 10⁵ stored variants: a real study's definition (ten samples run), then 10⁵ designs
    within its ranges stored as a running study stores them, their outputs a smooth function of the
    parameters (what is measured here is the dashboard, not the analysis)."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore, variant_key

    d = tmp_path_factory.mktemp("large")
    (d / "lhs.toml").write_text(STUDY.replace("samples = 250", "samples = 10"))
    db = str(d / "results.db")
    assert main(["study", str(d / "lhs.toml"), "--db", db]) == 0
    rng = np.random.default_rng(5)
    n = 100_000
    k = 4.5e8 * rng.uniform(0.7, 1.3, n)
    zeta = 0.05 * rng.uniform(0.7, 1.3, n)
    with ResultStore(db) as store:
        studies = StudyStore(store)
        st = studies.study("support-lhs")
        start = studies.next_position(st.id)
        rows = [
            {
                "key": variant_key([k[i], zeta[i]]),
                "position": start + i,
                "parameters": {"support.stiffness": k[i], "support.damping_ratio": zeta[i]},
                "outputs": {
                    "displacement_max_m": 5.5e5 / k[i] * (1 + zeta[i]),
                    "transmitted_force_range_N": 8.4e5 + 1e4 * zeta[i] + k[i] * 1e-4,
                },
                "status": "ok",
                "model_sha256": st.model_sha256,
            }
            for i in range(n)
        ]
        for i in range(0, n, 20_000):
            studies.add(st.id, rows[i : i + 20_000])
    return db


@pytest.mark.slow  # about a minute: 10⁵ variants stored first (python benchmarks/dashboard.py times it)
def test_a_study_of_a_hundred_thousand_variants_is_shown_in_a_real_browser(large):
    from playwright.sync_api import expect, sync_playwright

    from mechdyn.dashboard.app import create_app

    with serving(create_app(large)) as address, sync_playwright() as p:
        browser, page, errors = open_in_chromium(p, address + "/studies/1")
        expect(page.locator("#count")).to_have_text("100011 (0 failed)")
        page.locator("#scatter").scroll_into_view_if_needed()
        expect(page.locator("#scatter")).to_have_attribute("data-drawn", "yes")
        expect(page.locator("#sample-note")).to_contain_text("of the 100011 variants that succeeded")
        drawn = page.evaluate("document.getElementById('scatter').data[0].x.length")
        assert 1_000 <= drawn <= 3_000  # by default an evenly spread part of the sample, in SVG
        page.select_option("#scatter-points", "all")  # the whole sample, in WebGL
        expect(page.locator("#scatter .gl-canvas").first).to_be_attached()
        drawn = page.evaluate("document.getElementById('scatter').data[0].x.length")
        assert 10_000 <= drawn <= 20_000
        page.locator("#history").scroll_into_view_if_needed()
        expect(page.locator("#history-best")).to_contain_text("best (smallest)")
        page.locator("#variants").scroll_into_view_if_needed()
        expect(page.locator("#rows")).to_have_text("variants 1–100 of 100011")
        page.locator("#variants th", has_text="displacement_max_m").click()
        expect(page.locator("#variants th", has_text="displacement_max_m")).to_have_attribute(
            "data-order", "asc"
        )
        cells = page.locator("#variants tbody tr td:nth-child(5)").all_inner_texts()
        values = [float(c) for c in cells]
        assert values == sorted(values)
        assert not errors, errors
        browser.close()
