"""The ``mechdyn`` command line: one subcommand per registered analysis, plus ``analyses`` and
``results``.

The parser is built from the analysis registry without importing any numerical library, so
``mechdyn --help`` and ``mechdyn analyses`` answer at once; an analysis imports what it runs.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from mechdyn.errors import MechdynError

__all__ = ["build_parser", "console", "main"]


def build_parser() -> argparse.ArgumentParser:
    from mechdyn import __version__
    from mechdyn.cli import analyses_command, dashboard, fields, new, report, results, study
    from mechdyn.cli.runner import add_analysis_parser
    from mechdyn.registry import analyses

    p = argparse.ArgumentParser(
        prog="mechdyn",
        description="Dynamic analysis of machines at the design stage. Every analysis run is stored "
        "in the results database (see `mechdyn results`); `mechdyn analyses` lists the analyses.",
        epilog="examples:\n"
        "  mechdyn modal examples/turret_indexing.toml --compare-rigid --plots plots\n"
        "  mechdyn mechanism examples/press_link_drive.toml --csv press.csv\n"
        "  mechdyn study examples/studies/press_support_influence.toml\n"
        "  mechdyn analyses --json",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--version", action="version", version=f"mechdyn {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for analysis in analyses().values():
        add_analysis_parser(sub, analysis)
    analyses_command.register(sub)
    fields.register(sub)
    new.register(sub)
    study.register(sub)
    results.register(sub)
    report.register(sub)
    dashboard.register(sub)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 2 bad input, 1 a study none of whose
    variants but the base design could be evaluated)."""
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except MechdynError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except Exception as exc:  # the database library's errors, wherever they come from: one line
        from sqlalchemy.exc import SQLAlchemyError

        if not isinstance(exc, SQLAlchemyError):
            raise
        from mechdyn.store.database import describe
        from mechdyn.store.store import resolve_url

        print(f"error: {describe(exc, resolve_url(getattr(args, 'db', None)))}", file=sys.stderr)
        return 2


def console() -> int:
    """The ``mechdyn`` command (and ``python -m mechdyn``): :func:`main`, then every object left moved
    out of the garbage collector's reach, so that the interpreter's exit does not walk them again and
    again as it unloads each module (half a second after a mechanism's run: more than its analysis).
    Nothing is lost: the run is stored and the files are closed by then, and the memory goes back to
    the system with the process. Returns the exit status."""
    import gc

    status = main()
    gc.freeze()
    return status


if __name__ == "__main__":  # pragma: no cover
    sys.exit(console())
