"""The ``mechdyn`` command line: one entry point, one subcommand per analysis."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from mechdyn.cli import drivetrain, gear, mechanism, mount, results, support
from mechdyn.errors import MechdynError

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    from mechdyn import __version__

    p = argparse.ArgumentParser(
        prog="mechdyn",
        description="Dynamic analysis of machines at the design stage. Every analysis run is stored "
        "in the results database (see `mechdyn results`).",
    )
    p.add_argument("--version", action="version", version=f"mechdyn {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    drivetrain.register(sub)
    gear.register(sub)
    mechanism.register(sub)
    support.register(sub)
    mount.register(sub)
    results.register(sub)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 2 bad input)."""
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except MechdynError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
