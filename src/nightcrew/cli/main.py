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
SUBCOMMANDS = ["run", "check", "modules", "call", "events", "shell", "server", "sim", "reduce", "tasks", "flats"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="nightcrew", description="Observatory control system.")
    parser.add_argument("--version", action="version", version=f"nightcrew {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks and debug logging")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in SUBCOMMANDS:
        module = importlib.import_module(f"nightcrew.cli.{name}")
        module.add_parser(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
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
