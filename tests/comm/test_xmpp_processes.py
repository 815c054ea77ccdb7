"""Modules in separate ``nightcrew run`` processes on one Prosody: calls and events across them."""

from __future__ import annotations

import asyncio
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from nightcrew.events import TestEvent
from nightcrew.modules import Module
from nightcrew.testing import modules_ready

from .conftest import Network
from .process_modules import IPointAndShoot
from .xmpp_servers import DOMAIN, XmppServer

pytestmark = pytest.mark.xmpp
REPO = Path(__file__).resolve().parents[2]


def write_config(path: Path, cls: str, name: str, server: XmppServer, room: str, **extra: str) -> Path:
    server.account(name)
    lines = [f"class: tests.comm.process_modules.{cls}"]
    lines += [f"{key}: {value}" for key, value in extra.items()]
    lines += [
        "comm:",
        "  class: nightcrew.comm.xmpp.XmppComm",
        f"  jid: {name}@{DOMAIN}",
        f"  password: ${{{name.upper()}_PASSWORD}}",
        f"  server: {server.address}",
        f"  room: {room}",
        f"  ca_file: {server.ca_file}",
        "  policy: open",  # about processes on XMPP, not access (test_closed_default.py)
    ]
    path.write_text("\n".join(lines) + "\n")
    return path


def nightcrew(*args: str, env: dict[str, str]) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "nightcrew", *args],
        cwd=REPO,  # so that tests.comm.process_modules can be imported
        env={**os.environ, **env},
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


async def test_two_processes_call_each_other_and_exchange_events(
    prosody_network: Network, tmp_path: Path
) -> None:
    server = prosody_network.server
    assert server is not None
    room = prosody_network.room
    telescope = write_config(tmp_path / "telescope.yaml", "MountForTests", "telescope", server, room)
    camera = write_config(tmp_path / "camera.yaml", "ImagerForTests", "camera", server, room)
    env = {"TELESCOPE_PASSWORD": "secret-for-tests", "CAMERA_PASSWORD": "secret-for-tests"}
    processes = [nightcrew("run", str(telescope), env=env), nightcrew("run", str(camera), env=env)]
    try:
        operator = await prosody_network.start(Module, "operator")
        heard: list[tuple[TestEvent, str]] = []
        got_event = asyncio.Event()

        async def on_test_event(event: TestEvent, sender: str) -> None:
            heard.append((event, sender))
            got_event.set()

        await operator.comm.register_event(TestEvent, on_test_event)
        deadline = time.monotonic() + 20
        # In the room is not enough: a module joins it before it is ready.
        while not await modules_ready(operator, ["telescope", "camera"]):
            assert all(p.poll() is None for p in processes), [p.communicate()[1] for p in processes]
            assert time.monotonic() < deadline, "modules did not come online and ready"
            await asyncio.sleep(0.1)

        mount = await operator.comm.proxy("telescope", IPointAndShoot)
        result = await mount.point_and_expose(45)
        assert result == "image-1 at 45 deg; heard 'exposed image-1 from camera'"
        await asyncio.wait_for(got_event.wait(), 5)
        assert heard[0] == (TestEvent(message="exposed image-1"), "camera")
    finally:
        for process in processes:
            process.terminate()
    for process in processes:
        _, stderr = process.communicate(timeout=10)
        assert process.returncode == 0, stderr


def test_run_with_a_wrong_password_prints_one_line_and_exits_1(
    prosody_server: XmppServer, tmp_path: Path
) -> None:
    config = write_config(tmp_path / "camera.yaml", "ImagerForTests", "camera", prosody_server, "nightcrew")
    process = nightcrew("run", str(config), env={"CAMERA_PASSWORD": "wrong"})
    _, stderr = process.communicate(timeout=30)
    assert process.returncode == 1
    assert stderr.splitlines() == [
        "nightcrew: error: camera@observatory.test: login refused (wrong password or unknown account)"
    ]
