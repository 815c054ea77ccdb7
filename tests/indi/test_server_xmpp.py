"""IndiServer reaches its devices through proxies: here the telescope is a module on a real XMPP room."""

from __future__ import annotations

import asyncio

import pytest

from nightcrew.astro import altaz_to_radec, j2000_to_of_date
from nightcrew.clock import AcceleratedClock
from nightcrew.events import MoveRaDecEvent
from nightcrew.interfaces import MotionStatus
from nightcrew.modules import Module
from nightcrew.modules.indi.server import IndiServer
from nightcrew.modules.sim import SimTelescope
from nightcrew.site import Site

# The session's Prosody and a room per test, as tests/comm has them (imported to be found here).
from tests.comm.conftest import Network, prosody_network, prosody_server  # noqa: F401
from tests.indi.server_clients import PATIENCE, getprop, require_clients, setprop, wait_for

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")

pytestmark = pytest.mark.xmpp


@pytest.fixture
def network(request: pytest.FixtureRequest) -> Network:
    """A room of its own on the session's Prosody."""
    prosody: Network = request.getfixturevalue("prosody_network")
    return prosody


async def test_a_telescope_on_xmpp_is_listed_and_slewed_by_indi_clients(network: Network) -> None:
    require_clients()
    clock = AcceleratedClock("2024-01-15T22:00:00+00:00", speed=20.0)
    telescope = await network.start(SimTelescope, "telescope", clock=clock, site=SITE)
    watcher = await network.start(Module, "watcher", clock=clock)
    moves: asyncio.Queue[MoveRaDecEvent] = asyncio.Queue()

    async def on_move(event: MoveRaDecEvent, sender: str) -> None:
        await moves.put(event)

    await watcher.comm.register_event(MoveRaDecEvent, on_move)
    server = await network.start(
        IndiServer, "indi", port=0, telescope="telescope", poll_interval=0.2, clock=clock, site=SITE
    )
    port = str(server.port)
    values = await wait_for(port, ["telescope.TELESCOPE_PARK.PARK"], lambda v: True, "the telescope served")
    assert values == {"telescope.TELESCOPE_PARK.PARK": "On"}

    await setprop(port, "telescope.TELESCOPE_PARK.UNPARK=On")
    unparked = {"telescope.TELESCOPE_PARK.UNPARK": "On", "telescope.TELESCOPE_PARK._STATE": "Ok"}
    await wait_for(port, list(unparked), lambda v: v == unparked)
    ra, dec = altaz_to_radec(55.0, 200.0, SITE.latitude, SITE.longitude, clock.time())
    ra_date, dec_date = j2000_to_of_date(ra, dec, clock.time())
    await setprop(port, f"telescope.EQUATORIAL_EOD_COORD.RA;DEC={ra_date / 15.0:.8f};{dec_date:.8f}")
    move = await asyncio.wait_for(moves.get(), PATIENCE)
    assert (move.ra, move.dec) == pytest.approx((ra, dec), abs=2e-6)
    values = await wait_for(
        port,
        ["telescope.EQUATORIAL_EOD_COORD._STATE", "telescope.EQUATORIAL_EOD_COORD.DEC"],
        lambda v: v["telescope.EQUATORIAL_EOD_COORD._STATE"] == "Ok",
    )
    assert float(values["telescope.EQUATORIAL_EOD_COORD.DEC"]) == pytest.approx(dec_date, abs=1e-5)
    assert await telescope.get_motion_status() is MotionStatus.TRACKING
    listed = await getprop(port, "telescope.DRIVER_INFO.DRIVER_INTERFACE")
    assert listed == {"telescope.DRIVER_INFO.DRIVER_INTERFACE": "5"}  # telescope and guider
