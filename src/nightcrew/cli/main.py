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
from pathlib import Path

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
    "archive",
    "solver",
    "tasks",
    "flats",
    "pointing",
    "report",
    "alpaca",
    "init",
    "up",
    "status",
    "start",
    "stop",
    "restart",
    "logs",
    "systemd",
    "audit",
    "catalogue",
]


#: Global options that take a value.
_VALUED = frozenset({"--log-format", "--log-file", "--log-file-format"})


def build_parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The parser; with ``argv`` naming a subcommand, only that subcommand's module is imported.

    Importing every subcommand costs ~1 s (``sim`` pulls in astropy), which a ``nightcrew run``
    of one module should not pay; ``--help`` and unknown commands still see them all.
    """
    parser = argparse.ArgumentParser(prog="nightcrew", description="Observatory control system.")
    parser.add_argument("--version", action="version", version=f"nightcrew {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks and debug logging")
    parser.add_argument(
        "--log-format",
        choices=("text", "json", "systemd"),
        default="text",
        help="stderr log lines: text, JSON lines, or with journald's level prefixes (systemd)",
    )
    parser.add_argument("--log-file", metavar="FILE", help="also log to FILE, rotated at 10 MB (5 kept)")
    parser.add_argument("--log-file-format", choices=("text", "json"), default="text", help="format of FILE")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    # The first word that is neither a global option nor its value is the subcommand.
    words = list(argv or ())
    command = next(
        (w for i, w in enumerate(words) if not w.startswith("-") and (i == 0 or words[i - 1] not in _VALUED)),
        None,
    )
    for name in [command] if command in SUBCOMMANDS else SUBCOMMANDS:
        module = importlib.import_module(f"nightcrew.cli.{name}")
        module.add_parser(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    words = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(words)
    args = parser.parse_args(words)
    from nightcrew.supervisor import configure_logging

    configure_logging(
        logging.DEBUG if args.debug else logging.INFO,
        console_format=args.log_format,
        log_file=Path(args.log_file) if args.log_file else None,
        file_format=args.log_file_format,
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
