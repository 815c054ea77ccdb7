"""Entry point of the ``nightcrew`` command.

Each subcommand lives in its own module of this package, exposing
``add_parser(subparsers) -> argparse.ArgumentParser`` whose parser has ``func`` set (via
``set_defaults``) to a function ``(args) -> int`` returning the exit code. Expected failures raise
:class:`~nightcrew.errors.NightcrewError`; they are printed as one line (exit 2 for
:class:`~nightcrew.errors.ConfigError`, else 1), with a traceback only under ``--debug``.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys
from collections.abc import Sequence

from nightcrew import __version__
from nightcrew.errors import ConfigError, NightcrewError

__all__ = ["main"]

#: Subcommand modules, in the order ``--help`` lists them.
SUBCOMMANDS = [
    "run",
    "check",
    "modules",
    "call",
    "events",
    "shell",
    "console",
    "server",
    "sim",
    "reduce",
    "tasks",
    "flats",
    "report",
    "alpaca",
    "catalogue",
]


def build_parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The parser; with ``argv`` naming a subcommand, only that subcommand's module is imported.

    Importing every subcommand costs ~1 s (``sim`` pulls in astropy), which a ``nightcrew run``
    of one module should not pay; ``--help`` and unknown commands still see them all.
    """
    parser = argparse.ArgumentParser(prog="nightcrew", description="Observatory control system.")
    parser.add_argument("--version", action="version", version=f"nightcrew {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks and debug logging")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    # Global options take no values, so the first other word is the subcommand.
    command = next((word for word in argv or () if not word.startswith("-")), None)
    for name in [command] if command in SUBCOMMANDS else SUBCOMMANDS:
        module = importlib.import_module(f"nightcrew.cli.{name}")
        module.add_parser(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    words = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(words)
    args = parser.parse_args(words)
    logging.basicConfig(
        level=logging.DEBUG if args.debug else logging.INFO,
        format="%(asctime)s %(levelname)-7s %(name)s: %(message)s",
    )
    try:
        code: int = args.func(args)
        return code
    except NightcrewError as exc:
        if args.debug:
            raise
        print(f"nightcrew: error: {exc}", file=sys.stderr)
        return 2 if isinstance(exc, ConfigError) else 1
    except KeyboardInterrupt:
        return 130
