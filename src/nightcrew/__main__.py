from nightcrew.cli.main import main

raise SystemExit(main())
