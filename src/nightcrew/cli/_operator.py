"""What the operator commands (``modules``, ``call``, ``events``, ``shell``) share.

The operator joins the network as a module of its own (with no interfaces beyond IModule/IConfig),
built from a comm description file given with ``--comm`` (or ``$NIGHTCREW_COMM``). The functions
here take that module's comm, so they are the same for any transport.
"""

from __future__ import annotations

import argparse
import json
import os
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from nightcrew.cli._running import quiet_module_logs
from nightcrew.comm.base import Comm
from nightcrew.comm.calls import parse_shell_call
from nightcrew.comm.codec import encode
from nightcrew.config import build_object, load_config, parse_yaml
from nightcrew.errors import ConfigError, InvalidArgumentError, NightcrewError
from nightcrew.interfaces import IModule
from nightcrew.interfaces.base import interface_methods
from nightcrew.modules import Module

__all__ = [
    "ModuleInfo",
    "add_comm_argument",
    "call_method",
    "format_value",
    "list_modules",
    "method_names",
    "operator_module",
    "parse_cli_arguments",
    "parse_shell_call",
    "quiet_module_logs",
]


def add_comm_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--comm",
        metavar="FILE.yaml",
        default=os.environ.get("NIGHTCREW_COMM"),
        help="comm description with the operator's own account (default: $NIGHTCREW_COMM)",
    )


def load_comm(path: str | None) -> Comm:
    """The comm described in ``path`` (a file with ``class:`` and the comm's keys)."""
    if not path:
        raise ConfigError("no comm given: use --comm FILE.yaml or set NIGHTCREW_COMM")
    config = load_config(path)
    # Operator commands often run side by side with one file (``events`` in one terminal, ``call``
    # in another). On XMPP a second login with the same resource takes the first session over, so
    # each command gets a resource of its own unless the file's JID names one.
    jid = config.get("jid")
    if isinstance(jid, str) and "/" not in jid:
        config.set_located("jid", f"{jid}/operator-{os.getpid()}", config.location_of("jid"))
    comm = build_object(config, Comm)
    assert isinstance(comm, Comm)
    return comm


#: Clock seconds a command waits for a module it names that is not online (yet): one starting now.
CLIENT_WAIT = 3.0


@asynccontextmanager
async def operator_module(comm: Comm) -> AsyncIterator[Module]:
    """An opened module on ``comm`` for the operator, knowing every module online; closed on exit."""
    module = Module(comm=comm)
    await module.open()
    try:
        # A one-shot command acts at once: it must not miss peers announced just after open().
        await comm.settle()
        yield module
    finally:
        await module.close()


@dataclass(frozen=True)
class ModuleInfo:
    """One online module as ``nightcrew modules`` shows it."""

    name: str
    state: str
    label: str
    interfaces: list[str]


async def list_modules(comm: Comm) -> list[ModuleInfo]:
    """Every online module with its state, label and interfaces (state '?' if it does not answer)."""
    infos = []
    for name in sorted(comm.clients):
        try:
            interfaces = await comm.get_interface_names(name)
        except NightcrewError:
            continue  # went offline meanwhile
        state, label = comm.presence_state(name) or "?", name
        if state == "?" and IModule.__name__ in interfaces:
            try:
                module = await comm.proxy(name, IModule)
                state, label = str(await module.get_state()), await module.get_label()
            except NightcrewError:
                pass
        # Sorted: XMPP service discovery gives the features in no particular order.
        infos.append(ModuleInfo(name, state, label, sorted(interfaces)))
    return infos


async def method_names(comm: Comm, module: str) -> list[str]:
    """Remotely callable methods of ``module`` (of the interfaces this process knows) that this
    caller may call: the callee's own listing says which (it shows each caller its rights)."""
    known = interface_methods(await comm.get_interfaces(module))
    try:
        listed = set(await comm.execute(module, "system.listMethods", []))
    except NightcrewError:
        return sorted(known)  # a peer without introspection: what its interfaces declare
    return sorted(name for name in known if name in listed)


async def call_method(comm: Comm, target: str, args: list[Any]) -> Any:
    """Call ``target`` (``module.method``) with ``args``; return the wire result."""
    module, dot, method = target.partition(".")
    if not dot or not module or not method:
        raise InvalidArgumentError(f"'{target}' is not MODULE.METHOD")
    await comm.wait_for_client(module, CLIENT_WAIT)  # if not online, execute() says so
    return await comm.execute(module, method, [encode(a, f"argument {i + 1}") for i, a in enumerate(args)])


def parse_cli_arguments(texts: list[str]) -> list[Any]:
    """Command-line arguments as YAML scalars or flow lists/maps (``3``, ``1.5``, ``true``, ``[1, 2]``)."""
    values = []
    for text in texts:
        try:
            values.append(parse_yaml(text, "argument") if text else "")
        except ConfigError as exc:
            raise InvalidArgumentError(f"cannot read argument {_shorten(text)!r}: {exc.message}") from None
    return values


def format_value(value: Any) -> str:
    """A wire value as compact JSON (dates ISO, bytes as their length)."""

    def default(obj: object) -> str:
        if isinstance(obj, datetime):
            return obj.isoformat()
        if isinstance(obj, bytes):
            return f"<{len(obj)} bytes>"
        raise TypeError(type(obj).__name__)

    return json.dumps(value, default=default, ensure_ascii=False)


def _shorten(text: str, limit: int = 60) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."
