"""The docs' figures are the figures the program prints: every ``<!-- figures: … -->`` block of a
page is written again from a fresh run and compared (docs/_ext/figures.py; regenerate with
``python docs/_ext/figures.py``)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

FIGURES = Path(__file__).resolve().parents[1] / "docs" / "_ext" / "figures.py"


def _module():
    spec = importlib.util.spec_from_file_location("docs_figures", FIGURES)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


figures = _module()


@pytest.mark.parametrize("page", figures.pages(), ids=lambda p: p.name)
def test_the_page_shows_what_the_program_prints(page):
    old, new = figures.refresh(page)
    assert old == new, f"{page.name}: figures differ from a fresh run; run python docs/_ext/figures.py"


def test_a_stale_figure_is_caught(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "Press A's floor force:\n\n<!-- figures: support examples/press_on_support.toml force_unit=tonf\n"
        "keys: transmitted_force_range_N -->\n<!-- end figures -->\n"
    )
    assert figures.main([str(page)]) == 0  # written
    fresh = page.read_text()
    assert "| transmitted force range | 85.983 | tonf |" in fresh
    assert figures.main(["--check", str(page)]) == 0
    page.write_text(fresh.replace("85.983", "85.97"))
    assert figures.main(["--check", str(page)]) == 1
