"""``mechdyn fields TYPE``: the model-file reference of one file type, in the terminal."""

from __future__ import annotations

import argparse
import json
import textwrap
from dataclasses import asdict

__all__ = ["register"]


def _plain(text: str) -> str:
    """reST literals and emphasis as plain text."""
    return text.replace("``", "").replace("**", "")


def _wrapped(text: str, indent: str) -> str:
    return textwrap.fill(_plain(text), 100, initial_indent=indent, subsequent_indent=indent)


def _fields(args: argparse.Namespace) -> int:
    from mechdyn.errors import MechdynError
    from mechdyn.io.modelfile import file_types
    from mechdyn.io.reference import reference

    if args.type not in file_types():
        known = ", ".join(file_types())
        raise MechdynError(f"mechdyn fields: no file type {args.type!r}; give one of {known}")
    tables, _ = reference(args.type)
    if args.json:
        print(json.dumps([asdict(t) | {"header": t.header} for t in tables], indent=2, ensure_ascii=False))
        return 0
    print(f'{args.type} files ([model] type = "{args.type}"): every quantity is a string with its unit')
    for t in tables:
        need = "required" if t.required else "optional"
        each = ", one table per element" if t.is_array else ""
        print(f"\n{t.header}  ({need}{each})")
        if t.description:
            print(_wrapped(t.description, "  "))
        if t.values:
            print(f"  each entry: name = value, the value {_plain(t.values)}")
        for f in t.fields:
            print(f"  {f.name}: {_plain(f.kind)}; {_plain(f.default)}")
            if f.meaning:
                print(_wrapped(f.meaning, "      "))
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "fields",
        help="print the fields of a model-file type: each table, field, unit, default and meaning",
        description="The model-file reference of one file type, read from the schema that validates "
        "the files (the same as the documentation's).",
        epilog="examples:\n  mechdyn fields drivetrain\n  mechdyn fields mount --json\n\n"
        "`mechdyn new TYPE FILE` writes a commented template of a file of TYPE that loads and runs.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("type", help="a model type (drivetrain, mechanism, support, mount, …) or study")
    p.add_argument("--json", action="store_true", help="the tables and fields as JSON")
    p.set_defaults(func=_fields)
