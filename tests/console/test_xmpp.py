"""The console against an observatory on Prosody: in this process, and as ``nightcrew console --comm``."""

from __future__ import annotations

import asyncio
import os
import re
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from nightcrew.events import TestEvent
from nightcrew.modules.console import WebConsole
from nightcrew.modules.sim import SimTelescope

# The session's Prosody and a room per test, as tests/comm has them (imported to be found here).
from tests.comm.conftest import Network, prosody_network, prosody_server  # noqa: F401
from tests.comm.xmpp_servers import DOMAIN, XmppServer

from .conftest import ACCOUNTS, OPERATOR, OPERATOR_PASSWORD, PATIENCE, SITE, ApiClient, open_socket

pytestmark = pytest.mark.xmpp
REPOSITORY = Path(__file__).resolve().parents[2]
PLEIADES = (56.75, 24.12)


@pytest.fixture
def xmpp(request: pytest.FixtureRequest) -> Network:
    """Modules on the session's Prosody, in a room of this test's own."""
    network: Network = request.getfixturevalue("prosody_network")
    return network


async def test_the_console_on_xmpp_lists_calls_and_relays(
    xmpp: Network, clients: Callable[[str], ApiClient]
) -> None:
    telescope = await xmpp.start(SimTelescope, "telescope", site=SITE, init_time=0.0)
    console = await xmpp.start(
        WebConsole, "console", port=0, accounts=ACCOUNTS, status_interval=0.1, site=SITE
    )
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    socket = await open_socket(client)
    modules = {m["name"]: m for m in socket.messages[0]["modules"]}
    assert "ITelescope" in modules["telescope"]["interfaces"]
    assert await client.call("telescope", "init") == (200, {"result": None})
    status, body = await client.call("telescope", "move_altaz", -20.0, 0.0)  # below the horizon
    assert status == 502 and body["error"]["class"] == "MoveError" and body["error"]["module"] == "telescope"
    sender = await xmpp.start(WebConsole, "sender", port=0, accounts=ACCOUNTS)
    await socket.wait_for(
        lambda m: m["type"] == "module_joined" and m["module"]["name"] == "sender", "the sender joining"
    )
    await sender.comm.send_event(TestEvent(message="over xmpp"))
    event = await socket.wait_for(lambda m: m["type"] == "event" and m["event"] == "TestEvent", "the event")
    assert event["sender"] == "sender" and event["fields"] == {"message": "over xmpp"}
    await telescope.close()
    await socket.wait_for(
        lambda m: m == {"type": "module_left", "name": "telescope"}, "the telescope leaving"
    )


def write_comm(path: Path, server: XmppServer, name: str, room: str) -> Path:
    account = server.account(name)
    path.write_text(
        "class: nightcrew.comm.xmpp.XmppComm\n"
        f"jid: {name}@{DOMAIN}\n"
        f"password: {account.password}\n"
        f"server: {server.address}\n"
        f"room: {room}\n"
        f"ca_file: {server.ca_file}\n"
    )
    return path


async def test_nightcrew_console_serves_an_observatory_on_xmpp(
    xmpp: Network, tmp_path: Path, clients: Callable[[str], ApiClient]
) -> None:
    assert xmpp.server is not None
    await xmpp.start(SimTelescope, "telescope", site=SITE, init_time=0.0)
    comm = write_comm(tmp_path / "console-comm.yaml", xmpp.server, "console", xmpp.room)
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "nightcrew",
        "console",
        "--comm",
        str(comm),
        "--port",
        "0",
        cwd=REPOSITORY,
        env={**os.environ, "NIGHTCREW_CONSOLE_PASSWORD": "from-the-environment"},
        stdin=asyncio.subprocess.DEVNULL,
        stdout=asyncio.subprocess.DEVNULL,
        stderr=asyncio.subprocess.PIPE,
    )
    try:
        assert process.stderr is not None
        async with asyncio.timeout(PATIENCE):
            line = ""
            while "nightcrew console at" not in line:
                line = (await process.stderr.readline()).decode()
                assert line, "the console ended before serving"
        found = re.search(r"(http://127\.0\.0\.1:\d+/); log in as 'operator' with password (\S+)", line)
        assert found is not None and found.group(2) == "from-the-environment"
        client = clients(found.group(1))
        assert (await client.login("operator", "from-the-environment"))[0] == 200
        modules = (await client.get("/api/modules"))[1]["modules"]
        assert [m["name"] for m in modules] == ["telescope"]
        assert await client.call("telescope", "get_motion_status") == (200, {"result": "parked"})
    finally:
        if process.returncode is None:
            process.terminate()
        async with asyncio.timeout(PATIENCE):
            await process.wait()
    assert process.returncode == 0
