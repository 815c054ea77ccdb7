"""Every INDI module passes its device contract suite against the indi-bin simulators."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import pytest

from nightcrew.clock import RealClock
from nightcrew.modules.indi import IndiCamera, IndiDome, IndiFilterWheel, IndiFocuser, IndiTelescope
from nightcrew.modules.module import Module
from nightcrew.testing import (
    CameraContract,
    ContractProbe,
    ContractSetup,
    DomeContract,
    FilterWheelContract,
    FocuserContract,
    Observatory,
    TelescopeContract,
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


class TestIndiFocuserContract(FocuserContract):
    focus_start = 20.0
    long_focus_move = 60.0  # mm = 60000 steps: the simulator needs seconds for it

    @pytest.fixture
    async def contract(self, indi_server: IndiServer) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _setup(indi_server, IndiFocuser, "indi_simulator_focus", max_focus=100.0):
            yield setup


class TestIndiFilterWheelContract(FilterWheelContract):
    @pytest.fixture
    async def contract(self, indi_server: IndiServer) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _setup(indi_server, IndiFilterWheel, "indi_simulator_wheel"):
            yield setup


class TestIndiDomeContract(DomeContract):
    @pytest.fixture
    async def contract(self, indi_server: IndiServer) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _setup(indi_server, IndiDome, "indi_simulator_dome"):
            yield setup


class TestIndiTelescopeContract(TelescopeContract):
    @pytest.fixture
    async def contract(self, indi_server: IndiServer) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _setup(indi_server, IndiTelescope, "indi_simulator_telescope"):
            yield setup


class TestIndiCameraContract(CameraContract):
    cooled = True
    long_exposure_time = 30.0

    @pytest.fixture
    async def contract(self, indi_server: IndiServer) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _setup(indi_server, IndiCamera, "indi_simulator_ccd"):
            yield setup
