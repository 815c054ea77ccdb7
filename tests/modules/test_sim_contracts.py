"""The simulated devices (and the test camera driver) pass every device contract suite.

On an accelerated clock as the simulated observatory runs them; the telescope and the roof also at
real time with fast settings, as a real device would be driven.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import pytest

from nightcrew.clock import RealClock
from nightcrew.modules.sim import SimCamera, SimDome, SimFilterWheel, SimFocuser, SimRoof, SimTelescope
from nightcrew.testing import (
    CameraContract,
    ContractProbe,
    ContractSetup,
    DomeContract,
    FilterWheelContract,
    FocuserContract,
    Observatory,
    RoofContract,
    TelescopeContract,
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
