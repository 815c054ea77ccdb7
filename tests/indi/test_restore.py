"""Device faults that must not cost more than the frame in flight: a camera module that restarts
aborts the exposure its killed predecessor left running; after indiserver restarts, the modules set
again what they had set (filter, focus, cooling, tracking) before they report ready."""

from __future__ import annotations

import asyncio
from collections.abc import Callable

import pytest

from nightcrew.astro import altaz_to_radec
from nightcrew.bridges.indi import PropertyState
from nightcrew.clock import RealClock
from nightcrew.interfaces import ModuleState, MotionStatus
from nightcrew.modules.indi import IndiCamera, IndiFilterWheel, IndiFocuser, IndiTelescope
from nightcrew.testing import Observatory, wait_for
from nightcrew.testing.indi import SIMULATORS, IndiServer


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


async def test_after_an_indiserver_restart_the_modules_set_again_what_they_had_set(
    own_indi_server: Callable[..., IndiServer], caplog: pytest.LogCaptureFixture
) -> None:
    server = own_indi_server(
        "indi_simulator_ccd", "indi_simulator_focus", "indi_simulator_wheel", "indi_simulator_telescope"
    )
    where = {"host": server.host, "port": server.port}
    async with Observatory(clock=RealClock()) as obs:
        focuser = await obs.start(
            IndiFocuser, "focuser", device=SIMULATORS["indi_simulator_focus"], max_focus=100.0, **where
        )
        wheel = await obs.start(
            IndiFilterWheel, "filters", device=SIMULATORS["indi_simulator_wheel"], **where
        )
        camera = await obs.start(IndiCamera, "camera", device=SIMULATORS["indi_simulator_ccd"], **where)
        telescope = await obs.start(
            IndiTelescope, "telescope", device=SIMULATORS["indi_simulator_telescope"], **where
        )
        await telescope.init()
        site = telescope.observatory
        target = altaz_to_radec(60.0, 180.0, site.latitude, site.longitude, obs.clock.time())
        await telescope.move_radec(*target)
        focus = await focuser.get_focus() + 1.5
        await focuser.set_focus(focus)
        chosen = (await wheel.list_filters())[-1]
        await wheel.set_filter(chosen)
        await camera.set_cooling(True, -12.0)
        modules = (focuser, wheel, camera, telescope)

        server.kill()
        await wait_for(lambda: all(m.state is ModuleState.ERROR for m in modules), 30.0, message="ERROR")
        server.start()
        await wait_for(lambda: all(m.state is ModuleState.READY for m in modules), 30.0, message="READY")
        # The drivers came back in their defaults, and each module set again what it had set.
        assert "focuser: the focuser came back at" in caplog.text
        assert "filters: the wheel came back at" in caplog.text
        position = focuser._indi.vector("ABS_FOCUS_POSITION").number("FOCUS_ABSOLUTE_POSITION")
        assert position == pytest.approx(focus * 1000.0)
        slot = round(wheel._indi.vector("FILTER_SLOT").number("FILTER_SLOT_VALUE"))
        assert (await wheel.list_filters())[slot - 1] == chosen == await wheel.get_filter()
        assert "telescope: the mount came back: tracking RA" in caplog.text
        assert await telescope.get_motion_status() is MotionStatus.TRACKING
        assert await telescope.get_radec() == pytest.approx(target, abs=0.05)
        await wait_for(
            lambda: camera._indi.vector("CCD_TEMPERATURE").state is PropertyState.BUSY,
            10.0,
            message="cooling towards the set point again",
        )
