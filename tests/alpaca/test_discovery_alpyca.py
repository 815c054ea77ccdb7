"""alpyca's own discovery (``alpaca.discovery.search_ipv4``) finds AlpacaServer.

search_ipv4 broadcasts on every network interface, so the test runs it in a private network
namespace that has only a loopback interface (``unshare --net``, we are root): its broadcast goes
to 127.255.255.255:32227, where the server's responder listens, and nothing leaves the machine.
Needs util-linux ``unshare`` and iproute2 ``ip``; skipped without them, except under CI=true.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import pytest

_SCRIPT = """
import asyncio, json
from alpaca import discovery
from nightcrew.clock import RealClock
from nightcrew.modules.alpaca.server import AlpacaServer
from nightcrew.modules.sim import SimFocuser
from nightcrew.testing import Observatory

async def main():
    async with Observatory(clock=RealClock(), site=None) as obs:
        await obs.start(SimFocuser, "focuser")
        server = await obs.start(AlpacaServer, "alpaca", devices={"focuser": "focuser"}, port=0)
        assert server.discovery_port == 32227
        found = await asyncio.to_thread(discovery.search_ipv4, 2, 1)
        print(json.dumps({"port": server.port, "found": found}))

asyncio.run(main())
"""


def _tools() -> tuple[str, str]:
    unshare, ip = shutil.which("unshare"), shutil.which("ip")
    if unshare is None or ip is None or os.geteuid() != 0:
        if os.environ.get("CI") == "true":
            pytest.fail("needs root, util-linux unshare and iproute2 ip on CI")
        pytest.skip("needs root, unshare and ip for a private network namespace")
    return unshare, ip


def test_alpyca_discovery_finds_the_server() -> None:
    unshare, ip = _tools()
    command = [
        unshare,
        "--net",
        "sh",
        "-c",
        f'{ip} link set lo up && exec "$0" -c "$1"',
        sys.executable,
        _SCRIPT,
    ]
    result = subprocess.run(
        command, capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL, check=False
    )
    assert result.returncode == 0, result.stderr[-3000:]
    answer = json.loads(result.stdout.strip().splitlines()[-1])
    assert answer["found"] == [f"127.0.0.1:{answer['port']}"]
