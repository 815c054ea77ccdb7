"""The operator commands' logic, on an in-process network (over XMPP in tests/comm)."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator

import pytest

from nightcrew.cli._operator import (
    call_method,
    list_modules,
    operator_module,
    parse_cli_arguments,
    parse_shell_call,
)
from nightcrew.cli.events import event_types, watch_events
from nightcrew.cli.modules import format_table
from nightcrew.cli.shell import ShellCompleter, execute_line, run_shell
from nightcrew.comm.base import Comm
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.errors import InvalidArgumentError, RemoteError
from nightcrew.events import TestEvent
from nightcrew.modules import Module

from ..comm.sample import Calculator


@pytest.fixture
async def operator() -> AsyncIterator[Comm]:
    network = LocalNetwork()
    calc = Calculator(comm=LocalComm("calc", network=network), label="Calculator")
    await calc.open()
    async with operator_module(LocalComm("operator", network=network)) as module:
        yield module.comm
    await calc.close()


async def test_modules_lists_state_label_and_interfaces(operator: Comm) -> None:
    (info,) = await list_modules(operator)
    assert (info.name, info.state, info.label) == ("calc", "ready", "Calculator")
    assert {"ICalculator", "ISlow", "IModule", "IConfig"} <= set(info.interfaces)
    assert format_table([info]).startswith("calc  ready    ")


async def test_call_with_command_line_arguments(operator: Comm) -> None:
    assert await call_method(operator, "calc.add", parse_cli_arguments(["2", "3.5"])) == 5.5
    assert await call_method(operator, "calc.measure", parse_cli_arguments(["red"])) == {
        "value": 42.5,
        "unit": "adu",
        "colour": "red",
    }
    with pytest.raises(InvalidArgumentError, match=r"divide\(\): argument 'b': expected number, got string"):
        await call_method(operator, "calc.divide", parse_cli_arguments(["1", "zero"]))
    with pytest.raises(InvalidArgumentError, match=r"'calc' is not MODULE\.METHOD"):
        await call_method(operator, "calc", [])


def test_cli_arguments_are_yaml_scalars() -> None:
    assert parse_cli_arguments(["3", "1.5", "true", "R", "[1, 2]", "{a: 1}", ""]) == [
        3,
        1.5,
        True,
        "R",
        [1, 2],
        {"a": 1},
        "",
    ]
    with pytest.raises(InvalidArgumentError, match="cannot read argument"):
        parse_cli_arguments(["[1, 2"])


def test_shell_lines_are_python_calls_with_literal_arguments() -> None:
    assert parse_shell_call(' filters.set_filter("R") ') == ("filters.set_filter", ["R"])
    assert parse_shell_call("calc.add(1, 2.5)") == ("calc.add", [1, 2.5])
    with pytest.raises(InvalidArgumentError, match=r"expected module.method\(arguments\)"):
        parse_shell_call("add(1, 2)")
    with pytest.raises(InvalidArgumentError, match="arguments must be literals"):
        parse_shell_call("calc.add(x, 2)")
    with pytest.raises(InvalidArgumentError, match="keyword arguments are not supported"):
        parse_shell_call("calc.add(a=1)")
    with pytest.raises(InvalidArgumentError, match="not a call"):
        parse_shell_call("calc.add(")


async def test_shell_session_with_completion(operator: Comm) -> None:
    lines = iter(["calc.add(40, 2)", "calc.divide(1, 0)", "calc.nope()", "modules", "exit", "never read"])
    output: list[str] = []

    async def read_line(prompt: str) -> str | None:
        return next(lines)

    await run_shell(operator, read_line, output.append)
    assert output[0] == "42.0"
    assert output[1] == "error: InvalidArgumentError: calc: division by zero"
    assert output[2].startswith("error: InterfaceError: calc: no method 'nope'")
    assert output[3].startswith("calc ")
    assert len(output) == 4

    completer = ShellCompleter()
    await completer.refresh(operator)
    assert completer.candidates("ca") == ["calc."]
    assert completer.candidates("calc.di") == ["calc.divide("]
    assert completer.complete("calc.a", 0) == "calc.add(" and completer.complete("calc.a", 1) is None
    assert await execute_line(operator, "") == ""


async def test_events_are_printed_one_line_each(operator: Comm) -> None:
    lines: list[str] = []
    watcher = asyncio.create_task(watch_events(operator, event_types(["TestEvent"]), lines.append, count=2))
    await asyncio.sleep(0.01)
    sender = Module(comm=LocalComm("sender", network=operator._network))  # type: ignore[attr-defined]
    await sender.open()
    for message in ("one", "two", "three"):
        await sender.comm.send_event(TestEvent(message=message))
    await asyncio.wait_for(watcher, 5)
    await sender.close()
    assert len(lines) == 2
    assert lines[0].endswith(' sender TestEvent {"message": "one"}')
    with pytest.raises(InvalidArgumentError, match="unknown event type 'NoSuchEvent'"):
        event_types(["NoSuchEvent"])
    assert len(event_types(None)) >= 20


async def test_unknown_module(operator: Comm) -> None:
    with pytest.raises(RemoteError, match="'ghost' is not online"):
        await call_method(operator, "ghost.add", [1])
