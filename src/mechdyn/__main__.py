from mechdyn.cli.main import main

raise SystemExit(main())
