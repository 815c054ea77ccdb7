"""IndiTelescope's offset rates (TELESCOPE_TRACK_RATE with TRACK_CUSTOM) on indi-bin's telescope simulator."""

from __future__ import annotations

import time

import pytest

from nightcrew.clock import RealClock
from nightcrew.interfaces import PierSide
from nightcrew.modules.indi import IndiTelescope
from nightcrew.testing import Observatory
from nightcrew.testing.indi import IndiServer


async def test_custom_track_rates_move_the_tracked_position(indi_server: IndiServer) -> None:
    async with Observatory(clock=RealClock()) as obs:
        telescope = await obs.start(
            IndiTelescope,
            "telescope",
            host=indi_server.host,
            port=indi_server.port,
            device="Telescope Simulator",
        )
        await telescope.init()
        await telescope.move_radec(*telescope._radec_of(11.0, 91.0))  # by the park position: a short slew
        try:
            assert await telescope.get_pier_side() is PierSide.WEST  # the Dec axis runs south here
            assert await telescope._hw_set_tracking_rates(10.0, -5.0) is True
            assert telescope._indi.vector("TELESCOPE_TRACK_MODE").members["TRACK_CUSTOM"] is True
            ra0, dec0 = await telescope.get_radec()
            began = time.monotonic()
            await obs.clock.sleep(3.0)
            ra1, dec1 = await telescope.get_radec()
            elapsed = time.monotonic() - began
            # The simulator reports about once a second: either position may be up to a second old.
            assert (ra1 - ra0) * 3600.0 == pytest.approx(10.0 * elapsed, abs=10.0 * 1.2)
            assert (dec1 - dec0) * 3600.0 == pytest.approx(-5.0 * elapsed, abs=5.0 * 1.2)
            assert await telescope._hw_set_tracking_rates(0.0, 0.0) is True
            assert telescope._indi.vector("TELESCOPE_TRACK_MODE").members["TRACK_SIDEREAL"] is True
            # Faster than the sidereal rate eastwards the RA axis would turn back: left to position updates.
            assert await telescope._hw_set_tracking_rates(20.0, 0.0) is False
        finally:
            await telescope.park()
