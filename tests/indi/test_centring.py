"""Centring on the INDI telescope simulator, by offsets and by a sync (see
tests/observing/bridged_centring.py for where the light comes from)."""

from __future__ import annotations

from nightcrew.clock import RealClock
from nightcrew.modules.indi import IndiTelescope
from nightcrew.testing import Observatory
from nightcrew.testing.indi import IndiServer
from tests.observing.bridged_centring import HiddenPointingError, centre_both_ways


class IndiMountWithError(HiddenPointingError, IndiTelescope):
    """The INDI telescope simulator, seen through a tube that points off."""


async def test_centring_on_the_indi_mount(indi_server: IndiServer) -> None:
    async with Observatory(clock=RealClock()) as obs:
        mount = await obs.start(
            IndiMountWithError,
            "mount",
            host=indi_server.host,
            port=indi_server.port,
            device="Telescope Simulator",
        )
        await mount.init()
        # Near the park position (hour angle -6 h, Dec 0): the simulator slews in real time.
        await centre_both_ways(obs, mount, mount._radec_of(25.0, 100.0))
