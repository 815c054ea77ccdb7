"""Centring on the alpaca-simulators mount, by offsets and by a sync (see
tests/observing/bridged_centring.py for where the light comes from)."""

from __future__ import annotations

from nightcrew.astro import altaz_to_radec
from nightcrew.clock import RealClock
from nightcrew.modules.alpaca import AlpacaTelescope
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import SIMULATOR_SITE, AlpacaSimulator
from tests.observing.bridged_centring import HiddenPointingError, centre_both_ways


class AlpacaMountWithError(HiddenPointingError, AlpacaTelescope):
    """alpaca-simulators' mount, seen through a tube that points off."""


async def test_centring_on_the_alpaca_mount(alpaca_simulator: AlpacaSimulator) -> None:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        mount = await obs.start(AlpacaMountWithError, "mount", server=alpaca_simulator.url)
        await mount.init()
        # Where the mount stands when that is high enough (the session's simulator keeps its state):
        # a short slew, as the simulator slews in real time.
        alt, az = await mount.get_altaz()
        if alt < 30.0:
            alt, az = 60.0, 180.0
        ra, dec = altaz_to_radec(alt, az, SIMULATOR_SITE.latitude, SIMULATOR_SITE.longitude, obs.clock.time())
        await centre_both_ways(obs, mount, (float(ra) % 360.0, float(dec)))
