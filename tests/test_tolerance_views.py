"""A tolerance study's results as a designer reads them in its report and on its dashboard page: each
limit's probability in words with its 95 % interval and method, the sample size and how far to trust
it, each output's histogram and CDF with its limit drawn, and the tolerances ranked per limit (a table
and a bar chart); numbers with three significant digits at least."""

from __future__ import annotations

import contextlib
import copy
import html as htmllib
import io
import re
import time
import tomllib
import urllib.error
import urllib.request
from types import SimpleNamespace

import pytest

from conftest import EXAMPLES, open_in_chromium, serving
from mechdyn.cli.main import main

STUDY = EXAMPLES / "studies" / "press_support_tolerance.toml"
SAMPLES = 32  # a power of 2 (quasi-Monte Carlo): 16 replicates of 2
NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:e[+-]\d+)?")
FIGURE = r"[-+\d.e]+"
SENTENCE = re.compile(
    rf"P\((?P<event>[^)]*)\) = (?P<p>{FIGURE}) \[(?P<low>{FIGURE}), (?P<high>{FIGURE})\] "
    r"\(95 %, (?P<method>[^,]+),"
)


def _significant(text: str) -> int:
    """The significant digits a number is written with ("0.328" 3, "0.04" 1, "1.23e-04" 3)."""
    return len(text.lstrip("-+").split("e")[0].replace(".", "").lstrip("0"))


def _short(text: str) -> list[str]:
    """Numbers written with a decimal point or an exponent and fewer than three significant digits."""
    return [x for x in NUMBER.findall(text) if ("." in x or "e" in x) and _significant(x) < 3]


def _words(page: str) -> str:
    """A page's text as a reader sees it (no markup, no embedded pictures)."""
    page = re.sub(r'src="data:[^"]+"', 'src=""', page)
    page = re.sub(r"<(style|script)\b.*?</\1>", " ", page, flags=re.S)
    return " ".join(htmllib.unescape(re.sub(r"<[^>]+>", " ", page)).split())


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    """The shipped press A tolerance study with fewer samples, run into a database with its report;
    its result read back from the database."""
    from mechdyn.reports.html import toml_text
    from mechdyn.store import ResultStore
    from mechdyn.studies.run import stored_result

    folder = tmp_path_factory.mktemp("tolerance_views")
    data = tomllib.loads(STUDY.read_text(encoding="utf-8"))
    data["study"]["model"] = str((STUDY.parent / data["study"]["model"]).resolve())
    data["study"]["samples"] = SAMPLES
    path, db, report = folder / STUDY.name, str(folder / "r.db"), folder / "report.html"
    path.write_text(toml_text(data), encoding="utf-8")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main(["study", str(path), "--db", db, "--report", str(report)]) == 0
    with ResultStore(db, read_only=True) as store:
        result = stored_result(store, data["study"]["name"])
    return SimpleNamespace(
        db=db, report=report.read_text(encoding="utf-8"), result=result, printed=printed.getvalue()
    )


EVENTS = {  # each limit of the study file in words, the limit in the output's unit
    "displacement_max_m": "displacement max > 1.30 mm",
    "transmitted_force_range_N": "transmitted force range > 86.5 tonf",
}


def _expected_sentences(result) -> list[tuple[str, float, float, float]]:
    """Each limit's event, probability and interval as the findings hold them (fractions)."""
    out = []
    for d in result.findings["limits"]:
        p = d["probability"]
        out.append((EVENTS[d["output"]], p["value"], p["low"], p["high"]))
    return out


def _check_sentences(text: str, result) -> None:
    """Every limit's sentence is in ``text``, its numbers the findings' to three significant digits."""
    found = {m["event"]: m for m in SENTENCE.finditer(text)}
    for event, p, low, high in _expected_sentences(result):
        assert event in found, (event, text[:2000])
        m = found[event]
        for written, value in ((m["p"], p), (m["low"], low), (m["high"], high)):
            assert float(written) == pytest.approx(float(f"{value:.3g}"), rel=1e-12), (event, written, value)
            assert written == "0" or _significant(written) >= 3, written  # a zero is written 0
        assert m["method"] == "randomized quasi-Monte Carlo"
        assert low <= p <= high


def test_the_command_prints_each_limits_probability_above_its_tables(ran):
    head = ran.printed.split("\n\n")[0]  # before the first table
    _check_sentences(head, ran.result)


def test_the_report_leads_with_each_limits_probability_and_method_in_words(ran):
    header = ran.report.split("<main>")[0]
    headlines = re.findall(r'<p class="headline">(.*?)</p>', header, flags=re.S)
    assert len(headlines) == len(ran.result.findings["limits"]) == 2
    _check_sentences(" ".join(htmllib.unescape(h) for h in headlines), ran.result)
    assert not _short(" ".join(headlines))


def test_the_report_states_the_sample_size_and_how_far_to_trust_the_probabilities(ran):
    text = _words(ran.report)
    section = text.split("Probabilities of exceeding the limits")[2].split("Findings")[0]
    assert section.startswith(
        f" {SAMPLES} samples by randomized quasi-Monte Carlo (scrambled Sobol, 16 replicates)"
    )
    assert "95 % intervals by replicate spread" in section
    warned = [w for d in ran.result.findings["limits"] for w in d["probability"]["warnings"]]
    for w in warned:  # the uncertainty core's own validity warnings, each named by its limit
        assert w in section
    if not warned:
        assert "Every estimate is valid at this sample size" in section
    assert not _short(section), _short(section)


def test_the_report_shows_each_outputs_histogram_and_cdf_and_each_limits_ranking(ran):
    captions = re.findall(
        r'<figure><img alt="([^"]*)" src="data:image/png;base64,[A-Za-z0-9+/=]{2000,}"', ran.report
    )
    captions = [htmllib.unescape(c) for c in captions]
    for words in ("displacement max", "transmitted force range"):
        drawn = [c for c in captions if c.startswith(f"{words}: histogram and CDF of the {SAMPLES} samples")]
        assert len(drawn) == 1, captions  # once: the Plots section does not draw it again
    rankings = [c for c in captions if "the tolerances ranked" in c]
    assert [c.split(":")[0] for c in rankings] == [
        "P(displacement max > 1.30 mm)",
        "P(transmitted force range > 86.5 tonf)",
    ]
    text = _words(ran.report)
    for d in ran.result.findings["limits"]:
        table = text.split(f"tolerances ranked by their share of P({EVENTS[d['output']]}) parameter measure")[
            1
        ]
        first, second = d["ranking"]["ranked"]
        assert table.index(first) < table.index(second)  # the largest share first


def test_a_rare_limit_leads_with_its_small_probability_method_and_no_failure_with_a_bound(ran):
    """The sentence of a limit found rare leads with its small-probability estimate (method, interval,
    cost), the samples' estimate after it; one no sample exceeded gives the samples' upper bound."""
    from mechdyn.studies.kinds.tolerance_show import headline, statement

    findings = copy.deepcopy(ran.result.findings)
    first, second = findings["limits"]
    first["small_probability"] = {
        **first["probability"],
        "value": 1.234e-4,
        "low": 6.02e-5,
        "high": 2.53e-4,
        "method": "importance sampling at the FORM design point",
        "interval_method": "p·exp(±z·√ln(1 + CoV²))",
        "evaluations": 400,
        "cov": 0.3712,
        "warnings": [],
    }
    second["probability"] |= {
        "value": 0.0,
        "low": 0.0,
        "high": 0.1089,
        "failures": 0,
        "warnings": ["none seen"],
    }
    fake = SimpleNamespace(study=ran.result.study, findings=findings, variants=ran.result.variants)
    rare, bound = headline(fake)
    assert rare.startswith(
        "P(displacement max > 1.30 mm) = 1.23e-04 [6.02e-05, 2.53e-04] (95 %, importance sampling at the "
        "FORM design point, 400 evaluations, coefficient of variation 0.371); by the samples: "
        "P(displacement max"
    )
    assert bound == (
        "P(transmitted force range > 86.5 tonf) < 0.109 (95 % upper bound, randomized quasi-Monte Carlo: no "
        f"sample of {SAMPLES} beyond the limit)"
    )
    _note, warnings = statement(fake)
    assert "transmitted force range > 86.5 tonf: none seen" in warnings


def _get(url: str) -> tuple[int, str]:
    try:
        with urllib.request.urlopen(url) as r:
            return r.status, r.read().decode()
    except urllib.error.HTTPError as e:
        with e:
            return e.code, e.read().decode()


@pytest.fixture(scope="module")
def server(ran):
    from mechdyn.dashboard.app import create_app

    with serving(create_app(ran.db)) as address:
        yield address


def _findings(address: str) -> str:
    """The study's findings section, once worked out in the background (polled, no fixed wait)."""
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        status, body = _get(f"{address}/studies/1/findings")
        if status == 200:
            return body
        time.sleep(0.1)
    pytest.fail("the findings never came")


def test_the_dashboards_study_page_shows_the_same_probabilities_figures_and_rankings(server, ran):
    section = _findings(server)
    text = _words(section)
    _check_sentences(text, ran.result)
    assert f"{SAMPLES} samples by randomized quasi-Monte Carlo" in text
    figures = re.findall(r'<img alt="([^"]*)" src="([^"]+)"', section)
    captions = [htmllib.unescape(c) for c, _ in figures]
    led = captions[:4]  # the histograms and the rankings come first, before the tables
    assert led == [
        f"displacement max: histogram and CDF of the {SAMPLES} samples, each limit dashed with its "
        "probability",
        led[1],
        f"transmitted force range: histogram and CDF of the {SAMPLES} samples, each limit dashed with its "
        "probability",
        led[3],
    ]
    assert led[1].startswith("P(displacement max > 1.30 mm): the tolerances ranked")
    assert section.index("histogram and CDF") < section.index("tolerances ranked by their share")
    for _c, url in figures[:4]:  # each picture is served as a PNG
        with urllib.request.urlopen(server + htmllib.unescape(url)) as r:
            assert r.headers["content-type"] == "image/png" and r.read(8) == b"\x89PNG\r\n\x1a\n"
    assert not _short(text.split("Findings")[0].split("press-support-tolerance: scatter")[0])
    # the whole page carries the same section once worked out, and the list leads with the probability
    _status, page = _get(server + "/studies/1")
    _check_sentences(_words(page), ran.result)
    _status, listing = _get(server + "/")
    assert "P(displacement max &gt; 1.30 mm) = " in listing


def test_the_dashboards_importances_are_the_studys_own_ranking_of_its_tolerances(server, ran):
    """The importances view of an output shows the ranking the findings hold (not PED-ANOVA's)."""
    import json

    _findings(server)
    for column, key in ((2, "displacement_max_m"), (3, "transmitted_force_range_N")):
        _status, body = _get(f"{server}/api/studies/1/importances?column={column}")
        got, ranking = json.loads(body), ran.result.findings["outputs"][key]["ranking"]
        assert got["method"] == f"the study's own ranking: {ranking['method']}"
        assert got["values"] == pytest.approx(ranking["measures"], rel=1e-12)


@pytest.mark.slow  # the dashboard's page by HTTP by default (above); drawn in Chromium in CI's heavy step
@pytest.mark.usefixtures("patient_browser_checks")
def test_the_probabilities_and_their_pictures_show_in_a_real_browser(server, ran):
    from playwright.sync_api import expect, sync_playwright

    _findings(server)  # worked out: the page carries them
    with sync_playwright() as p:
        browser, page, errors = open_in_chromium(p, server + "/studies/1")
        try:
            views = page.locator("#findings-views")
            expect(views.locator("p.headline").first).to_contain_text("P(displacement max > 1.30 mm) = ")
            expect(views.locator("#findings-statement")).to_contain_text(f"{SAMPLES} samples")
            images = views.locator("img")
            expect(images).to_have_count(4)
            for k in range(4):
                images.nth(k).scroll_into_view_if_needed()
                expect(images.nth(k)).to_have_js_property("complete", True)
                assert images.nth(k).evaluate("img => img.naturalWidth") > 300
            assert not errors, errors
        finally:
            browser.close()
