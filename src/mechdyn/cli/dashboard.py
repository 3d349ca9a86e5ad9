"""``mechdyn dashboard``: serve the web dashboard over the results database."""

from __future__ import annotations

import argparse

__all__ = ["register"]

EXAMPLES = (
    "examples:\n  mechdyn dashboard\n  mechdyn dashboard --db postgresql://me@db-host/mechdyn --port 8060\n"
    "  mechdyn dashboard --host 0.0.0.0 --allowed-host lab-pc.example.org"
)


def _serve(args: argparse.Namespace) -> int:
    from mechdyn.dashboard.app import serve

    serve(
        args.db,
        host=args.host,
        port=args.port,
        allowed_hosts=args.allowed_host or (),
        keep_designs=args.keep_designs,
    )
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "dashboard",
        help="serve a web dashboard over the results database (read-only)",
        description="Runs and studies listed with filters, a run's summary, curves and model file, "
        "runs or variants side by side, a study's views. The database is opened read-only; the "
        "server listens on 127.0.0.1 unless told otherwise.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--db", metavar="URL", help="results database (default: $MECHDYN_DB, else mechdyn.db)")
    p.add_argument(
        "--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1, this machine only)"
    )
    p.add_argument("--port", type=int, default=8050, help="port (default: 8050)")
    p.add_argument(
        "--allowed-host",
        action="append",
        metavar="NAME",
        help="a host name the dashboard answers besides the loopback names (repeatable), e.g. the "
        "machine's name when it listens beyond it with --host",
    )
    p.add_argument(
        "--keep-designs",
        action="store_true",
        help="let a study's what-if form keep a design as a new variant of that study (the only "
        "write the dashboard makes; without it the dashboard writes nothing)",
    )
    p.set_defaults(func=_serve)
