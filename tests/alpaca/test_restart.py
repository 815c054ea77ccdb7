"""alpaca-simulators is killed and restarted mid-session: the modules go to ERROR and come back
to READY by themselves, and work again, without being restarted."""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable
from importlib import resources
from typing import Any

import pytest
import yaml

from nightcrew.bridges.alpaca import AlpacaClient
from nightcrew.clock import RealClock
from nightcrew.errors import GrabImageError, ModuleError
from nightcrew.interfaces import (
    ExposureStatus,
    ICamera,
    IFilters,
    IFocuser,
    IModule,
    ITelescope,
    ModuleState,
    MotionStatus,
)
from nightcrew.modules.alpaca import AlpacaCamera, AlpacaFilterWheel, AlpacaFocuser, AlpacaTelescope
from nightcrew.testing import ContractProbe, Observatory, wait_for
from nightcrew.testing.alpaca import SIMULATOR_SITE, TEST_OVERRIDES, AlpacaSimulator, merge_config

_QUICK = {"reconnect_interval": 0.2, "timeout": 5.0}


async def test_modules_recover_when_the_server_comes_back(
    start_alpaca_simulator: Callable[..., AlpacaSimulator], caplog: pytest.LogCaptureFixture
) -> None:
    simulator = start_alpaca_simulator()
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        caller = await obs.start(ContractProbe, "other")  # calls as any other module would
        modules = [
            await obs.start(AlpacaTelescope, "telescope", server=simulator.url, **_QUICK),
            await obs.start(AlpacaCamera, "camera", server=simulator.url, **_QUICK),
            await obs.start(AlpacaFocuser, "focuser", server=simulator.url, **_QUICK),
            await obs.start(AlpacaFilterWheel, "filters", server=simulator.url, **_QUICK),
        ]
        assert all(m.state is ModuleState.READY for m in modules)
        telescope = await caller.comm.proxy("telescope", ITelescope)
        await telescope.init()
        _, az = await telescope.get_altaz()
        pointing = (45.0, (az + 5.0) % 360.0)
        await telescope.move_altaz(*pointing)  # as for flats: an Alt/Az position, not tracked
        pid = simulator.pid
        simulator.stop()

        await wait_for(
            lambda: all(m.state is ModuleState.ERROR for m in modules), 30.0, message="modules in ERROR"
        )
        focuser = await caller.comm.proxy("focuser", IFocuser)
        with pytest.raises(ModuleError, match=r"error state: lost focuser 0 at http://127\.0\.0\.1:\d+"):
            await focuser.set_focus(10.0)
        state = await (await caller.comm.proxy("camera", IModule)).get_error_string()
        assert "lost camera 0 at" in state

        simulator.start()
        assert simulator.pid != pid
        await wait_for(
            lambda: all(m.state is ModuleState.READY for m in modules), 30.0, message="modules READY again"
        )
        await focuser.set_focus(10.2)
        assert await focuser.get_focus() == pytest.approx(10.2)
        # The mount came back parked; the module pointed it at its Alt/Az position again.
        assert "telescope: the mount came back: pointing at Alt 45.000°" in caplog.text
        assert await telescope.get_motion_status() is MotionStatus.IDLE
        device = modules[0].device
        assert (await device.get("altitude"), await device.get("azimuth")) == pytest.approx(pointing, abs=0.1)
        await telescope.move_altaz(50.0, pointing[1])
        wheel = await caller.comm.proxy("filters", IFilters)
        await wheel.set_filter("Blue")
        assert await wheel.get_filter() == "Blue"
        camera = await caller.comm.proxy("camera", ICamera)
        filename = await camera.grab_data()
        assert filename.endswith(".fits")


async def test_a_camera_losing_its_server_mid_exposure_writes_no_file(
    start_alpaca_simulator: Callable[..., AlpacaSimulator],
) -> None:
    simulator = start_alpaca_simulator()
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        camera = await obs.start(AlpacaCamera, "camera", server=simulator.url, **_QUICK)
        await camera.set_exposure_time(30.0)
        exposure = asyncio.ensure_future(camera.grab_data())
        await wait_for(camera_exposing(camera), 10.0, message="exposing")
        simulator.stop()
        with pytest.raises(
            GrabImageError, match=r"exposure failed: camera 0 at http://127\.0\.0\.1:\d+: GET "
        ):
            await exposure
        assert await obs.vfs.listdir("/cache") == []  # no half-written FITS file
        assert camera.state is ModuleState.ERROR
        simulator.start()
        await wait_for(lambda: camera.state is ModuleState.READY, 30.0, message="camera READY again")
        await camera.set_exposure_time(0.2)
        assert (await camera.grab_data()).endswith(".fits")


def camera_exposing(camera: AlpacaCamera) -> Callable[[], Awaitable[bool]]:
    """The device itself exposes (CameraState 2), not just the module (which says so before it asks)."""

    async def exposing() -> bool:
        return await camera.get_exposure_status() is ExposureStatus.EXPOSING and (
            await camera.device.get("camerastate") == 2
        )

    return exposing


async def test_a_new_camera_module_aborts_the_exposure_a_killed_one_left_running(
    start_alpaca_simulator: Callable[..., AlpacaSimulator],
) -> None:
    simulator = start_alpaca_simulator()
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        killed = await obs.start(AlpacaCamera, "camera", server=simulator.url, **_QUICK)
        await killed.set_exposure_time(600.0)
        exposure = asyncio.ensure_future(killed.grab_data())
        await wait_for(camera_exposing(killed), 10.0, message="exposing")
        # As kill -9 would: from now on nothing of this module reaches the device, not even an abort.
        await killed.device.client.close()
        exposure.cancel()
        await asyncio.wait({exposure})
    async with AlpacaClient(simulator.url) as client:
        assert await client.device("camera").get("camerastate") == 2  # still exposing, unattended

    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        camera = await obs.start(AlpacaCamera, "camera", server=simulator.url, **_QUICK)
        assert camera.state is ModuleState.READY
        assert await camera.device.get("camerastate") == 0  # aborted before it said ready
        await camera.set_exposure_time(0.2)
        assert (await camera.grab_data()).endswith(".fits")


def _second(device_type: str, **changes: Any) -> dict[str, Any]:
    """alpaca-simulators' device 1 of ``device_type``: its template's device 0 with ``changes``."""
    template_file = resources.files("alpaca_simulators").joinpath("config/template.yaml")
    template = yaml.safe_load(template_file.read_text())
    return {device_type: {1: {**template["devices"][device_type][0], **changes}}}


async def test_after_a_server_restart_the_modules_set_again_what_they_had_set(
    start_alpaca_simulator: Callable[..., AlpacaSimulator], caplog: pytest.LogCaptureFixture
) -> None:
    """Device 1 of the telescope powers up unparked, device 1 of the focuser counts relative steps
    only: the one module parks its mount again, the other (its motor does not move when its server
    restarts) keeps the position it counted, so nothing is sent to it."""
    devices = {**_second("telescope", atpark=False), **_second("focuser", absolute=False)}
    simulator = start_alpaca_simulator(overrides=merge_config(TEST_OVERRIDES, {"devices": devices}))
    quick = {"server": simulator.url, **_QUICK}
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        parked = await obs.start(AlpacaTelescope, "parked", device_number=1, **quick)
        relative = await obs.start(AlpacaFocuser, "relative", device_number=1, **quick)
        await parked.init()
        await parked.park()
        assert await parked.device.get("atpark") is True
        relative_focus = await relative.get_focus() + 0.5
        await relative.set_focus(relative_focus)
        focuser = await obs.start(AlpacaFocuser, "focuser", server=simulator.url, **_QUICK)
        wheel = await obs.start(AlpacaFilterWheel, "filters", server=simulator.url, **_QUICK)
        camera = await obs.start(AlpacaCamera, "camera", server=simulator.url, **_QUICK)
        telescope = await obs.start(AlpacaTelescope, "telescope", server=simulator.url, **_QUICK)
        await telescope.init()
        target = await telescope.get_radec()  # where it points after unparking: above the horizon
        await telescope.move_radec(*target)
        focus = await focuser.get_focus() + 1.5
        await focuser.set_focus(focus)
        chosen = (await wheel.list_filters())[-1]
        await wheel.set_filter(chosen)
        await camera.set_cooling(True, -12.0)
        steps = await focuser.device.get("position")
        assert await wheel.device.get("position") != 0  # the wheel restarts in slot 0

        simulator.stop()
        await wait_for(lambda: focuser.state is ModuleState.ERROR, 30.0, message="focuser in ERROR")
        simulator.start()
        modules = (focuser, wheel, camera, telescope, parked, relative)
        await wait_for(lambda: all(m.state is ModuleState.READY for m in modules), 30.0, message="READY")
        # The devices came back in their defaults, and each module set again what it had set.
        assert "focuser: the focuser came back at" in caplog.text
        assert "filters: the wheel came back at" in caplog.text
        assert await focuser.device.get("position") == steps
        assert await focuser.get_focus() == pytest.approx(focus)
        assert (await wheel.device.get("names"))[await wheel.device.get("position")] == chosen
        assert await wheel.get_filter() == chosen
        assert await camera.device.get("cooleron") is True
        assert await camera.device.get("setccdtemperature") == pytest.approx(-12.0)
        assert "telescope: the mount came back: tracking RA" in caplog.text
        assert (
            await telescope.device.get("tracking") is True and await telescope.device.get("atpark") is False
        )
        ra, dec = await telescope.get_radec()
        assert (ra, dec) == pytest.approx(target, abs=0.05)
        assert "parked: the mount came back unparked: parking it again" in caplog.text
        assert await parked.device.get("atpark") is True
        assert await parked.get_motion_status() is MotionStatus.PARKED
        assert "relative: the focuser came back" not in caplog.text
        assert await relative.get_focus() == pytest.approx(relative_focus)
