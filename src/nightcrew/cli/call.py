"""``nightcrew call MODULE.METHOD [ARGS...] --comm FILE.yaml``: call a method, print its result.

Arguments are read as YAML scalars or flow collections (``3``, ``1.5``, ``true``, ``R``,
``"[1, 2]"``). The result is printed as JSON; a remote error is printed as one line, exit 1.
"""

from __future__ import annotations

import argparse
import asyncio
from typing import Any

from nightcrew.cli._operator import (
    add_comm_argument,
    call_method,
    format_value,
    load_comm,
    operator_module,
    parse_cli_arguments,
    quiet_module_logs,
)

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "call", help="call a method of a module", description=__doc__.split("\n\n", 1)[1]
    )
    parser.add_argument("target", metavar="MODULE.METHOD")
    parser.add_argument("arguments", nargs="*", metavar="ARG")
    add_comm_argument(parser)
    parser.set_defaults(func=_command)
    return parser


async def _call(comm_file: str | None, target: str, texts: list[str]) -> str:
    args = parse_cli_arguments(texts)
    async with operator_module(load_comm(comm_file)) as operator:
        return format_value(await call_method(operator.comm, target, args))


def _command(args: argparse.Namespace) -> int:
    with quiet_module_logs(args.debug):
        print(asyncio.run(_call(args.comm, args.target, args.arguments)))
    return 0
