"""The multi-host observatory and the test's driver of its night (see observatory_hosts.py)."""

from __future__ import annotations

import shutil
from collections.abc import AsyncIterator, Iterator
from pathlib import Path

import pytest

from nightcrew.clock import AcceleratedClock
from nightcrew.comm.xmpp import XmppComm
from nightcrew.modules import Module
from nightcrew.testing.hosts import hosts_missing
from nightcrew.testing.samba import samba_missing
from nightcrew.testing.sshd import sshd_missing
from tests.hosts.night_driver import NightDriver
from tests.hosts.observatory_hosts import (
    CLOCK_SPEED,
    CLOCK_START,
    DOMAIN,
    PASSWORD,
    ROOM,
    Observatory,
    start,
    stop,
)
from tests.vfs.remote_servers import require


@pytest.fixture
def observatory(tmp_path: Path) -> Iterator[Observatory]:
    prosody = [] if shutil.which("prosody") else ["prosody (apt-get install prosody)"]
    require(hosts_missing() + sshd_missing() + samba_missing() + prosody)
    built = start(tmp_path)
    try:
        yield built
    finally:
        problems = stop(built)
    assert not problems, "\n".join(problems)


@pytest.fixture
async def night(observatory: Observatory) -> AsyncIterator[NightDriver]:
    comm = XmppComm(
        f"operator@{DOMAIN}", PASSWORD, server=observatory.xmpp_server, room=ROOM, ca_file=observatory.ca_file
    )
    driver = Module(comm=comm, clock=AcceleratedClock(CLOCK_START, speed=CLOCK_SPEED))
    await driver.open()
    try:
        yield NightDriver(observatory, driver)
    finally:
        await driver.close()
