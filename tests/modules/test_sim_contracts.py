"""The simulated devices (and the test camera driver) pass every device contract suite.

On an accelerated clock as the simulated observatory runs them; the telescope and the roof also at
real time with fast settings, as a real device would be driven.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import pytest

from nightcrew.clock import RealClock
from nightcrew.interfaces import WeatherSensor
from nightcrew.modules.sim import (
    SimCamera,
    SimCoverCalibrator,
    SimDome,
    SimFilterWheel,
    SimFocuser,
    SimRoof,
    SimRotator,
    SimSwitch,
    SimTelescope,
    SimWeatherStation,
)
from nightcrew.testing import (
    CameraContract,
    ContractProbe,
    ContractSetup,
    CoverCalibratorContract,
    DomeContract,
    FilterWheelContract,
    FocuserContract,
    Observatory,
    RoofContract,
    RotatorContract,
    SwitchContract,
    TelescopeContract,
    WeatherStationContract,
)

from .devices import GradientCamera

#: The simulator's own devices the camera would ask for the scene: absent here.
NO_PEERS: dict[str, Any] = {
    "telescope": None,
    "focuser": None,
    "filters": None,
    "roof": None,
    "weather": None,
}


class TestSimTelescope(TelescopeContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimTelescope, "telescope"), probe)


class TestSimTelescopeInRealTime(TelescopeContract):
    long_step = 10.0

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory(clock=RealClock()) as obs:
            probe = await obs.start(ContractProbe, "probe")
            telescope = await obs.start(
                SimTelescope, "telescope", slew_rate=20.0, settle_time=0.1, init_time=0.1
            )
            yield ContractSetup(telescope, probe)


class TestSimCamera(CameraContract):
    cooled = True

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            camera = await obs.start(
                SimCamera,
                "camera",
                detector={"chip_width": 256, "chip_height": 256},
                readout_time=0.5,
                **NO_PEERS,
            )
            yield ContractSetup(camera, probe)


class TestGradientCamera(CameraContract):
    cooled = True

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(GradientCamera, "camera"), probe)


class TestSimRoof(RoofContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimRoof, "roof"), probe)


class TestSimRoofInRealTime(RoofContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory(clock=RealClock()) as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimRoof, "roof", open_time=1.0, close_time=1.0), probe)


class TestSimDome(DomeContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimDome, "dome"), probe)


class TestSimFocuser(FocuserContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimFocuser, "focuser"), probe)


class TestSimFilterWheel(FilterWheelContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            wheel = await obs.start(SimFilterWheel, "filters", filters=["B", "V", "R"])
            yield ContractSetup(wheel, probe)


class TestSimRotator(RotatorContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimRotator, "rotator", sky_offset=30.0), probe)


class TestSimSwitch(SwitchContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        switches = [
            {"name": "outlet", "value": 1.0},
            {"name": "dew heater", "min_value": 0.0, "max_value": 100.0, "step": 5.0, "value": 20.0},
            {"name": "voltage", "can_write": False, "max_value": 24.0, "step": 0.0, "value": 12.3},
        ]
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimSwitch, "switch", switches=switches), probe)


class TestSimCoverCalibrator(CoverCalibratorContract):
    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimCoverCalibrator, "flats"), probe)


class TestSimFlatPanel(CoverCalibratorContract):
    """A panel on the dome wall: a light and no cover."""

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimCoverCalibrator, "panel", cover=False), probe)


class TestSimWeatherStation(WeatherStationContract):
    required_sensors = (WeatherSensor.TEMPERATURE, WeatherSensor.HUMIDITY, WeatherSensor.RAIN)

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory() as obs:
            probe = await obs.start(ContractProbe, "probe")
            yield ContractSetup(await obs.start(SimWeatherStation, "weather", seed=3), probe)
