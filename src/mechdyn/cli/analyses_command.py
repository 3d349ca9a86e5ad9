"""``mechdyn analyses``: what is registered, for users and for tools."""

from __future__ import annotations

import argparse
import json

__all__ = ["register"]


def _analyses(args: argparse.Namespace) -> int:
    from mechdyn.registry import analyses

    found = analyses()
    if args.json:
        print(json.dumps([a.describe() for a in found.values()], indent=2))
        return 0
    from mechdyn.cli.common import Table, print_table

    print_table(
        Table(
            "analyses (mechdyn NAME FILE; mechdyn NAME --help for its options)",
            ["name", "model types", "options", "what it computes"],
            [
                [a.name, ", ".join(a.model_types), " ".join(o.flag for o in a.options) or "—", a.help]
                for a in found.values()
            ],
        )
    )
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "analyses",
        help="list the registered analyses, their options and summary keys",
        epilog="examples:\n  mechdyn analyses\n  mechdyn analyses --json",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--json",
        action="store_true",
        help="for each analysis: name, model types, options and summary keys with units",
    )
    p.set_defaults(func=_analyses)
