"""What if: a study's design evaluated at once from sliders, beside the study's best, a mechanism's
linkage animated; only the study's own parameters, in range, as numbers; nothing written."""

from __future__ import annotations

import json
import urllib.error
import urllib.parse
import urllib.request

import pytest

from conftest import EXAMPLES, open_in_chromium, serving
from mechdyn.cli.main import main

STUDY = f"""
[study]
name = "fourbar-whatif"
kind = "lhs"
model = "{(EXAMPLES / "fourbar.toml").as_posix()}"
analysis = "mechanism"
samples = 30
seed = 2
options = {{ angles = 72 }}

[[parameters]]
path = "points.B.x"
range = "±3 %"

[[parameters]]
path = "bodies.coupler.mass"
range = "±20 %"

[[outputs]]
output = "driving_torque_max_Nm"

[[outputs]]
output = "shaking_force_max_N"
"""


pytestmark = pytest.mark.usefixtures("patient_browser_checks")


@pytest.fixture(scope="module")
def database(tmp_path_factory):
    d = tmp_path_factory.mktemp("whatif")
    (d / "study.toml").write_text(STUDY)
    db = str(d / "results.db")
    assert main(["study", str(d / "study.toml"), "--db", db]) == 0
    return db


@pytest.fixture(scope="module")
def server(database):
    from mechdyn.dashboard.app import create_app

    with serving(create_app(database)) as address:
        yield address


def _ask(server: str, **values: object) -> tuple[int, dict]:
    url = server + "/api/studies/1/whatif?" + urllib.parse.urlencode(values)
    try:
        with urllib.request.urlopen(url) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as e:
        with e:
            return e.code, json.loads(e.read())


def test_a_design_is_evaluated_as_the_study_s_analysis_evaluates_it(server, database, tmp_path):
    from mechdyn.io import load_model
    from mechdyn.registry import get

    status, d = _ask(server, **{"points.B.x": 196.0, "bodies.coupler.mass": 1.3})
    assert status == 200 and d["status"] == "ok"
    # the same design built by hand from the example file
    text = (EXAMPLES / "fourbar.toml").read_text().replace('B = ["194.608480 mm"', 'B = ["196 mm"')
    text = text.replace('mass = "1.2 kg"', 'mass = "1.3 kg"', 1)
    path = tmp_path / "fourbar.toml"
    path.write_text(text)
    summary = get("mechanism").run(load_model(path), angles=72).summary()
    got = {o["key"]: o["value"] for o in d["outputs"]}
    assert got["driving_torque_max_Nm"] == pytest.approx(summary["driving_torque_max_Nm"], rel=1e-12)
    assert got["shaking_force_max_N"] == pytest.approx(summary["shaking_force_max_N"], rel=1e-12)
    # beside the study's best (its smallest last output, as stored), and the linkage over the cycle
    assert d["best"]["id"] >= 1 and len(d["best"]["outputs"]) == 2
    link = d["linkage"]
    assert len(link["angles_deg"]) == 36 and {b["name"] for b in link["bodies"]} == {
        "crank",
        "coupler",
        "rocker",
    }
    assert d["curves"] and len(d["curves"][0]["x"]) == len(d["curves"][0]["y"])


@pytest.mark.parametrize(
    ("values", "says"),
    [
        ({"points.B.x": 250}, "outside its range"),
        ({"nope": 1}, "is not a parameter of this study"),
        ({"points.B.x": "abc"}, "is not a number"),
        ({"points.B.x": "inf"}, "not a finite number"),
    ],
)
def test_the_what_if_takes_only_the_study_s_parameters_in_range_as_numbers(server, values, says):
    status, d = _ask(server, **values)
    assert status == 400 and says in d["error"]


def test_nothing_is_written_and_the_database_stays_read_only(server, database):
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(database, read_only=True) as store:
        before = StudyStore(store).counts(1)
    for x in (190.0, 195.0, 200.0):
        assert _ask(server, **{"points.B.x": x})[0] == 200
    with ResultStore(database, read_only=True) as store:
        assert StudyStore(store).counts(1) == before


def test_moving_a_slider_evaluates_the_design_and_animates_its_linkage_in_a_real_browser(server):
    from playwright.sync_api import expect, sync_playwright

    with sync_playwright() as p:
        browser, page, errors = open_in_chromium(p, server + "/studies/1")
        expect(page.locator("#whatif-status")).to_contain_text("evaluated in")
        expect(page.locator("#whatif-outputs tbody tr")).to_have_count(2)
        expect(page.locator("#whatif-best-title")).to_contain_text("the study's best (variant")
        # the linkage, animated over the cycle: 36 frames, a play button, this design and the best
        expect(page.locator("#whatif-linkage .main-svg").first).to_be_attached()
        expect(page.locator("#whatif-linkage .updatemenu-button")).to_have_count(1)
        page.wait_for_function(
            "document.getElementById('whatif-linkage')._transitionData._frames.length === 36"
        )
        first = page.locator("#whatif-outputs tbody tr").first.locator("td").nth(1).inner_text()
        # move the coupler's mass to the end of its range
        slider = page.locator("#whatif input[name='bodies.coupler.mass']")
        slider.evaluate("el => { el.value = el.max; el.dispatchEvent(new Event('input')); }")
        expect(page.locator("#whatif-outputs tbody tr").first.locator("td").nth(1)).not_to_have_text(first)
        expect(page.locator("#whatif-status")).to_contain_text("evaluated in")
        page.click("#whatif-linkage .updatemenu-button")  # play
        assert not errors, errors
        browser.close()


def _keep(server: str, headers: dict[str, str] | None = None, **values: object) -> tuple[int, dict]:
    url = server + "/api/studies/1/keep?" + urllib.parse.urlencode(values)
    request = urllib.request.Request(url, method="POST", headers=headers or {})
    try:
        with urllib.request.urlopen(request) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as e:
        with e:
            return e.code, json.loads(e.read())


def test_a_read_only_dashboard_keeps_no_design(server, database):
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    status, d = _keep(server, {"X-Mechdyn": "keep"}, **{"points.B.x": 196.0})
    assert status == 403 and "--keep-designs" in d["error"]
    with ResultStore(database, read_only=True) as store:
        assert StudyStore(store).counts(1)["variants"] == 31


def test_started_to_keep_designs_it_keeps_one_as_a_new_variant_of_that_study_only(database, tmp_path):
    import shutil

    from mechdyn.dashboard.app import create_app
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    db = str(tmp_path / "copy.db")
    shutil.copy(database, db)
    app = create_app(db, keep_designs=True)
    assert app.state.store.read_only  # the pages still read through a read-only connection
    with serving(app) as address:
        design = {"points.B.x": 196.5, "bodies.coupler.mass": 1.25}
        # only from the dashboard's own page (a header another site cannot send), only in range
        assert _keep(address, **design)[0] == 403
        assert _keep(address, {"X-Mechdyn": "keep"}, **{"points.B.x": 999})[0] == 400
        status, d = _keep(address, {"X-Mechdyn": "keep"}, **design)
        assert status == 200 and d["status"] == "ok"
        _, what = _ask(address, **design)
        again = _keep(address, {"X-Mechdyn": "keep"}, **design)[1]  # the same design: the same variant
        assert again["variant"] == d["variant"]
    with ResultStore(db, read_only=True) as store:
        studies = StudyStore(store)
        assert studies.counts(1)["variants"] == 32
        v = studies.variant(d["variant"])
    assert v.study == "fourbar-whatif" and v.status == "ok"
    assert v.parameters["bodies.coupler.mass"] == pytest.approx(1.25)
    assert v.parameters["points.B.x"] == pytest.approx(0.1965)
    for o in what["outputs"]:
        assert v.outputs[o["key"]] == pytest.approx(o["value"], rel=1e-12)
