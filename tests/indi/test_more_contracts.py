"""The INDI rotator, weather and cover-calibrator modules pass their device contract suites
against the indi-bin simulators."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import pytest

from nightcrew.clock import RealClock
from nightcrew.interfaces import WeatherSensor
from nightcrew.modules.indi import IndiCoverCalibrator, IndiRotator, IndiWeather
from nightcrew.modules.module import Module
from nightcrew.testing import (
    ContractProbe,
    ContractSetup,
    CoverCalibratorContract,
    Observatory,
    RotatorContract,
    WeatherStationContract,
)
from nightcrew.testing.indi import SIMULATORS, IndiServer


async def _setup(
    server: IndiServer, cls: type[Module], driver: str, **options: Any
) -> AsyncIterator[ContractSetup[Any]]:
    async with Observatory(clock=RealClock()) as obs:
        probe = await obs.start(ContractProbe, "probe")
        module = await obs.start(
            cls, "device", host=server.host, port=server.port, device=SIMULATORS[driver], **options
        )
        yield ContractSetup(module, probe)


class TestIndiRotatorContract(RotatorContract):
    timeout = 60.0
    long_turn = 60.0  # degrees: 6 s at the simulator's 10°/s, long enough to interrupt

    @pytest.fixture
    async def contract(self, indi_server: IndiServer) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _setup(indi_server, IndiRotator, "indi_simulator_rotator"):
            yield setup


class TestIndiWeatherContract(WeatherStationContract):
    timeout = 60.0
    required_sensors = (WeatherSensor.TEMPERATURE, WeatherSensor.WIND_SPEED, WeatherSensor.SAFE)

    @pytest.fixture
    async def contract(self, indi_server: IndiServer) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _setup(indi_server, IndiWeather, "indi_simulator_weather", interval=1.0):
            yield setup


class TestIndiLightPanelContract(CoverCalibratorContract):
    """indi_simulator_lightpanel: a light without a cover."""

    @pytest.fixture
    async def contract(self, indi_server: IndiServer) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _setup(indi_server, IndiCoverCalibrator, "indi_simulator_lightpanel"):
            yield setup
