"""AlpacaTelescope's offset rates (non-sidereal tracking) on alpaca-simulators' telescope."""

from __future__ import annotations

import time
from collections.abc import AsyncIterator

import pytest

from nightcrew.clock import RealClock
from nightcrew.modules.alpaca import AlpacaTelescope
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import SIMULATOR_SITE, AlpacaSimulator


@pytest.fixture
async def telescope(alpaca_simulator: AlpacaSimulator) -> AsyncIterator[AlpacaTelescope]:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        module = await obs.start(AlpacaTelescope, "telescope", server=alpaca_simulator.url)
        await module.init()
        yield module


async def test_offset_rates_move_the_tracked_position(telescope: AlpacaTelescope) -> None:
    await telescope.move_radec(*await telescope.get_radec())  # where it is: tracking, no slew to speak of
    # 60"/s in RA (an angle of RA) and -30"/s in Dec: what a fast near-Earth object does.
    assert await telescope._hw_set_tracking_rates(60.0, -30.0) is True
    assert await telescope.device.get("rightascensionrate") == pytest.approx(60.0 / 15.0 * 0.99727, rel=1e-4)
    assert await telescope.device.get("declinationrate") == pytest.approx(-30.0)
    ra0, dec0 = await telescope.get_radec()
    began = time.monotonic()
    await telescope.clock.sleep(1.0)
    ra1, dec1 = await telescope.get_radec()
    elapsed = time.monotonic() - began
    # Within the time the two reads took (their wall times bracket the positions).
    assert (ra1 - ra0) * 3600.0 == pytest.approx(60.0 * elapsed, abs=60.0 * 0.3)
    assert (dec1 - dec0) * 3600.0 == pytest.approx(-30.0 * elapsed, abs=30.0 * 0.3)
    assert await telescope._hw_set_tracking_rates(0.0, 0.0) is True
    ra2, dec2 = await telescope.get_radec()
    await telescope.clock.sleep(0.5)
    ra3, dec3 = await telescope.get_radec()
    assert abs(ra3 - ra2) * 3600.0 < 1.0 and abs(dec3 - dec2) * 3600.0 < 1.0
