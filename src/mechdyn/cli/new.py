"""``mechdyn new TYPE [PATH]``: a commented template of a model file, from the schema of its type."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["register"]


def _new(args: argparse.Namespace) -> int:
    from mechdyn.errors import MechdynError
    from mechdyn.io.modelfile import file_types
    from mechdyn.io.template import template
    from mechdyn.io.template_examples import EXAMPLES

    if args.type not in file_types():
        known = ", ".join(file_types())
        raise MechdynError(f"mechdyn new: no file type {args.type!r}; give one of {known}")
    if args.path is None:
        sys.stdout.write(template(args.type))
        return 0
    path = Path(args.path)
    if path.is_dir():
        raise MechdynError(f"mechdyn new: {path} is a folder; give the path of the file to write")
    if path.exists() and not args.force:
        raise MechdynError(
            f"mechdyn new: {path} exists; give another path, or --force to overwrite it with the template"
        )
    if not path.parent.is_dir():
        raise MechdynError(
            f"mechdyn new: {path.parent} is not a folder; create it first or give another path"
        )
    path.write_text(template(args.type, str(path)), encoding="utf-8")
    example = EXAMPLES.get(args.type)
    run = f"; run it: {example.run.replace('FILE', str(path))}" if example and example.run else ""
    print(f"wrote {path}, a {args.type} template{run}")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "new",
        help="write a commented template of a model file (every table and field, with units and "
        "defaults) that loads and runs",
        description="A commented template of a model file of TYPE, generated from the schema that "
        "validates the files: every table and field with its meaning, unit and default. A small "
        "example model is given as values with their units, so that the file loads and its analysis "
        "runs as written; every other field is commented out with its default.",
        epilog="examples:\n"
        "  mechdyn new drivetrain                  (print it)\n"
        "  mechdyn new drivetrain gearbox.toml     (write it, then: mechdyn modal gearbox.toml)\n"
        "  mechdyn new support press.toml --force  (overwrite press.toml)",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("type", help="a model type (drivetrain, mechanism, support, mount, …) or study")
    p.add_argument("path", nargs="?", help="the file to write (default: print the template)")
    p.add_argument("--force", action="store_true", help="overwrite PATH if it exists")
    p.set_defaults(func=_new)
