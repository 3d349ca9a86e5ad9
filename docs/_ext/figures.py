"""Docs figures written by the runs they describe.

A block in a docs page names an analysis, a model file (relative to the repository), its options and
the summary keys to show::

    <!-- figures: drive examples/press_driven.toml no_startup=true
         keys: speed_fluctuation_ratio period_s flywheel_for_target_kg_m2 -->
    | quantity | value | unit |
    | --- | --- | --- |
    | speed fluctuation ratio | 0.019177 |  |
    <!-- end figures -->

The table under it is that run's summary for those keys, each value written by the program's own rule
(:func:`mechdyn.results.summary_table`: the unit a designer reads it in, and
:func:`mechdyn.numbers.number_text`: five significant digits), so a page shows what ``mechdyn`` prints.

``python docs/_ext/figures.py`` writes every block of every page again; ``--check`` writes nothing and
exits 1 naming each page whose figures differ from a fresh run (the tests run it).
"""

from __future__ import annotations

import argparse
import re
import shlex
import sys
import warnings
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
DISPLAY = ("force_unit", "length_unit")
"""Options that choose the unit a value is shown in (as the command's ``--force-unit``), not the run."""
BLOCK = re.compile(
    r"(?P<head><!-- figures: (?P<spec>.*?)-->\n)(?P<body>.*?)(?P<tail><!-- end figures -->)", re.DOTALL
)


def _value(text: str) -> Any:
    for cast in (int, float):
        try:
            return cast(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text, text)


def parse(spec: str) -> tuple[str, str, dict[str, Any], list[str]]:
    """(analysis, model file, options, keys) of a block's head: options as ``name=value``, read as
    the analysis declares them (a quantity with its unit, ``"60 t"``; names separated by commas; a
    path to another model file relative to the repository)."""
    from mechdyn.registry import get
    from mechdyn.units import to_si

    words, _, keys = spec.partition("keys:")
    analysis, model, *options = shlex.split(words)
    declared = {o.name: o for o in get(analysis).options}
    opts: dict[str, Any] = {}
    for o in options:
        name, text = o.split("=", 1)
        kind = declared[name].kind if name in declared else None
        if kind == "quantity":
            opts[name] = to_si(text, declared[name].unit or "")
        elif kind == "names":
            opts[name] = text.split(",")
        elif kind == "text" and text.endswith(".toml"):
            opts[name] = str(ROOT / text)
        else:
            opts[name] = _value(text)
    return analysis, model, opts, keys.split()


def table(analysis: str, model: str, options: dict[str, Any], keys: list[str]) -> str:
    """The markdown table of a block: the run's summary for ``keys``, as the program writes it."""
    import mechdyn
    from mechdyn.numbers import is_number, number_text
    from mechdyn.registry import get
    from mechdyn.results import summary_table

    options = dict(options)
    run_options = {k: v for k, v in options.items() if k not in DISPLAY}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = get(analysis).run(mechdyn.load(ROOT / model), **run_options)
    summary = result.summary()
    missing = [k for k in keys if k not in summary]
    if missing:
        raise KeyError(f"{analysis} {model}: no summary key {', '.join(missing)}")
    shown = {k: options.pop(k) for k in DISPLAY if k in options}
    rows = summary_table({k: summary[k] for k in keys}, display_units=shown).rows
    lines = ["| quantity | value | unit |", "| --- | --- | --- |"]
    for label, value, unit in rows:
        text = number_text(float(value)) if is_number(value) and not isinstance(value, int) else str(value)
        unit = "" if unit in ("", "1") else unit
        lines.append(f"| {label} | {text} | {unit} |")
    return "\n".join(lines) + "\n"


def refresh(page: Path) -> tuple[str, str]:
    """(the page as it is, the page with every block written again)."""
    text = page.read_text(encoding="utf-8")

    def block(m: re.Match[str]) -> str:
        return m["head"] + table(*parse(m["spec"])) + m["tail"]

    return text, BLOCK.sub(block, text)


def pages() -> list[Path]:
    """Every docs page with a figures block."""
    return sorted(p for p in DOCS.rglob("*.md") if "<!-- figures:" in p.read_text(encoding="utf-8"))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 where a page is stale")
    parser.add_argument("pages", nargs="*", type=Path, help="pages to do (default: every page with a block)")
    args = parser.parse_args(argv)
    stale = []
    for page in args.pages or pages():
        old, new = refresh(page)
        if old != new:
            stale.append(page)
            if not args.check:
                page.write_text(new, encoding="utf-8")
    for page in stale:
        verb = "differs from a fresh run" if args.check else "written"
        shown = page.resolve().relative_to(ROOT) if page.resolve().is_relative_to(ROOT) else page
        print(f"{shown}: {verb}")
    return 1 if stale and args.check else 0


if __name__ == "__main__":
    sys.exit(main())
