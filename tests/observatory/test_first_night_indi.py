"""The first night of an observatory ``nightcrew init`` wrote for the indi-bin simulators, shorter:
init → server → check → up → one target an hour east of the meridian → the dome opens, the frames
are written, the task is done → ``nightcrew up`` stopped: the dome closes and the mount parks (read
back from indiserver).

indiserver runs in a network namespace of its own and is reached like a remote server; the site
is where it is 22:00 now (see night.py). Without indi-bin, root or Prosody the test skips, except
under CI=true.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest

from nightcrew.astro import local_sidereal_time
from nightcrew.bridges.indi.client import IndiClient
from nightcrew.testing.indi import IndiServer
from tests.comm.xmpp_servers import require_command

from .night import LATITUDE, evening_longitude, running_observatory, task_file, wait
from .simulators import run_indi_simulators

pytestmark = pytest.mark.xmpp
NIGHT_TIMEOUT = 600.0  # wall seconds on a busy machine
EAST_OF_MERIDIAN = 15.0  # degrees of right ascension: one hour before the target culminates


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
    deadline = time.monotonic() + NIGHT_TIMEOUT
    devices = ["--indi", f"{indi_server.host}:{indi_server.port}"]
    with running_observatory(tmp_path, devices, longitude, deadline) as night:
        # An hour east of the meridian: the frames end long before it, so no meridian flip (flips are
        # tested in tests/robotic) spends half a minute of real-time slewing here.
        ra = (float(local_sidereal_time(now.timestamp(), longitude)) + EAST_OF_MERIDIAN) % 360
        task_file(night.directory / "target.yaml", "east field", ra, LATITUDE, "Red", count=2)
        night("tasks", "--db", "tasks.sqlite", "add", "target.yaml")
        wait(lambda: set(night.tasks().values()) == {"COMPLETED"}, deadline, "the task done")
        assert len(night.science_frames()) >= 2
    assert asyncio.run(switch_on(indi_server, "Dome Simulator", "DOME_SHUTTER")) == "SHUTTER_CLOSE"
    assert asyncio.run(switch_on(indi_server, "Telescope Simulator", "TELESCOPE_PARK")) == "PARK"
