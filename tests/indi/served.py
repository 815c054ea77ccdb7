"""The simulated observatory served by IndiServer on a free loopback port, for the IndiServer tests.

It runs in the test's process on a fast clock (no network namespace needed: the server binds
127.0.0.1 only). ``serve()`` is the ``served`` fixture of tests/indi/conftest.py.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from typing import Any

from nightcrew.clock import AcceleratedClock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.events import MoveRaDecEvent
from nightcrew.modules import Module
from nightcrew.modules.indi.server import IndiServer
from nightcrew.modules.sim import SimCamera, SimDome, SimFilterWheel, SimFocuser, SimTelescope
from nightcrew.site import Site
from nightcrew.vfs import MemoryFile, VirtualFileSystem
from tests.indi.server_clients import require_clients, wait_for

__all__ = ["EPOCH", "SITE", "Served", "serve"]

#: A winter night at a mid-northern site, the Sun well down.
EPOCH = "2024-01-15T22:00:00+00:00"
SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")


@dataclass
class Served:
    server: IndiServer
    telescope: SimTelescope
    camera: SimCamera
    focuser: SimFocuser
    filters: SimFilterWheel
    dome: SimDome
    clock: AcceleratedClock
    network: LocalNetwork
    moves: asyncio.Queue[MoveRaDecEvent] = field(default_factory=asyncio.Queue)

    @property
    def port(self) -> str:
        return str(self.server.port)


@asynccontextmanager
async def serve() -> AsyncIterator[Served]:
    require_clients()
    clock = AcceleratedClock(EPOCH, speed=20.0)
    network = LocalNetwork()
    vfs = VirtualFileSystem({"cache": MemoryFile()})

    def context(name: str) -> dict[str, Any]:
        return {"comm": LocalComm(name, network=network), "clock": clock, "site": SITE, "vfs": vfs}

    modules: list[Module] = []
    try:
        telescope = SimTelescope(**context("telescope"))
        camera = SimCamera(
            roof=None,
            weather=None,
            detector={"chip_width": 64, "chip_height": 48},
            readout_time=0.5,
            **context("camera"),
        )
        focuser = SimFocuser(**context("focuser"))
        filters = SimFilterWheel(filters=["B", "V", "R"], **context("filters"))
        dome = SimDome(**context("dome"))
        watcher = Module(**context("watcher"))
        for module in (telescope, camera, focuser, filters, dome, watcher):
            modules.append(module)
            await module.open()
        server = IndiServer(
            port=0,
            telescope="telescope",
            camera="camera",
            focuser="focuser",
            filters="filters",
            dome="dome",
            poll_interval=0.2,
            **context("indi"),
        )
        modules.append(server)
        await server.open()
        result = Served(server, telescope, camera, focuser, filters, dome, clock, network)

        async def on_move(event: MoveRaDecEvent, sender: str) -> None:
            await result.moves.put(event)

        await watcher.comm.register_event(MoveRaDecEvent, on_move)
        # Served once every device is attached (each defines DRIVER_INFO then).
        await wait_for(result.port, [f"{d}.DRIVER_INFO.DRIVER_NAME" for d in server.devices], lambda v: True)
        yield result
    finally:
        for module in reversed(modules):
            await module.close()
