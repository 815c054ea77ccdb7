"""``nightcrew events [--type NAME ...] [--count N] --comm FILE.yaml``: print events as they arrive.

One line per event: clock time, sender, event name and its fields as JSON. Runs until Ctrl-C, or
until ``--count`` events were printed.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
from collections.abc import Callable
from typing import Any

from nightcrew.cli._operator import (
    add_comm_argument,
    format_value,
    load_comm,
    operator_module,
    quiet_module_logs,
)
from nightcrew.comm.base import Comm
from nightcrew.errors import InvalidArgumentError
from nightcrew.events.base import Event, event_by_name, event_names

__all__ = ["add_parser", "event_types", "watch_events"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "events", help="print events as they arrive", description=__doc__.split("\n\n", 1)[1]
    )
    parser.add_argument("--type", action="append", dest="types", metavar="NAME", help="only this event type")
    parser.add_argument("--count", type=int, default=None, help="stop after this many events")
    add_comm_argument(parser)
    parser.set_defaults(func=_command)
    return parser


def event_types(names: list[str] | None) -> list[type[Event]]:
    """The event classes called ``names`` (all known ones when None)."""
    if not names:
        names = event_names()
    types = []
    for name in names:
        event_type = event_by_name(name)
        if event_type is None:
            raise InvalidArgumentError(f"unknown event type '{name}' (known: {', '.join(event_names())})")
        types.append(event_type)
    return types


async def watch_events(
    comm: Comm, types: list[type[Event]], show: Callable[[str], None], count: int | None = None
) -> None:
    """Register for ``types`` and hand a line per event to ``show``; return after ``count`` events."""
    enough = asyncio.Event()
    seen = 0

    async def on_event(event: Event, sender: str) -> None:
        nonlocal seen
        if count is not None and seen >= count:
            return
        seen += 1
        stamp = comm.clock.now().strftime("%Y-%m-%dT%H:%M:%S")
        show(f"{stamp} {sender} {event.event_name()} {format_value(event.to_dict())}")
        if count is not None and seen >= count:
            enough.set()

    for event_type in types:
        await comm.register_event(event_type, on_event)
    await enough.wait()


async def _watch(comm_file: str | None, names: list[str] | None, count: int | None) -> None:
    types = event_types(names)
    async with operator_module(load_comm(comm_file)) as operator:

        def show(line: str) -> None:
            print(line, flush=True)

        await watch_events(operator.comm, types, show, count)


def _command(args: argparse.Namespace) -> int:
    try:
        with quiet_module_logs(args.debug):
            asyncio.run(_watch(args.comm, args.types, args.count))
    except KeyboardInterrupt:
        print(file=sys.stderr)
    return 0
