"""``python -m mechdyn``: the command line (:mod:`mechdyn.cli`)."""

from mechdyn.cli.main import console

raise SystemExit(console())
