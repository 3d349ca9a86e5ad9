"""No package of mechdyn imports another package's private names or modules (issue 48).

A name or module that starts with one underscore is its package's own; another package that needs it
asks for a public one. Every import statement counts, at module level or inside a function.
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "mechdyn"


def _package(module: str) -> str:
    """The top-level package of ``mechdyn.a.b`` (``mechdyn.a``); a top-level module is its own."""
    parts = module.split(".")
    return ".".join(parts[:2])


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _crossings() -> list[str]:
    found = []
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC.parent).with_suffix("")
        module = ".".join(rel.parts[:-1] if rel.name == "__init__" else rel.parts)
        here = _package(module)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.ImportFrom) or node.level or not node.module:
                continue
            target = node.module
            if not target.startswith("mechdyn.") or _package(target) == here:
                continue
            parts = target.split(".")[2:]
            names = [a.name for a in node.names]
            if any(_private(p) for p in parts) or any(_private(n) for n in names):
                found.append(f"{module}:{node.lineno}: from {target} import {', '.join(names)}")
    return found


def test_no_package_imports_another_packages_private_names():
    assert not _crossings(), "\n".join(_crossings())
