"""IndiCoverCalibrator on a cover and a light: indi-bin's Flip Flat driver (``indi_flipflat``) in
its own simulation mode, switched on by a client before the module connects (as a user would with
``indi_setprop``). The driver moves its simulated cover in 3 wall seconds and defines no
CAP_ABORT, so halting is refused."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from nightcrew.bridges.indi.client import IndiClient
from nightcrew.clock import RealClock
from nightcrew.errors import NotSupportedError
from nightcrew.interfaces import CalibratorState, CoverState
from nightcrew.modules.indi import IndiCoverCalibrator
from nightcrew.testing import Observatory
from nightcrew.testing.indi import IndiServer

DEVICE = "Flip Flat"


async def simulate(server: IndiServer) -> None:
    client = IndiClient(server.host, server.port, devices=[DEVICE])
    await client.open()
    try:
        await client.wait_defined(DEVICE, "SIMULATION", within=10)
        await client.send(DEVICE, "SIMULATION", {"ENABLE": True, "DISABLE": False}, wait=10)
    finally:
        await client.close()


async def test_the_flip_flat_closes_lights_and_opens(own_indi_server: Callable[..., IndiServer]) -> None:
    server = own_indi_server("indi_flipflat")
    await simulate(server)
    async with Observatory(clock=RealClock()) as obs:
        flip_flat = await obs.start(
            IndiCoverCalibrator, "calibrator", host=server.host, port=server.port, device=DEVICE
        )
        await flip_flat.close_cover()
        assert await flip_flat.get_cover_state() is CoverState.CLOSED
        assert flip_flat._indi.vector("CAP_PARK").on_switches() == ["PARK"]
        assert await flip_flat.get_max_brightness() == 255
        await flip_flat.calibrator_on(100)
        assert await flip_flat.get_calibrator_state() is CalibratorState.READY
        assert await flip_flat.get_brightness() == 100
        await flip_flat.calibrator_off()
        assert await flip_flat.get_calibrator_state() is CalibratorState.OFF
        with pytest.raises(NotSupportedError, match="CAP_ABORT"):
            await flip_flat.halt_cover()
        await flip_flat.open_cover()
        assert await flip_flat.get_cover_state() is CoverState.OPEN
