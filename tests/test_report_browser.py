"""Reports as a reviewer opens them: in Chromium, at 1280 px, nothing cut off, every plot drawn."""

from __future__ import annotations

import pytest

from conftest import EXAMPLES, chromium
from mechdyn.cli.main import main

WIDTH, HEIGHT = 1280, 800


# what the page reports about itself: page-wide overflow, tables that neither fit nor scroll, images
# that did not decode, the headline's place, the model file as written
_LAYOUT = """() => {
  const page = document.documentElement;
  const wraps = [...document.querySelectorAll('.tablewrap')];
  return {
    pageOverflow: page.scrollWidth - window.innerWidth,
    cutTables: wraps.filter(w => w.scrollWidth > w.clientWidth + 1
                              && getComputedStyle(w).overflowX !== 'auto').length,
    scrollingTables: wraps.filter(w => w.scrollWidth > w.clientWidth + 1).length,
    tables: wraps.length,
    images: [...document.images].map(i => ({ok: i.complete && i.naturalWidth > 0,
                                            fits: i.getBoundingClientRect().right <= window.innerWidth,
                                            src: i.src.slice(0, 22)})),
    headlineTop: (document.querySelector('p.headline') || {getBoundingClientRect: () => ({top: 1e9})})
                   .getBoundingClientRect().top,
    pre: [...document.querySelectorAll('pre')].map(p => p.textContent),
    summaries: [...document.querySelectorAll('h3')].filter(h => h.textContent.trim() === 'summary').length,
  };
}"""


SLOW = pytest.mark.slow


@pytest.mark.parametrize(
    ("argv", "name", "figures"),
    [
        (["mechanism", str(EXAMPLES / "press_link_drive.toml"), "--angles", "90"], "press", None),
        # the support's and the study's reports in CI's heavy step (the same page and checks)
        pytest.param(
            ["support", str(EXAMPLES / "press_on_mounts.toml"), "--cycles", "2"], "mounts", None, marks=SLOW
        ),
        pytest.param(
            ["study", str(EXAMPLES / "studies" / "press_support_influence.toml")], "study", 1, marks=SLOW
        ),
    ],
    ids=["mechanism", "support", "study"],
)
def test_a_report_reads_in_chromium_at_1280_px(tmp_path, argv, name, figures):
    from playwright.sync_api import sync_playwright

    from mechdyn import load
    from mechdyn.registry import get

    out = tmp_path / f"{name}.html"
    assert main([*argv, "--db", str(tmp_path / "r.db"), "--report", str(out)]) == 0
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
        try:
            page = browser.new_page(viewport={"width": WIDTH, "height": HEIGHT})
            page.goto(out.as_uri())
            page.wait_for_load_state("load")  # every embedded image decoded before it is measured
            shown = page.evaluate(_LAYOUT)
            page.screenshot(path=str(tmp_path / f"{name}.png"), full_page=False)
        finally:
            browser.close()
    assert shown["pageOverflow"] <= 0, "the page scrolls sideways: something is wider than the window"
    assert shown["cutTables"] == 0 and shown["tables"] > 0
    assert shown["images"] and all(i["ok"] and i["fits"] for i in shown["images"]), shown["images"]
    if argv[0] == "study":
        assert any("[study]" in text for text in shown["pre"])  # the study file as the user wrote it
        return
    assert 0 <= shown["headlineTop"] < HEIGHT  # the figures that matter, on the first screen
    assert shown["summaries"] == 1  # one summary table, not two
    assert any("[model]" in text for text in shown["pre"])  # the model file as the user wrote it
    loaded = load(argv[1])
    options = {"angles": 90} if argv[0] == "mechanism" else {"cycles": 2, "store": None}
    result = get(argv[0]).run(loaded, **options)
    animated = 1 if argv[0] == "mechanism" else 0
    assert len(shown["images"]) == len(result.plots()) + animated  # every plot, and the linkage
    if animated:
        assert shown["images"][0]["src"].startswith("data:image/gif")
