"""The first night of an observatory ``nightcrew init`` wrote for the indi-bin simulators, shorter:
init → server → check → up → one target → the dome opens, the frames are written, the task is done
→ ``nightcrew up`` stopped: the dome closes and the mount parks (read back from indiserver).

indiserver runs in a network namespace of its own and is reached like a remote server; the site
is where it is 22:00 now (see night.py). Without indi-bin, root or Prosody the test skips, except
under CI=true.
"""

from __future__ import annotations

import asyncio
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest

from nightcrew.astro import local_sidereal_time
from nightcrew.bridges.indi.client import IndiClient
from nightcrew.server import stop_server
from nightcrew.testing.indi import IndiServer
from nightcrew.testing.processes import free_port
from tests.comm.xmpp_servers import require_command

from .night import LATITUDE, Night, evening_longitude, task_file, wait
from .simulators import run_indi_simulators

pytestmark = pytest.mark.xmpp
NIGHT_TIMEOUT = 600.0  # wall seconds on a busy machine


@pytest.fixture
def indi_server(tmp_path: Path) -> Iterator[IndiServer]:
    require_command("prosody", "prosody")
    yield from run_indi_simulators(tmp_path / "indiserver")


async def switch_on(server: IndiServer, device: str, name: str) -> str:
    """The member of a switch vector that is on, as indiserver reports it."""
    client = IndiClient(server.host, server.port, devices=[device])
    await client.open()
    try:
        vector = await client.wait_defined(device, name, within=30)
        return next(member for member, value in vector.members.items() if value is True)
    finally:
        await client.close()


@pytest.mark.timeout(900)  # a night in real time (a few minutes when idle)
def test_first_night_on_indi_simulators(indi_server: IndiServer, tmp_path: Path) -> None:
    now = datetime.now(UTC)
    longitude = evening_longitude(now)
    directory = tmp_path / "observatory"
    environment = {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}:{os.environ['PATH']}",
        "NIGHTCREW_SUPERVISOR_SOCKET": str(tmp_path / "supervisor.sock"),
        "NIGHTCREW_COMM": "operator.yaml",
    }
    xmpp_port = free_port()
    night = Night(tmp_path, environment)
    night(
        "init", str(directory), "--non-interactive", "--indi", f"{indi_server.host}:{indi_server.port}",
        "--latitude", str(LATITUDE), "--longitude", str(longitude),
        "--xmpp-server", f"127.0.0.1:{xmpp_port}", "--console-port", str(free_port()),
        "--good-weather-after", "0",
    )  # fmt: skip
    night.directory = directory
    up: subprocess.Popen[bytes] | None = None
    try:
        yaml_files = sorted(p.name for p in directory.glob("*.yaml"))
        night("server", "init", "xmpp", "--port", str(xmpp_port), *yaml_files)
        night("server", "start", "xmpp")
        night("check", ".")
        with open(tmp_path / "up.log", "wb") as log:
            up = subprocess.Popen(
                [sys.executable, "-m", "nightcrew", "up", "."], cwd=directory, env=environment, stderr=log
            )
        deadline = time.monotonic() + NIGHT_TIMEOUT
        wait(lambda: night.status().get("mastermind", ["", ""])[1] == "running", deadline, "the modules")
        lst = float(local_sidereal_time(now.timestamp(), longitude))
        task_file(directory / "target.yaml", "zenith field", lst, LATITUDE, "Red", count=2)
        night("tasks", "--db", "tasks.sqlite", "add", "target.yaml")
        wait(lambda: set(night.tasks().values()) == {"COMPLETED"}, deadline, "the task done")
        assert len(night.science_frames()) >= 2
    finally:
        if up is not None:
            up.send_signal(signal.SIGTERM)  # modules close: the dome first, the mount parks
            up.wait(timeout=120)
        if (directory / "xmpp" / "prosody.pid").exists():
            stop_server(directory / "xmpp")
    assert up is not None and up.returncode == 0
    assert asyncio.run(switch_on(indi_server, "Dome Simulator", "DOME_SHUTTER")) == "SHUTTER_CLOSE"
    assert asyncio.run(switch_on(indi_server, "Telescope Simulator", "TELESCOPE_PARK")) == "PARK"
