"""AlpacaTelescope beyond the contract: tracking, tracking rates, sync, pier side, Alt/Az vs RA/Dec
tracking, and an Alpaca error during a slew."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from nightcrew.clock import RealClock
from nightcrew.errors import InvalidArgumentError, MoveError
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.alpaca import AlpacaTelescope
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import SIMULATOR_SITE, AlpacaSimulator
from tests.alpaca.faulty_server import FaultyServer, alpaca_error, value


@pytest.fixture
async def telescope(alpaca_simulator: AlpacaSimulator) -> AsyncIterator[AlpacaTelescope]:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        module = await obs.start(AlpacaTelescope, "telescope", server=alpaca_simulator.url)
        await module.init()
        yield module


async def test_radec_slews_track_and_altaz_slews_do_not(telescope: AlpacaTelescope) -> None:
    await telescope.move_altaz(50.0, 200.0)
    assert await telescope.device.get("tracking") is False
    assert await telescope.get_config_value("tracking") is False
    ra, dec = await telescope.get_radec()
    await telescope.move_radec(ra, dec)
    assert await telescope.device.get("tracking") is True
    assert await telescope.get_motion_status() is MotionStatus.TRACKING
    assert abs(await telescope.device.get("rightascension") * 15.0 - ra) < 0.01  # hours on the wire


async def test_tracking_rates_sync_and_pier_side(telescope: AlpacaTelescope) -> None:
    assert "sidereal" in await telescope.get_config_value_options("tracking_rate")
    await telescope.set_config_value("tracking_rate", "lunar")
    assert await telescope.get_config_value("tracking_rate") == "lunar"
    assert await telescope.device.get("trackingrate") == 1
    await telescope.set_config_value("tracking_rate", "sidereal")
    with pytest.raises(InvalidArgumentError, match="unknown tracking rate 'warp'"):
        await telescope.set_config_value("tracking_rate", "warp")
    await telescope.set_config_value("tracking", False)
    assert await telescope.device.get("tracking") is False
    assert await telescope.get_config_value("pier_side") in ("east", "west", "unknown")

    await telescope.move_altaz(60.0, 180.0)
    ra, dec = await telescope.get_radec()
    await telescope.move_radec(ra, dec)
    await telescope.sync_radec((ra + 0.5) % 360.0, dec)
    synced_ra, _ = await telescope.get_radec()
    assert abs((synced_ra - ra - 0.5 + 180.0) % 360.0 - 180.0) < 0.05
    with pytest.raises(InvalidArgumentError):
        await telescope.sync_radec(400.0, 0.0)


async def test_an_alpaca_error_during_a_slew_is_a_move_error_naming_device_and_call() -> None:
    server = FaultyServer()
    server.replies.update(
        {
            "connecting": value(False),
            "atpark": value(False),
            "tracking": value(True),
            "sitelatitude": value(SIMULATOR_SITE.latitude),
            "sitelongitude": value(SIMULATOR_SITE.longitude),
            "slewtoaltazasync": alpaca_error(0x408, "the mount is parked"),
        }
    )
    await server.start()
    try:
        async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
            telescope = await obs.start(AlpacaTelescope, "telescope", server=server.url)
            await telescope.init()
            with pytest.raises(
                MoveError, match=r"telescope 0 at .*: PUT slewtoaltazasync: InvalidWhileParked"
            ):
                await telescope.move_altaz(45.0, 90.0)
            assert await telescope.get_motion_status() is MotionStatus.ERROR
    finally:
        await server.stop()
