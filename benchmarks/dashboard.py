"""The dashboard at full size: a study of 10⁵ stored variants, each of its pages timed on the server
and drawn in Chromium.

    python benchmarks/dashboard.py           # press A's Sobol study at N = 16 384: 163 840 variants
    python benchmarks/dashboard.py --quick   # N = 1 024: 10 240 variants, within a minute or two
    python benchmarks/dashboard.py --json    # one JSON object with the times and ratios

The study is a real one (``examples/studies/press_sobol.toml`` with more base samples, a power of two
as Sobol sampling needs: the smallest past 10⁵ variants), run into a fresh SQLite file. mechdyn:
``mechdyn dashboard`` over it (uvicorn in a thread), each request timed
from the client, the median of five after one to warm up: the study page, a page of its table sorted
by an output, its 500th page and its last, the sample of points its plots draw, the history, the Pareto front,
the importances, the findings. Baseline, in the same run: a plain static file of the same data (every
variant's parameters and outputs as JSON, what a page would send without the database's help) served
by the same server the same way. In Chromium (where Playwright and a Chromium are installed): the
time from opening the page to its first view drawn, and to the scatter plot drawn once scrolled to
(``*_painted_seconds``: measured in the page, from scrolling until the plot's frame is painted; the
others as Playwright sees it), then to every point of its sample drawn in WebGL when asked for.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import socket
import statistics
import sys
import tempfile
import threading
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STUDY = ROOT / "examples" / "studies" / "press_sobol.toml"


@contextmanager
def _serving(app):
    import uvicorn

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    while not server.started:
        time.sleep(0.05)
    try:
        yield f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(10)


def _get(url: str) -> tuple[int, int]:
    with urllib.request.urlopen(url) as r:
        return r.status, len(r.read())


def _timed(url: str, repeat: int = 5) -> dict[str, float]:
    _get(url)  # warm
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        status, size = _get(url)
        times.append(time.perf_counter() - t0)
    return {"seconds": statistics.median(times), "bytes": size, "status": status}


def _study(folder: Path, samples: int) -> str:
    """Run press A's Sobol study with ``samples`` base samples into a fresh database; its path."""
    from mechdyn.cli.main import main

    text = STUDY.read_text().replace("samples = 1024", f"samples = {samples}")
    text = text.replace('model = "../', f'model = "{(STUDY.parent.parent).as_posix()}/')
    path = folder / "study.toml"
    path.write_text(text)
    db = str(folder / "results.db")
    with contextlib.redirect_stdout(io.StringIO()):  # the study's own report is not this benchmark's
        done = main(["study", str(path), "--db", db, "--json"])
    if done != 0:
        raise RuntimeError("the study did not run")
    return db


def _static(db: str, folder: Path) -> Path:
    """The same data as a plain JSON file: every variant's id, parameters and outputs (SI)."""
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(db, read_only=True) as store:
        variants = StudyStore(store).variants("press-sobol")
    data = [{"id": v.id, **v.parameters, **v.outputs} for v in variants]
    path = folder / "static" / "variants.json"
    path.parent.mkdir()
    path.write_text(json.dumps(data))
    return path


def _browser(address: str) -> dict[str, float] | str:
    """Seconds from opening the study page to its first view drawn, and to the scatter plot drawn
    once scrolled to; or why not measured."""
    import os
    import shutil

    try:
        from playwright.sync_api import expect, sync_playwright
    except ImportError:
        return "Playwright is not installed"
    exe = os.environ.get("MECHDYN_TEST_CHROMIUM") or shutil.which("chromium")
    if not exe:
        return "no Chromium (scripts/with-chromium installs one)"
    # the page marks each view drawn (data-drawn, once painted); the time it was painted is taken in
    # the page itself, as Playwright's polls of a busy page come late
    painted = """window.__drawn = {};
      new MutationObserver(ms => ms.forEach(m => {
        const el = m.target;
        if (el.hasAttribute("data-drawn") && !(el.id in window.__drawn))
          window.__drawn[el.id] = performance.now();
      })).observe(document, {subtree: true, attributeFilter: ["data-drawn"]});"""
    out: dict[str, float] = {}
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=exe, args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        page.add_init_script(painted)
        for attempt in ("cold", "warm"):
            t0 = time.perf_counter()
            page.goto(address + "/studies/1")
            expect(page.locator("#variants tbody tr").first).to_be_attached(timeout=120_000)
            page.locator("#history").scroll_into_view_if_needed()
            expect(page.locator("#history")).to_have_attribute("data-drawn", "yes", timeout=120_000)
            first = time.perf_counter() - t0
            t1 = time.perf_counter()
            scrolled = page.evaluate("performance.now()")
            page.locator("#scatter").scroll_into_view_if_needed()
            expect(page.locator("#scatter")).to_have_attribute("data-drawn", "yes", timeout=120_000)
            seen = time.perf_counter() - t1
            drawn = page.evaluate("window.__drawn")
            out[f"{attempt}_first_view_seconds"] = first
            out[f"{attempt}_first_view_painted_seconds"] = drawn["history"] / 1e3
            out[f"{attempt}_scatter_seconds"] = seen
            out[f"{attempt}_scatter_painted_seconds"] = (drawn["scatter"] - scrolled) / 1e3
            # every point of the sample, in WebGL, when asked for
            t2 = page.evaluate(
                "document.getElementById('scatter').removeAttribute('data-drawn'),"
                " delete window.__drawn.scatter, performance.now()"
            )
            page.select_option("#scatter-points", "all")
            expect(page.locator("#scatter")).to_have_attribute("data-drawn", "yes", timeout=120_000)
            webgl = page.evaluate("window.__drawn.scatter") - t2
            out[f"{attempt}_scatter_webgl_painted_seconds"] = webgl / 1e3
        browser.close()
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="10 240 variants instead of 163 840")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)

    from starlette.applications import Starlette
    from starlette.routing import Mount
    from starlette.staticfiles import StaticFiles

    from mechdyn.dashboard.app import create_app

    samples = 1_024 if args.quick else 16_384
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        t0 = time.perf_counter()
        db = _study(folder, samples)
        study_seconds = time.perf_counter() - t0
        static = _static(db, folder)
        with _serving(Starlette(routes=[Mount("/", StaticFiles(directory=static.parent))])) as plain:
            baseline = _timed(plain + "/variants.json")
        app = create_app(db)
        with _serving(app) as address:
            cold = time.perf_counter()
            _get(address + "/studies/1")
            first_page = time.perf_counter() - cold
            while urllib.request.urlopen(address + "/studies/1/findings").status != 200:
                time.sleep(0.2)
            findings_seconds = time.perf_counter() - cold
            last = min(500, samples * 10 // 100)
            end = -(-samples * 10 // 100)  # the table's last page
            requests = {
                "study page": "/studies/1",
                "table, sorted by an output": "/api/studies/1/variants?sort=8&order=desc",
                f"table, page {last}": f"/api/studies/1/variants?sort=8&page={last}",
                f"table, last page ({end}), by a parameter, largest first": (
                    f"/api/studies/1/variants?sort=3&order=desc&page={end}"
                ),
                "points (the plots' sample)": "/api/studies/1/points",
                "history with the best so far": "/api/studies/1/history",
                "Pareto front": "/api/studies/1/pareto?x=8&y=9",
                "importances": "/api/studies/1/importances?column=8",
                "findings": "/studies/1/findings",
            }
            pages = {name: _timed(address + path) for name, path in requests.items()}
            browser = _browser(address)
            app.state.store.close()
    doc = {
        "benchmark": "dashboard",
        "quick": args.quick,
        "variants": samples * 10,
        "study_seconds": study_seconds,
        "first_page_seconds_cold": first_page,
        "findings_ready_seconds": findings_seconds,
        "baseline_static_file": baseline,
        "pages": {
            k: {**v, "ratio_to_static_file": v["seconds"] / baseline["seconds"]} for k, v in pages.items()
        },
        "slowest_page_seconds": max(v["seconds"] for v in pages.values()),
        "browser": browser,
    }
    if args.json:
        print(json.dumps(doc, indent=2))
        return 0
    print(f"press A Sobol study, {doc['variants']} variants (run in {study_seconds:.0f} s)")
    print(
        f"static file of the same data: {baseline['seconds'] * 1e3:.0f} ms, {baseline['bytes'] / 1e6:.1f} MB"
    )
    print(
        f"first study page, fresh server: {first_page:.2f} s; findings ready after {findings_seconds:.1f} s"
    )
    print(f"{'request':34} {'ms':>8} {'kB':>8} {'÷ static':>9}")
    for name, v in doc["pages"].items():
        print(f"{name:34} {v['seconds'] * 1e3:8.0f} {v['bytes'] / 1e3:8.0f} {v['ratio_to_static_file']:9.2f}")
    print(f"browser: {browser}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
