"""Device faults that must not cost more than the frame in flight: a camera module that restarts
aborts the exposure its killed predecessor left running; after indiserver restarts, the modules set
again what they had set (filter, focus, cooling, tracking) before they report ready."""

from __future__ import annotations

import asyncio
from collections.abc import Callable

from nightcrew.clock import RealClock
from nightcrew.interfaces import ModuleState
from nightcrew.modules.indi import IndiCamera
from nightcrew.testing import Observatory, wait_for
from nightcrew.testing.indi import IndiServer


async def test_a_new_camera_module_aborts_the_exposure_a_killed_one_left_running(
    own_indi_server: Callable[..., IndiServer],
) -> None:
    server = own_indi_server("indi_simulator_ccd")
    where = {"host": server.host, "port": server.port, "device": "CCD Simulator"}
    async with Observatory(clock=RealClock()) as obs:
        killed = await obs.start(IndiCamera, "camera", **where)
        await killed.set_exposure_time(600.0)
        exposure = asyncio.ensure_future(killed.grab_data())
        await wait_for(lambda: killed._indi.is_busy("CCD_EXPOSURE"), 10.0, message="exposing")
        # As kill -9 would: from now on nothing of this module reaches the driver, not even an abort.
        await killed._indi.client.close()
        exposure.cancel()
        await asyncio.wait({exposure})

    async with Observatory(clock=RealClock()) as obs:
        camera = await obs.start(IndiCamera, "camera", **where)
        assert camera.state is ModuleState.READY
        assert not camera._indi.is_busy("CCD_EXPOSURE")  # aborted before it said ready
        await camera.set_exposure_time(0.2)
        assert (await camera.grab_data()).endswith(".fits")
