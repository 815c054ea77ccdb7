"""``nightcrew modules --comm FILE.yaml``: list the online modules with state and interfaces."""

from __future__ import annotations

import argparse
import asyncio
from typing import Any

from nightcrew.cli._operator import (
    ModuleInfo,
    add_comm_argument,
    list_modules,
    load_comm,
    operator_module,
    quiet_module_logs,
)

__all__ = ["add_parser", "format_table"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser("modules", help="list online modules")
    add_comm_argument(parser)
    parser.set_defaults(func=_command)
    return parser


def format_table(infos: list[ModuleInfo]) -> str:
    """One line per module: name, state, interfaces (label where it differs from the name)."""
    if not infos:
        return "no modules online"
    width = max(len(i.name) for i in infos)
    lines = []
    for info in infos:
        label = f" ({info.label})" if info.label != info.name else ""
        lines.append(f"{info.name:<{width}}  {info.state:<8} {', '.join(info.interfaces)}{label}")
    return "\n".join(lines)


async def _list(comm_file: str | None) -> str:
    # The operator module knows who is online once open (on XMPP, the room's occupant list and
    # the pyobs modules' presence and discovery): no waiting for a time.
    async with operator_module(load_comm(comm_file)) as operator:
        return format_table(await list_modules(operator.comm))


def _command(args: argparse.Namespace) -> int:
    with quiet_module_logs(args.debug):
        print(asyncio.run(_list(args.comm)))
    return 0
