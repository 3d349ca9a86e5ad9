"""docs/development.md lists every module of the package with its first docstring sentence, written
from the code (docs/_ext/layout.py; regenerate with ``python docs/_ext/layout.py``)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

LAYOUT = Path(__file__).resolve().parents[1] / "docs" / "_ext" / "layout.py"


def _module():
    spec = importlib.util.spec_from_file_location("docs_layout", LAYOUT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


layout = _module()


def test_the_page_lists_every_module_as_the_code_has_it():
    old, new = layout.refresh()
    assert "<!-- modules -->" in old, "docs/development.md has lost its module listing"
    assert old == new, "the module listing in docs/development.md is stale: run python docs/_ext/layout.py"


def test_every_module_says_what_it_is_for():
    missing = [name for name, _, text in layout.modules() if not text]
    assert not missing, f"modules without a docstring: {missing}"


def test_a_new_module_shows_in_the_listing(tmp_path, monkeypatch):
    package = tmp_path / "mechdyn"
    (package / "wing").mkdir(parents=True)
    (package / "__init__.py").write_text('"""The package."""\n')
    (package / "wing" / "__init__.py").write_text('"""A wing. More about it."""\n')
    (package / "wing" / "room.py").write_text('"""One room: see :mod:`~mechdyn.wing`, e.g. here."""\nx = 1\n')
    monkeypatch.setattr(layout, "PACKAGE", package)
    text = layout.block()
    assert "wing/" in text and "A wing." in text and "More about it" not in text
    assert "wing/room.py" in text and "One room: see wing, e.g. here." in text
