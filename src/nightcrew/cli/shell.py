"""``nightcrew shell --comm FILE.yaml``: an interactive prompt for ``module.method(arguments)``.

Arguments are Python literals (``camera.set_exposure_time(2.5)``, ``filters.set_filter("R")``).
Tab completes module and method names. ``modules`` lists the online modules, ``exit`` (or Ctrl-D)
leaves.
"""

from __future__ import annotations

import argparse
import asyncio
from collections.abc import Awaitable, Callable
from typing import Any

from nightcrew.cli._operator import (
    add_comm_argument,
    call_method,
    format_value,
    list_modules,
    load_comm,
    method_names,
    operator_module,
    parse_shell_call,
    quiet_module_logs,
)
from nightcrew.cli.modules import format_table
from nightcrew.comm.base import Comm
from nightcrew.errors import NightcrewError

__all__ = ["ShellCompleter", "add_parser", "execute_line", "run_shell"]

PROMPT = "nightcrew> "


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "shell", help="interactive prompt for calling modules", description=__doc__.split("\n\n", 1)[1]
    )
    add_comm_argument(parser)
    parser.set_defaults(func=_command)
    return parser


class ShellCompleter:
    """Completes ``mod`` → ``module.`` and ``module.me`` → ``module.method(`` (readline protocol)."""

    def __init__(self) -> None:
        self.methods: dict[str, list[str]] = {}

    async def refresh(self, comm: Comm) -> None:
        methods = {}
        for name in comm.clients:
            try:
                methods[name] = await method_names(comm, name)
            except NightcrewError:
                continue
        self.methods = methods

    def candidates(self, text: str) -> list[str]:
        module, dot, prefix = text.partition(".")
        if dot:
            return [f"{module}.{m}(" for m in self.methods.get(module, []) if m.startswith(prefix)]
        return sorted(f"{name}." for name in self.methods if name.startswith(text))

    def complete(self, text: str, state: int) -> str | None:
        found = self.candidates(text)
        return found[state] if state < len(found) else None


async def execute_line(comm: Comm, line: str) -> str:
    """Run one shell line; return what to print (results as JSON, errors as one line)."""
    line = line.strip()
    if not line:
        return ""
    if line == "modules":
        return format_table(await list_modules(comm))
    if line == "help":
        return __doc__.split("\n\n", 1)[1].strip() if __doc__ else ""
    try:
        target, args = parse_shell_call(line)
        return format_value(await call_method(comm, target, args))
    except NightcrewError as exc:
        return f"error: {type(exc).__name__}: {exc}"


async def run_shell(
    comm: Comm, read_line: Callable[[str], Awaitable[str | None]], write: Callable[[str], None]
) -> None:
    """The read-eval-print loop; ``read_line`` returns None at end of input."""
    completer = ShellCompleter()
    _install_readline(completer)
    while True:
        await completer.refresh(comm)
        line = await read_line(PROMPT)
        if line is None or line.strip() in ("exit", "quit"):
            return
        output = await execute_line(comm, line)
        if output:
            write(output)


def _install_readline(completer: ShellCompleter) -> None:
    try:
        import readline
    except ImportError:  # not on every platform; the shell works without completion
        return
    readline.set_completer(completer.complete)
    readline.set_completer_delims(" \t\n(),")
    readline.parse_and_bind("tab: complete")


async def _read_line(prompt: str) -> str | None:
    try:
        return await asyncio.to_thread(input, prompt)
    except EOFError:
        return None


async def _shell(comm_file: str | None) -> None:
    async with operator_module(load_comm(comm_file)) as operator:
        await run_shell(operator.comm, _read_line, print)


def _command(args: argparse.Namespace) -> int:
    with quiet_module_logs(args.debug):
        asyncio.run(_shell(args.comm))
    print()
    return 0
