"""A large study's table paged to its end, sorted by every kind of column either way, against the
database (SQLite and PostgreSQL), before and after its values are kept in memory and as the study
grows; and its scatter drawn from an evenly spread part of the page's sample, then every point of it in
WebGL, still picking variants to compare."""

from __future__ import annotations

import json
import math
import urllib.request

import numpy as np
import pytest

from conftest import open_in_chromium, serving
from mechdyn.cli.main import main
from test_dashboard_study_views import STUDY as SUPPORT_STUDY

STUDY = SUPPORT_STUDY.replace("samples = 250", "samples = 4")  # grown by _add below

pytestmark = pytest.mark.usefixtures("patient_browser_checks")


def _add(url: str, n: int, seed: int) -> None:
    """Store ``n`` more variants as a running study does: every 7th failed (no outputs), the damping
    ratio on a few levels (ties, sorted by id)."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore, variant_key

    rng = np.random.default_rng(seed)
    with ResultStore(url) as store:
        studies = StudyStore(store)
        st = studies.study("support-lhs")
        start = studies.next_position(st.id)
        rows = []
        for i in range(n):
            k, zeta = 4.5e8 * rng.uniform(0.7, 1.3), 0.05 * rng.choice([0.8, 1.0, 1.2])
            failed = (start + i) % 7 == 0
            outputs = {
                "displacement_max_m": 5.5e5 / k * (1 + zeta),
                "transmitted_force_range_N": 8.4e5 + k * 1e-4,
            }
            rows.append(
                {
                    "key": variant_key([k, zeta, seed]),
                    "position": start + i,
                    "parameters": {"support.stiffness": k, "support.damping_ratio": zeta},
                    "outputs": {} if failed else outputs,
                    "status": "failed" if failed else "ok",
                    "error": "diverged" if failed else None,
                    "model_sha256": st.model_sha256,
                }
            )
        studies.add(st.id, rows)


def _json(url: str):
    with urllib.request.urlopen(url) as r:
        return json.loads(r.read())


def _stored(url: str) -> list:
    """Every stored variant of the study, read once for a check of every sort."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(url, read_only=True) as store:
        return StudyStore(store).variants("support-lhs")


def _expected(variants: list, column: str | None, descending: bool) -> list[int]:
    """The study's variant ids sorted as the table sorts them, worked out here from every stored
    variant: by the column (missing last either way), ties by id."""

    def value(v):
        if column is None:
            return v.id
        if column == "status":
            return v.status
        x = {**v.parameters, **v.outputs}.get(column)
        return None if x is None or (isinstance(x, float) and math.isnan(x)) else x

    have = [v for v in variants if value(v) is not None]
    missing = [v.id for v in variants if value(v) is None]
    ordered = sorted(have, key=lambda v: v.id)
    ordered.sort(key=value, reverse=descending)  # stable: ties stay by id
    return [v.id for v in ordered] + sorted(missing)


def _check_every_sort(address: str, url: str, n: int, failed: int) -> None:
    from mechdyn.dashboard.study_data import PAGE_SIZE

    last = -(-n // PAGE_SIZE)
    columns = {"id": None, "status": "status", "1": "support.damping_ratio", "3": "transmitted_force_range_N"}
    variants = _stored(url)
    for sort, column in columns.items():
        for order in ("asc", "desc"):
            expected = _expected(variants, column, order == "desc")
            for number in (1, last // 2, last, last + 1):
                d = _json(f"{address}/api/studies/1/variants?sort={sort}&order={order}&page={number}")
                assert (d["variants"], d["failed"]) == (n, failed)
                rows = expected[(number - 1) * PAGE_SIZE : number * PAGE_SIZE]
                assert [r["id"] for r in d["rows"]] == rows, (sort, order, number)


@pytest.mark.parametrize(  # PostgreSQL's order in CI's heavy step (the store orders on it by default)
    "store_url", ["sqlite", pytest.param("postgresql", marks=pytest.mark.slow)], indirect=True
)
def test_every_page_of_the_table_is_sorted_by_any_column_as_the_database_holds_it(store_url, tmp_path):
    from mechdyn.dashboard.app import create_app

    (tmp_path / "lhs.toml").write_text(STUDY)
    assert main(["study", str(tmp_path / "lhs.toml"), "--db", store_url]) == 0
    _add(store_url, 1_230, seed=1)
    n, failed = _counts(store_url)
    app = create_app(store_url)
    with serving(app) as address:
        # before the study's values are kept: sorted by the database
        _check_every_sort(address, store_url, n, failed)
        # kept in memory (as the history reads them): sorted there, the same pages
        _json(address + "/api/studies/1/history")
        _check_every_sort(address, store_url, n, failed)
        # the study grows: its counts, its last pages, and its kept values follow
        _add(store_url, 321, seed=2)
        assert _counts(store_url) == (n + 321, failed + sum((n + i) % 7 == 0 for i in range(321)))
        n, failed = _counts(store_url)
        _check_every_sort(address, store_url, n, failed)
        _json(address + "/api/studies/1/history")
        _check_every_sort(address, store_url, n, failed)
        points = _json(address + "/api/studies/1/points")
        assert points["total"] == n - failed and len(points["ids"]) == n - failed


def _counts(url: str) -> tuple[int, int]:
    """The study's variants and how many of them failed, as stored."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(url, read_only=True) as store:
        variants = StudyStore(store).variants("support-lhs")
    return len(variants), sum(v.status != "ok" for v in variants)


@pytest.mark.slow  # a study of 7 000 variants, built and drawn in a browser: 10 s and more
def test_a_large_study_s_scatter_draws_a_part_of_its_sample_then_every_point_and_picks_them(tmp_path):
    from playwright.sync_api import expect, sync_playwright

    from mechdyn.dashboard.app import create_app

    (tmp_path / "lhs.toml").write_text(STUDY)
    db = str(tmp_path / "results.db")
    assert main(["study", str(tmp_path / "lhs.toml"), "--db", db]) == 0
    _add(db, 7_000, seed=3)
    n, failed = _counts(db)
    ok = n - failed
    with serving(create_app(db)) as address, sync_playwright() as p:
        browser, page, errors = open_in_chromium(p, address + "/studies/1")
        page.locator("#scatter").scroll_into_view_if_needed()
        expect(page.locator("#scatter")).to_have_attribute("data-drawn", "yes")
        expect(page.locator("#sample-note")).to_contain_text(f"of the {ok} variants that succeeded")
        # by default a part of it, evenly spread, in SVG (quick without a graphics card)
        expect(page.locator("#scatter-points")).to_be_visible()
        drawn = page.evaluate("document.getElementById('scatter').data[0]")
        assert drawn["type"] == "scatter" and 1_000 <= len(drawn["x"]) <= 3_000
        expect(page.locator("#sample-note")).to_contain_text(f"Drawn: an evenly spread {len(drawn['x'])} of")

        # the findings arrive when worked out and push the scatter down: drag once the page stands still
        expect(page.locator("#findings")).to_have_attribute("data-ready", "yes")

        def box_select() -> list[int]:
            page.locator("#scatter").scroll_into_view_if_needed()
            box = page.locator("#scatter .nsewdrag").bounding_box()
            page.mouse.move(box["x"] + 2, box["y"] + 2)
            page.mouse.down()
            page.mouse.move(box["x"] + box["width"] / 3, box["y"] + box["height"] - 2, steps=8)
            page.mouse.up()
            expect(page.locator("#selected")).to_contain_text(",")
            return [int(i) for i in page.locator("#selected").inner_text().split(",")]

        picked = box_select()
        assert set(picked) <= set(drawn["customdata"]) and len(picked) >= 2
        # every point of the page's sample, in WebGL: still picked by the box
        page.select_option("#scatter-points", "all")
        expect(page.locator("#scatter .gl-canvas").first).to_be_attached()
        every = page.evaluate("document.getElementById('scatter').data[0]")
        assert every["type"] == "scattergl" and len(every["x"]) == ok
        more = box_select()
        assert len(more) > len(picked) and set(more) <= set(every["customdata"])
        # the compare link names them (test_dashboard follows one to the comparison)
        href = page.get_attribute("#compare", "href")
        assert href == "/compare?" + "&".join(f"variant={i}" for i in more[:20])
        assert not errors, errors
        browser.close()
