"""Faults: indiserver killed and restarted, a property in Alert, a spoiled stream. One clear error
naming device and property, the module in ERROR, no file half-written, recovery by itself."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

import pytest

from nightcrew.clock import RealClock
from nightcrew.errors import GrabImageError, ModuleError, MoveError
from nightcrew.interfaces import ModuleState, MotionStatus
from nightcrew.modules.indi import (
    IndiCamera,
    IndiCoverCalibrator,
    IndiDome,
    IndiFilterWheel,
    IndiFocuser,
    IndiRotator,
    IndiTelescope,
    IndiWeather,
)
from nightcrew.modules.module import Module
from nightcrew.testing import Observatory, wait_for
from nightcrew.testing.indi import SIMULATORS, IndiServer

from .faulty_proxy import FaultyProxy

MODULES: dict[str, tuple[type[Module], dict[str, Any]]] = {
    "indi_simulator_telescope": (IndiTelescope, {}),
    "indi_simulator_ccd": (IndiCamera, {}),
    "indi_simulator_focus": (IndiFocuser, {"max_focus": 100.0}),
    "indi_simulator_wheel": (IndiFilterWheel, {}),
    "indi_simulator_dome": (IndiDome, {}),
    "indi_simulator_weather": (IndiWeather, {"interval": 1.0}),
    "indi_simulator_rotator": (IndiRotator, {}),
    "indi_simulator_lightpanel": (IndiCoverCalibrator, {}),
}


async def _state(module: Module, state: ModuleState, within: float = 30.0) -> None:
    await wait_for(lambda: module.state is state, within, message=f"{module.name} to be {state}")


async def _files(obs: Observatory) -> list[str]:
    return sorted(await obs.vfs.find("/cache/*"))


async def test_modules_recover_when_indiserver_is_restarted(
    own_indi_server: Callable[..., IndiServer],
) -> None:
    server = own_indi_server()
    async with Observatory(clock=RealClock()) as obs:
        modules = {
            driver: await obs.start(
                cls,
                driver.removeprefix("indi_simulator_"),
                host=server.host,
                port=server.port,
                device=SIMULATORS[driver],
                **options,
            )
            for driver, (cls, options) in MODULES.items()
        }
        assert all(m.state is ModuleState.READY for m in modules.values())
        server.kill()
        for module in modules.values():
            await _state(module, ModuleState.ERROR)
            assert "lost" in await module.get_error_string()
        focuser = modules["indi_simulator_focus"]
        assert isinstance(focuser, IndiFocuser)
        with pytest.raises(ModuleError, match="error state"):
            focuser._guard_call("set_focus")
        server.start()
        for module in modules.values():
            await _state(module, ModuleState.READY)
        # Working again, each with a real action.
        await focuser.set_focus(await focuser.get_focus() + 1.0)
        wheel = modules["indi_simulator_wheel"]
        assert isinstance(wheel, IndiFilterWheel)
        await wheel.set_filter((await wheel.list_filters())[1])
        camera = modules["indi_simulator_ccd"]
        assert isinstance(camera, IndiCamera)
        await camera.set_exposure_time(0.1)
        assert (await camera.grab_data()).endswith(".fits")
        weather = modules["indi_simulator_weather"]
        assert isinstance(weather, IndiWeather)
        await weather.read_now()
        assert (await weather.get_current_weather()).sensors["temperature"] is not None
        panel = modules["indi_simulator_lightpanel"]
        assert isinstance(panel, IndiCoverCalibrator)
        await panel.calibrator_on(1)
        await panel.calibrator_off()


async def test_indiserver_killed_mid_exposure_and_mid_slew(
    own_indi_server: Callable[..., IndiServer],
) -> None:
    server = own_indi_server("indi_simulator_ccd", "indi_simulator_telescope")
    async with Observatory(clock=RealClock()) as obs:
        camera = await obs.start(
            IndiCamera, "camera", host=server.host, port=server.port, device="CCD Simulator"
        )
        telescope = await obs.start(
            IndiTelescope, "telescope", host=server.host, port=server.port, device="Telescope Simulator"
        )
        await telescope.init()
        _, az = await telescope.get_altaz()
        await camera.set_exposure_time(30.0)
        exposure = asyncio.ensure_future(camera.grab_data())
        slew = asyncio.ensure_future(telescope.move_altaz(45.0, (az + 120.0) % 360.0))
        await wait_for(lambda: telescope._motion_status is MotionStatus.SLEWING, 30.0, message="slewing")
        await wait_for(lambda: camera._busy, 30.0, message="exposing")
        server.kill()
        with pytest.raises(GrabImageError, match=r"CCD Simulator.*(lost|closed)"):
            await exposure
        with pytest.raises(MoveError, match=r"move_altaz failed: .*(lost|closed)"):
            await slew
        assert await _files(obs) == []
        await _state(camera, ModuleState.ERROR)
        await _state(telescope, ModuleState.ERROR)
        server.start()
        await _state(camera, ModuleState.READY)
        await _state(telescope, ModuleState.READY)
        await camera.set_exposure_time(0.1)
        assert await camera.grab_data() in await _files(obs)


async def test_a_property_in_alert_is_one_clear_error(indi_server: IndiServer) -> None:
    async with Observatory(clock=RealClock()) as obs:
        # The simulator's travel ends at 100000 steps = 100 mm; this config believes in 200 mm.
        focuser = await obs.start(
            IndiFocuser,
            "focuser",
            host=indi_server.host,
            port=indi_server.port,
            device="Focuser Simulator",
            max_focus=200.0,
        )
        with pytest.raises(MoveError, match=r"Focuser Simulator\.ABS_FOCUS_POSITION: went to Alert"):
            await focuser.set_focus(150.0)
        assert await focuser.get_motion_status() is MotionStatus.ERROR
        await focuser.set_focus(40.0)  # the next good move works
        assert await focuser.get_focus() == pytest.approx(40.0)


@pytest.mark.parametrize(
    ("fault", "message"),
    [
        ("truncate_blob", r"CCD Simulator\.CCD1: the stream ended inside a message"),
        ("lying_blob", r"CCD Simulator\.CCD1: BLOB CCD1 is larger than announced"),
        ("malformed", r"Focuser Simulator\.ABS_FOCUS_POSITION: malformed XML"),
    ],
)
async def test_a_spoiled_stream_fails_the_exposure_cleanly(
    indi_server: IndiServer, fault: str, message: str
) -> None:
    async with FaultyProxy(indi_server) as proxy, Observatory(clock=RealClock()) as obs:
        camera = await obs.start(
            IndiCamera, "camera", host="127.0.0.1", port=proxy.port, device="CCD Simulator"
        )
        await camera.set_exposure_time(0.2)
        proxy.spoil(fault)
        with pytest.raises(GrabImageError, match=message):
            await camera.grab_data()
        assert proxy.applied.is_set()
        assert await _files(obs) == []
        await _state(camera, ModuleState.ERROR)
        assert message.split(":")[0].replace("\\", "") in await camera.get_error_string()
        await _state(camera, ModuleState.READY)
        assert await camera.grab_data() in await _files(obs)


async def test_a_wheel_holding_other_filters_than_configured_is_an_error(indi_server: IndiServer) -> None:
    async with Observatory(clock=RealClock()) as obs:
        wheel = await obs.start(
            IndiFilterWheel,
            "wheel",
            host=indi_server.host,
            port=indi_server.port,
            device="Filter Simulator",
            filters=["U", "B", "V"],
            connect_timeout=3.0,
        )
        assert wheel.state is ModuleState.ERROR
        error = await wheel.get_error_string()
        assert "Filter Simulator.FILTER_NAME: the wheel holds ['Red', 'Green'" in error
        assert "expects ['U', 'B', 'V']" in error


async def test_a_module_started_before_its_server_is_ready_once_the_server_is(
    own_indi_server: Callable[..., IndiServer],
) -> None:
    server = own_indi_server("indi_simulator_focus")
    server.kill()
    async with Observatory(clock=RealClock()) as obs:
        focuser = await obs.start(
            IndiFocuser,
            "focuser",
            host=server.host,
            port=server.port,
            device="Focuser Simulator",
            connect_timeout=1.0,
        )
        assert focuser.state is ModuleState.ERROR
        error = await focuser.get_error_string()
        assert f"INDI device 'Focuser Simulator' on {server.host}:{server.port} not ready within 1 s" in error
        assert "cannot connect to indiserver" in error
        server.start()
        await _state(focuser, ModuleState.READY)
        await focuser.set_focus(await focuser.get_focus() - 0.5)  # the fresh simulator is at 50 of 0..50 mm
