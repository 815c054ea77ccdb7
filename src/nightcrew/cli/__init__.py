"""The ``nightcrew`` command line; one file per subcommand, each with ``add_parser()``."""
