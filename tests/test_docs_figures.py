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
    page = figures.pages()[0]
    old, _ = figures.refresh(page)
    block = figures.BLOCK.search(old)
    assert block is not None
    body = block["body"]
    row = body.splitlines()[2]  # the first row after the header
    value = row.split("|")[2].strip()
    stale = tmp_path / "page.md"
    stale.write_text(old.replace(row, row.replace(value, value + "1"), 1))
    assert figures.main(["--check", str(stale)]) == 1
    assert figures.main(["--check", str(page)]) == 0
