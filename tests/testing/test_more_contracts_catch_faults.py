"""The rotator, switch, cover-calibrator and weather-station suites fail on drivers that break the
contract, with a message that says how."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

import pytest

from nightcrew.interfaces import WeatherSensor
from nightcrew.modules import Module
from nightcrew.modules.sim import SimCoverCalibrator, SimRotator, SimSwitch, SimWeatherStation
from nightcrew.testing import (
    ContractProbe,
    ContractSetup,
    CoverCalibratorContract,
    Observatory,
    RotatorContract,
    SwitchContract,
    WeatherStationContract,
)


class SlippingRotator(SimRotator):
    """Reports its position angle 2° beyond where it turned."""

    async def _hw_get_position_angle(self) -> float:
        return (await super()._hw_get_position_angle() + 2.0) % 360.0


class LooseSwitch(SimSwitch):
    """Takes any value, in range or not."""

    async def set_switch_value(self, switch: int, value: float) -> None:
        self.values[switch] = value


class StubbornCover(SimCoverCalibrator):
    """Ignores halt_cover: the cover swings on."""

    async def _hw_halt_cover(self) -> None:
        pass


class KelvinStation(SimWeatherStation):
    """Reports the temperature in kelvin."""

    async def _hw_read_sensors(self) -> dict[WeatherSensor, float | None]:
        readings = await super()._hw_read_sensors()
        temperature = readings.get(WeatherSensor.TEMPERATURE)
        readings[WeatherSensor.TEMPERATURE] = None if temperature is None else temperature + 273.15
        return readings


class UnsafeStation(SimWeatherStation):
    """Its safety sensor says unsafe, yet its verdict (rain only) says good."""

    async def _hw_read_sensors(self) -> dict[WeatherSensor, float | None]:
        return {WeatherSensor.RAIN: 0.0, WeatherSensor.SAFE: 0.0}


@asynccontextmanager
async def setup(cls: type[Module], name: str, **kwargs: Any) -> AsyncIterator[ContractSetup[Any]]:
    async with Observatory(speed=100.0) as obs:
        probe = await obs.start(ContractProbe, "probe")
        yield ContractSetup(await obs.start(cls, name, **kwargs), probe)


async def test_a_rotator_reporting_off_target_fails() -> None:
    async with setup(SlippingRotator, "rotator") as contract:
        with pytest.raises(AssertionError, match=r"rotator at PA .*, sent to"):
            await RotatorContract().test_a_turn_gets_there_and_reports_its_status(contract)


async def test_a_switch_taking_values_off_its_range_fails() -> None:
    async with setup(LooseSwitch, "switch", switches=[{"name": "outlet"}]) as contract:
        with pytest.raises(pytest.fail.Exception, match="DID NOT RAISE"):
            await SwitchContract().test_values_off_range_or_off_step_are_refused_and_nothing_changes(contract)


async def test_a_cover_that_does_not_halt_fails() -> None:
    async with setup(StubbornCover, "flats") as contract:
        with pytest.raises(pytest.fail.Exception, match="DID NOT RAISE"):
            await CoverCalibratorContract().test_halt_cover_stops_a_moving_cover(contract)


async def test_a_station_in_kelvin_fails_the_unit_check() -> None:
    async with setup(KelvinStation, "weather") as contract:
        with pytest.raises(AssertionError, match=r"temperature = 2\d\d\.\d+: not within .*a wrong unit"):
            await WeatherStationContract().test_sensors_are_known_kinds_with_finite_values_in_their_units(
                contract
            )


async def test_a_station_good_while_unsafe_fails() -> None:
    async with setup(UnsafeStation, "weather") as contract:
        with pytest.raises(AssertionError, match="good while unsafe"):
            await WeatherStationContract().test_the_verdict_agrees_with_the_safety_sensor(contract)
