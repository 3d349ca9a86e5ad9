"""The package's layout in docs/development.md, one line per module, written from the code.

Between ``<!-- modules -->`` and ``<!-- end modules -->`` the page lists every module of
``src/mechdyn`` (a package's ``__init__`` as the package), its number of lines and the first
sentence of its docstring, folder by folder. ``python docs/_ext/layout.py`` writes the block again;
``--check`` writes nothing and exits 1 where the page differs from the code (the tests run it), or
a module has no docstring.
"""

from __future__ import annotations

import argparse
import ast
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "src" / "mechdyn"
PAGE = ROOT / "docs" / "development.md"
BLOCK = re.compile(r"(?P<head><!-- modules -->\n)(?P<body>.*?)(?P<tail><!-- end modules -->)", re.DOTALL)
LONGEST = 700
"""Lines: a module beyond this is flagged in the listing (house rule: a room reads in one sitting)."""


def summary(path: Path) -> str | None:
    """The first sentence of a module's docstring, on one line (None without a docstring)."""
    doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")))
    if not doc:
        return None
    text = " ".join(doc.strip().split("\n\n")[0].split())
    text = re.sub(r":\w+:`~?([^`]+)`", lambda m: m[1].rsplit(".", 1)[-1] if "~" in m[0] else m[1], text)
    text = text.replace("``", "")
    end = re.search(r"(?<![.\s][a-z])\.(\s|$)", text)
    return text[: end.start() + 1] if end else text


def modules() -> list[tuple[str, int, str | None]]:
    """(name relative to src/mechdyn, lines, first sentence) of every module, in folder order."""
    rows = []
    for path in sorted(PACKAGE.rglob("*.py"), key=lambda p: (p.parent.relative_to(PACKAGE).parts, p.name)):
        if "__pycache__" in path.parts or "migrations" in path.parts:
            continue
        rel = path.relative_to(PACKAGE)
        name = str(rel.parent) + "/" if rel.name == "__init__.py" else str(rel)
        if name == "./":
            name = "mechdyn/"
        lines = len(path.read_text(encoding="utf-8").splitlines())
        rows.append((name, lines, summary(path)))
    return rows


def block() -> str:
    """The listing as the page shows it (a fenced block, one line per module)."""
    rows = modules()
    width = max(len(n) for n, _, _ in rows)
    out = ["```"]
    for name, lines, text in rows:
        flag = " (over 700 lines)" if lines > LONGEST else ""
        out.append(f"{name:<{width}}  {lines:>4}  {text or '(no docstring)'}{flag}")
    out.append("```")
    return "\n".join(out) + "\n"


def refresh(page: Path = PAGE) -> tuple[str, str]:
    """(the page as it is, the page with its block written again)."""
    old = page.read_text(encoding="utf-8")
    new = BLOCK.sub(lambda m: m["head"] + block() + m["tail"], old)
    return old, new


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 where the page is stale")
    args = parser.parse_args(argv)
    old, new = refresh()
    missing = [n for n, _, t in modules() if t is None]
    if args.check:
        if old != new:
            print(f"{PAGE.name}: the module listing differs from the code; run python docs/_ext/layout.py")
        for n in missing:
            print(f"{n}: no module docstring")
        return int(old != new or bool(missing))
    PAGE.write_text(new, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
