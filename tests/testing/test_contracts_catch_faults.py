"""The contract suites fail on drivers that break the contract, with a message that says how."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

import numpy as np
import pytest

from nightcrew.errors import RemoteTimeoutError
from nightcrew.events import BadWeatherEvent
from nightcrew.interfaces import Window
from nightcrew.modules import Module
from nightcrew.modules.camera import BaseCamera, ExposureSettings, Frame
from nightcrew.modules.sim import SimFilterWheel, SimRoof, SimTelescope
from nightcrew.testing import (
    CameraContract,
    ContractProbe,
    ContractSetup,
    FilterWheelContract,
    Observatory,
    RoofContract,
    TelescopeContract,
    timed_call,
)
from nightcrew.timeout import DEFAULT_TIMEOUT, timeout


class OffTargetTelescope(SimTelescope):
    """Reports 0.1° north of where it was sent."""

    async def _hw_get_radec(self) -> tuple[float, float]:
        ra, dec = await super()._hw_get_radec()
        return ra, dec + 0.1


class HastyTelescope(SimTelescope):
    """Announces 5 s for an Alt/Az slew that takes longer."""

    @timeout(5)
    async def move_altaz(self, alt: float, az: float) -> None:
        await super().move_altaz(alt, az)


class FullFrameCamera(BaseCamera):
    """Ignores the window: always returns the whole chip."""

    def _hw_full_frame(self) -> Window:
        return Window(0, 0, 64, 48)

    async def _hw_expose(self, settings: ExposureSettings) -> Frame:
        await self.clock.sleep(settings.exposure_time)
        return Frame(np.zeros((48, 64), dtype=np.uint16))


class CarelessRoof(SimRoof):
    """Does not close on bad weather."""

    async def on_bad_weather(self, event: BadWeatherEvent, sender: str) -> None:
        pass


@asynccontextmanager
async def setup(cls: type[Module], name: str, **kwargs: Any) -> AsyncIterator[ContractSetup[Any]]:
    async with Observatory() as obs:
        probe = await obs.start(ContractProbe, "probe")
        yield ContractSetup(await obs.start(cls, name, **kwargs), probe)


async def test_a_telescope_reporting_off_target_fails_the_pointing_check() -> None:
    async with setup(OffTargetTelescope, "telescope") as contract:
        with pytest.raises(AssertionError, match=r"move_radec: reported .* is 360\.0\" from the target"):
            await TelescopeContract().test_move_radec_tracks_the_target_and_announces_it(contract)


async def test_a_telescope_announcing_too_short_a_timeout_fails() -> None:
    async with setup(HastyTelescope, "telescope", slew_rate=1.0) as contract:
        # Called through the comm as every suite calls, the slew is cut off after what it announced.
        with pytest.raises(RemoteTimeoutError, match=r"move_altaz\(\) did not finish within 5 s"):
            await TelescopeContract().test_motions_end_within_the_timeouts_they_announce(contract)


async def test_a_camera_ignoring_the_window_fails_the_exposure() -> None:
    async with setup(FullFrameCamera, "camera") as contract:
        with pytest.raises(
            Exception, match=r"driver returned an image of shape \(48, 64\), expected \(12, 16\)"
        ):
            await CameraContract().test_an_exposure_writes_a_fits_file_and_announces_it(contract)


async def test_a_roof_ignoring_bad_weather_fails() -> None:
    class QuickRoofContract(RoofContract):
        timeout = 30.0

    async with setup(CarelessRoof, "roof", open_time=5.0) as contract:
        with pytest.raises(
            AssertionError, match="the roof closing on bad weather: not within 30 clock seconds"
        ):
            await QuickRoofContract().test_bad_weather_closes_and_keeps_closed_until_good_weather(contract)


async def test_a_motion_too_quick_to_interrupt_fails_saying_so() -> None:
    async with setup(SimFilterWheel, "filters", filters=["B", "V"], change_time=0.0) as contract:
        with pytest.raises(
            pytest.fail.Exception, match="finished a filter change before it could be interrupted"
        ):
            await FilterWheelContract().test_a_second_change_while_moving_is_busy(contract)


async def test_a_suite_without_its_fixture_says_what_is_missing() -> None:
    fixture = TelescopeContract.contract.__wrapped__  # type: ignore[attr-defined]
    with pytest.raises(NotImplementedError, match="TelescopeContract must override the 'contract' fixture"):
        await anext(fixture(TelescopeContract()))


async def test_timed_call_reports_the_announced_timeout_and_the_time_taken() -> None:
    async with setup(HastyTelescope, "telescope", slew_rate=1.0, settle_time=0.0, init_time=0.0) as contract:
        announced, took = await timed_call(contract, "init")  # IMotion.init announces 300 s
        assert announced == 300.0 and took < 1.0
        announced, _ = await timed_call(contract, "get_radec")  # announces nothing: the default
        assert announced == DEFAULT_TIMEOUT
        announced, took = await timed_call(contract, "move_altaz", 75.0, 0.0)  # 10° from park at 1°/s
        assert announced == 5.0 and took >= 10.0
