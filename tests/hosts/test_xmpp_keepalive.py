"""XMPP pings: a module notices a silent link to the server within seconds and reconnects.

Prosody runs on a simulated host; the test's modules reach it over a link that is cut silently
(nobody is told, packets vanish). One module pings the server, the other does not: only the pinging
one notices. After the link is mended the pinging one is back in the room and answers calls.
"""

from __future__ import annotations

import logging
import shutil
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.comm.xmpp import XmppComm
from nightcrew.modules import Module
from nightcrew.server import Account, init_server, stop_server
from nightcrew.testing import wait_for
from nightcrew.testing.hosts import OUTSIDE, Hosts, hosts_missing
from tests.comm.sample import Calculator, ICalculator
from tests.vfs.remote_servers import require

pytestmark = pytest.mark.xmpp
log = logging.getLogger(__name__)
DOMAIN = "observatory.test"
PASSWORD = "secret-for-tests"
PING_INTERVAL, PING_TIMEOUT = 1.0, 2.0


@pytest.fixture
def server(tmp_path: Path) -> Iterator[tuple[Hosts, str, str]]:
    """Prosody on host "server": (hosts, its address as the test reaches it, its CA file)."""
    require(hosts_missing() + ([] if shutil.which("prosody") else ["prosody (apt-get install prosody)"]))
    directory = tmp_path / "xmpp"
    accounts = [Account(name, DOMAIN, PASSWORD) for name in ("pinging", "silent")]
    init_server(directory, accounts, host="0.0.0.0", port=5222, domains=[DOMAIN])
    with Hosts(["server"], outside=["server"]) as hosts:
        starting = hosts["server"].run(
            [sys.executable, "-m", "nightcrew", "server", "start", str(directory)], log=tmp_path / "start.log"
        )
        assert starting.wait(timeout=60) == 0, (tmp_path / "start.log").read_text()
        try:
            yield (
                hosts,
                f"{hosts['server'].address(OUTSIDE)}:5222",
                str(directory / "certs" / f"{DOMAIN}.crt"),
            )
        finally:
            stop_server(directory)


def comm(name: str, address: str, ca_file: str, ping_interval: float | None) -> XmppComm:
    return XmppComm(
        f"{name}@{DOMAIN}", PASSWORD, server=address, ca_file=ca_file, connect_timeout=5,
        ping_interval=ping_interval, ping_timeout=PING_TIMEOUT,
        policy="open",  # about keepalives, not access
    )  # fmt: skip


async def test_pings_notice_a_silent_link_and_the_module_reconnects(server: tuple[Hosts, str, str]) -> None:
    hosts, address, ca_file = server
    pinging = Calculator(comm=comm("pinging", address, ca_file, PING_INTERVAL))
    silent = Module(comm=comm("silent", address, ca_file, None))
    await pinging.open()
    await silent.open()
    try:
        await wait_for(lambda: "pinging" in silent.comm.clients, 30, message="pinging in the room")
        hosts.cut("server", OUTSIDE)
        cut = time.monotonic()
        await wait_for(lambda: not pinging.comm.connected, 30, message="the pinging module noticed the cut")
        noticed = time.monotonic() - cut
        # The first unanswered ping ends the session: at most one interval plus one timeout later
        # (a busy machine adds a little).
        assert noticed <= PING_INTERVAL + PING_TIMEOUT + 5, f"noticed after {noticed:.1f} s"
        assert silent.comm.connected  # without pings nothing notices a silent link
        hosts.restore("server", OUTSIDE)
        restored = time.monotonic()
        await wait_for(lambda: pinging.comm.connected, 30, message="the pinging module reconnected")
        reconnected = time.monotonic() - restored

        async def answers() -> bool:
            try:
                proxy = await silent.comm.proxy("pinging", ICalculator)
                return await proxy.add(1, 2) == 3.0
            except Exception:  # not back in the room yet
                return False

        await wait_for(answers, 30, message="the pinging module answers calls again")
        answering = time.monotonic() - restored
        log.info(
            "silent link noticed after %.1f s; reconnected %.1f s and answering %.1f s after the restore",
            noticed, reconnected, answering,
        )  # fmt: skip
        print(f"\nnoticed {noticed:.1f} s; reconnected {reconnected:.1f} s; answering {answering:.1f} s")
    finally:
        await pinging.close()
        await silent.close()
