from mechdyn.cli.main import console

raise SystemExit(console())
