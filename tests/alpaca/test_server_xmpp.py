"""AlpacaServer serves modules it reaches over XMPP exactly as in-process ones.

The focuser and filter wheel log in to a real Prosody (the session fixture of tests/comm) and
AlpacaServer reaches them in the MUC room through proxies; alpyca moves them over Alpaca.
"""

from __future__ import annotations

import asyncio
import uuid
from collections.abc import AsyncIterator

import pytest
from alpaca.filterwheel import FilterWheel  # type: ignore[import-untyped]
from alpaca.focuser import Focuser  # type: ignore[import-untyped]

from nightcrew.clock import RealClock
from nightcrew.modules import Module
from nightcrew.modules.alpaca.server import AlpacaServer
from nightcrew.modules.sim import SimFilterWheel, SimFocuser
from nightcrew.testing import wait_for

from ..comm.conftest import prosody_server  # noqa: F401 - the session fixture, reused
from ..comm.xmpp_servers import XmppServer
from .served import wait_in_thread

pytestmark = pytest.mark.xmpp


@pytest.fixture
async def xmpp_modules(prosody_server: XmppServer) -> AsyncIterator[AlpacaServer]:  # noqa: F811
    room = f"alpaca-{uuid.uuid4().hex[:10]}"
    clock = RealClock()
    # The served modules trust the Alpaca server's account: this test is about Alpaca, not access.
    open_policy = {"policy": "open"}
    modules: list[Module] = [
        SimFocuser(
            comm=prosody_server.comm("focuser", room=room, **open_policy), clock=clock, speed=20.0, focus=20.0
        ),
        SimFilterWheel(
            comm=prosody_server.comm("filters", room=room, **open_policy),
            clock=clock,
            filters=["B", "V"],
            change_time=0.2,
        ),
        AlpacaServer(
            comm=prosody_server.comm("alpaca", room=room),
            clock=clock,
            devices={"focuser": "focuser", "filterwheel": "filters"},
            port=0,
            discovery_port=None,
        ),
    ]
    try:
        for module in modules:
            await module.open()
        server = modules[-1]
        assert isinstance(server, AlpacaServer)
        # The server sees the others once their presence reached it through the room.
        online = {"focuser", "filters"}
        await wait_for(lambda: online <= set(server.comm.clients), 30.0, message="focuser and filters online")
        yield server
    finally:
        for module in reversed(modules):
            await module.close()


async def test_alpyca_moves_modules_reached_over_xmpp(xmpp_modules: AlpacaServer) -> None:
    address = f"127.0.0.1:{xmpp_modules.port}"
    focuser, wheel = Focuser(address, 0), FilterWheel(address, 0)
    for device in (focuser, wheel):
        await asyncio.to_thread(setattr, device, "Connected", True)
    await asyncio.to_thread(focuser.Move, 21000)
    await wait_in_thread(lambda: not focuser.IsMoving, 30.0, "focuser arrived")
    assert await asyncio.to_thread(lambda: focuser.Position) == 21000
    assert await asyncio.to_thread(lambda: wheel.Names) == ["B", "V"]
    await asyncio.to_thread(setattr, wheel, "Position", 1)
    await wait_in_thread(lambda: wheel.Position == 1, 30.0, "filter V in the beam")
