"""The test indiserver runs only in its own network namespace and leaves nothing behind."""

from __future__ import annotations

import asyncio
import os
from collections.abc import Callable
from pathlib import Path

from nightcrew.testing.indi import IndiServer


async def _get_properties(host: str, port: int, device: str) -> bytes:
    """What the server sends up to the device's CONNECTION switch (its definitions come in many reads)."""
    reader, writer = await asyncio.open_connection(host, port)
    try:
        writer.write(b'<getProperties version="1.7"/>\n')
        received = b""
        async with asyncio.timeout(20):
            while f'<defSwitchVector device="{device}" name="CONNECTION"'.encode() not in received:
                received += await reader.read(65536)
        return received
    finally:
        writer.close()


def _exists(path: str) -> bool:
    return Path(path).exists()


async def test_server_answers_from_its_namespace_only(own_indi_server: Callable[..., IndiServer]) -> None:
    server = own_indi_server("indi_simulator_focus")
    assert server.host.startswith("10.")
    assert os.readlink(f"/proc/{server.pid}/ns/net") != os.readlink("/proc/self/ns/net")
    received = await _get_properties(server.host, server.port, "Focuser Simulator")
    assert received.startswith(b"<def") and b'device="Focuser Simulator"' in received
    assert set(server.driver_pids()) == {"indi_simulator_focus"}


async def test_kill_and_restart_by_pid(own_indi_server: Callable[..., IndiServer]) -> None:
    server = own_indi_server("indi_simulator_focus")
    first = server.pid
    assert first is not None
    server.kill()
    after_kill = server.pid
    assert after_kill is None and not _exists(f"/proc/{first}")
    server.start()
    second = server.pid
    assert second not in (None, first)
    assert b"Focuser Simulator" in await _get_properties(server.host, server.port, "Focuser Simulator")


def test_stop_removes_namespace_and_link(own_indi_server: Callable[..., IndiServer]) -> None:
    server = own_indi_server("indi_simulator_focus")
    holder, link = server.network.pid, server.network.host_side
    assert Path(f"/sys/class/net/{link}").exists()
    server.stop()
    assert not Path(f"/proc/{holder}").exists()
    assert not Path(f"/sys/class/net/{link}").exists()
