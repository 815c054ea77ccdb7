"""``nightcrew modules --comm FILE.yaml``: list the online modules with state and interfaces.

A frozen process still looks online to the others (its last presence stays in the room until the
server notices), so where a supervisor runs on this computer (``nightcrew up``, its default
socket or ``$NIGHTCREW_SUPERVISOR_SOCKET``) its word wins: a module it calls ``frozen`` is shown so.
"""

from __future__ import annotations

import argparse
import asyncio
import dataclasses
from typing import Any

from nightcrew.cli._operator import (
    ModuleInfo,
    add_comm_argument,
    list_modules,
    load_comm,
    operator_module,
    quiet_module_logs,
)
from nightcrew.supervisor import SupervisorError, default_socket_path, send_request

__all__ = ["add_parser", "format_table"]

_SUPERVISOR_ANSWER = 5.0  # seconds: a supervisor that does not answer is left out, not waited for


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
        infos = await list_modules(operator.comm)
    frozen = await _frozen_here()
    return format_table([dataclasses.replace(i, state="frozen") if i.name in frozen else i for i in infos])


async def _frozen_here() -> set[str]:
    """The modules this computer's supervisor calls frozen (none without a supervisor)."""
    try:
        request = send_request(default_socket_path(), {"command": "status", "module": None})
        reply = await asyncio.wait_for(request, _SUPERVISOR_ANSWER)
    except (SupervisorError, OSError, TimeoutError):
        return set()
    return {str(m["name"]) for m in reply["modules"] if m.get("state") == "frozen"}


def _command(args: argparse.Namespace) -> int:
    with quiet_module_logs(args.debug):
        print(asyncio.run(_list(args.comm)))
    return 0
