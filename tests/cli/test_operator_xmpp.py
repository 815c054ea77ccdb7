"""The operator commands as real processes against a module on Prosody.

A Calculator runs in this test process on XmppComm; ``nightcrew modules|call|events|shell`` run as
subprocesses with a comm description file of their own, as an operator would use them.
"""

from __future__ import annotations

import asyncio
import os
import sys
import time
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from nightcrew.events import TestEvent

# The session's Prosody and a room per test, as tests/comm has them (imported to be found here).
from tests.comm.conftest import Network, prosody_network, prosody_server  # noqa: F401
from tests.comm.sample import Calculator
from tests.comm.xmpp_servers import DOMAIN, XmppServer

pytestmark = pytest.mark.xmpp
REPOSITORY = Path(__file__).resolve().parents[2]
#: Wall seconds any one command may take (they need well under 5).
COMMAND_TIMEOUT = 30.0


def write_operator_comm(path: Path, server: XmppServer, room: str, password: str | None = None) -> Path:
    """A comm description file for the account ``operator`` (the file ``--comm`` takes)."""
    account = server.account("operator")
    path.write_text(
        "class: nightcrew.comm.xmpp.XmppComm\n"
        f"jid: operator@{DOMAIN}\n"
        f"password: {password or account.password}\n"
        f"server: {server.address}\n"
        f"room: {room}\n"
        f"ca_file: {server.ca_file}\n"
    )
    return path


class Finished:
    """What a finished command wrote and returned."""

    def __init__(self, code: int, stdout: str, stderr: str) -> None:
        self.code, self.stdout, self.stderr = code, stdout, stderr


async def start(*args: str, stdin: bytes | None = None) -> asyncio.subprocess.Process:
    # Started with asyncio so that this loop keeps serving the Calculator meanwhile.
    return await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "nightcrew",
        *args,
        cwd=REPOSITORY,
        env=os.environ.copy(),
        stdin=asyncio.subprocess.PIPE if stdin is not None else asyncio.subprocess.DEVNULL,
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )


async def finish(process: asyncio.subprocess.Process, stdin: bytes | None = None) -> Finished:
    try:
        stdout, stderr = await asyncio.wait_for(process.communicate(stdin), COMMAND_TIMEOUT)
    except TimeoutError:
        process.kill()
        await process.wait()
        raise
    assert process.returncode is not None
    return Finished(process.returncode, stdout.decode(), stderr.decode())


async def nightcrew(*args: str, stdin: bytes | None = None) -> Finished:
    return await finish(await start(*args, stdin=stdin), stdin)


@pytest.fixture
def network(request: pytest.FixtureRequest) -> Network:
    """Modules in a room of this test's own on the session's Prosody (tests/comm's fixture)."""
    prosody: Network = request.getfixturevalue("prosody_network")
    return prosody


@pytest.fixture
async def op_file(network: Network, tmp_path: Path) -> AsyncIterator[str]:
    """A Calculator online in the test's room, and the operator's comm file for that room."""
    assert network.server is not None
    await network.start(Calculator, "calc", label="Calculator")
    yield str(write_operator_comm(tmp_path / "op.yaml", network.server, network.room))


async def test_modules_lists_the_calculator_ready_with_its_interfaces(op_file: str) -> None:
    done = await nightcrew("modules", "--comm", op_file)
    assert (done.code, done.stderr) == (0, "")
    (line,) = done.stdout.splitlines()
    name, state, listed = line.removesuffix(" (Calculator)").split(maxsplit=2)
    assert (name, state) == ("calc", "ready")
    interfaces = listed.split(", ")
    assert interfaces == sorted(interfaces)
    assert {"ICalculator", "ISlow", "IModule", "IConfig"} <= set(interfaces)


async def test_call_prints_the_result(op_file: str) -> None:
    done = await nightcrew("call", "calc.add", "2", "3.5", "--comm", op_file)
    assert (done.code, done.stdout, done.stderr) == (0, "5.5\n", "")


async def test_a_remote_error_or_an_absent_module_is_one_line_and_exit_1(op_file: str) -> None:
    done = await nightcrew("call", "calc.divide", "1", "0", "--comm", op_file)
    assert (done.code, done.stdout) == (1, "")
    assert done.stderr.splitlines() == ["nightcrew: error: calc: division by zero"]
    done = await nightcrew("call", "dome.open_roof", "--comm", op_file)
    assert (done.code, done.stdout) == (1, "")
    assert done.stderr.splitlines() == ["nightcrew: error: module 'dome' is not online"]


async def test_events_prints_an_event_while_other_commands_use_the_same_file(
    network: Network, op_file: str
) -> None:
    sender = await network.start(Calculator, "sender")
    watcher = await start("events", "--type", "TestEvent", "--count", "1", "--comm", op_file)
    try:
        deadline = time.monotonic() + COMMAND_TIMEOUT
        while "operator" not in sender.comm.clients:
            assert time.monotonic() < deadline, "the watcher did not join"
            await asyncio.sleep(0.1)
        # A second command with the same account must not take the watcher's session over.
        done = await nightcrew("call", "calc.add", "1", "2", "--comm", op_file)
        assert (done.code, done.stdout) == (0, "3.0\n")
        # The watcher registers right after joining; send until it has printed one and left.
        async with asyncio.timeout(COMMAND_TIMEOUT):
            while watcher.returncode is None:
                await sender.comm.send_event(TestEvent(message="hello operator"))
                await asyncio.sleep(0.2)
    finally:
        done = await finish(watcher)
    assert (done.code, done.stderr) == (0, "")
    (line,) = done.stdout.splitlines()
    assert line.split(" ", 3)[1:] == ["sender", "TestEvent", '{"message": "hello operator"}']


async def test_shell_runs_piped_lines_until_end_of_input(op_file: str) -> None:
    lines = b"calc.add(2, 3.5)\nmodules\ncalc.divide(1, 0)\ncalc.measure('red')\n"
    done = await nightcrew("shell", "--comm", op_file, stdin=lines)
    assert (done.code, done.stderr) == (0, "")
    output = done.stdout.replace("nightcrew> ", "").splitlines()
    assert output[0] == "5.5"
    assert output[1].startswith("calc  ready    ")
    assert output[2] == "error: InvalidArgumentError: calc: division by zero"
    assert output[3] == '{"value": 42.5, "unit": "adu", "colour": "red"}'


async def test_a_wrong_password_is_one_line_and_a_non_zero_exit(network: Network, tmp_path: Path) -> None:
    assert network.server is not None
    op_file = write_operator_comm(tmp_path / "op.yaml", network.server, network.room, password="wrong")
    for command in (["modules"], ["call", "calc.add", "1", "2"], ["events"], ["shell"]):
        done = await nightcrew(*command, "--comm", str(op_file), stdin=b"")
        assert done.code == 1, (command, done.stderr)
        assert done.stdout.strip() == ""
        assert done.stderr.splitlines() == [
            f"nightcrew: error: operator@{DOMAIN}: login refused (wrong password or unknown account)"
        ], command
