"""The rotator, switch, cover-calibrator, observing-conditions and safety-monitor modules pass
nightcrew's device contract suites against alpaca-simulators (real time)."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import pytest

from nightcrew.clock import RealClock
from nightcrew.errors import NotSupportedError
from nightcrew.interfaces import CoverState, ICoverCalibrator, IRotator, MotionStatus, WeatherSensor
from nightcrew.modules.alpaca import (
    AlpacaCoverCalibrator,
    AlpacaObservingConditions,
    AlpacaRotator,
    AlpacaSafetyMonitor,
    AlpacaSwitch,
)
from nightcrew.testing import (
    ContractProbe,
    ContractSetup,
    CoverCalibratorContract,
    Observatory,
    RotatorContract,
    SwitchContract,
    WeatherStationContract,
)
from nightcrew.testing.alpaca import AlpacaSimulator

from .more_devices import FLIP_FLAT, PANEL


async def _started(module_class: type[Any], url: str, **options: Any) -> AsyncIterator[ContractSetup[Any]]:
    async with Observatory(clock=RealClock()) as obs:
        probe = await obs.start(ContractProbe, "probe")
        yield ContractSetup(await obs.start(module_class, "device", server=url, **options), probe)


class TestAlpacaRotator(RotatorContract):
    timeout = 60.0

    @pytest.fixture
    async def contract(self, alpaca_simulator: AlpacaSimulator) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _started(AlpacaRotator, alpaca_simulator.url):
            yield setup

    # alpaca-simulators' rotator arrives within the Move call (IsMoving is never true), so no turn
    # can be caught under way; what holds instead: a long turn has arrived when the call returns,
    # the device is not moving, and Halt is accepted and leaves the rotator usable.
    async def test_a_second_turn_while_turning_is_busy(self, contract: ContractSetup[Any]) -> None:
        await self._turns_at_once(contract)

    async def test_stop_motion_stops_a_turn_on_the_way(self, contract: ContractSetup[Any]) -> None:
        await self._turns_at_once(contract)
        await (await contract.proxy(IRotator)).stop_motion()
        assert await contract.module.device.get("ismoving") is False
        assert await (await contract.proxy(IRotator)).get_motion_status() is MotionStatus.IDLE

    async def _turns_at_once(self, contract: ContractSetup[Any]) -> None:
        rotator, start = await self._start(contract)
        target = (start + self.long_turn) % 360.0
        await rotator.move_position_angle(target)
        assert await contract.module.device.get("ismoving") is False
        assert self._near(await contract.module.device.get("position"), target)
        await rotator.move_position_angle(start)
        assert self._near(await rotator.get_position_angle(), start)


class TestAlpacaSwitch(SwitchContract):
    timeout = 60.0

    @pytest.fixture
    async def contract(self, alpaca_simulator: AlpacaSimulator) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _started(AlpacaSwitch, alpaca_simulator.url):
            yield setup


class TestAlpacaCoverCalibrator(CoverCalibratorContract):
    timeout = 60.0

    @pytest.fixture
    async def contract(self, more_devices_url: str) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _started(AlpacaCoverCalibrator, more_devices_url, device_number=FLIP_FLAT):
            yield setup

    async def test_halt_cover_stops_a_moving_cover(self, contract: ContractSetup[Any]) -> None:
        # alpaca-simulators' cover moves within the OpenCover call (CoverState is never Moving) and
        # it answers HaltCover with NotImplemented, as Alpaca allows for such a cover. What holds
        # instead: the refusal arrives as NotSupportedError and the cover stays where it was.
        device = await contract.proxy(ICoverCalibrator)
        await device.open_cover()
        assert await device.get_cover_state() is CoverState.OPEN
        with pytest.raises(NotSupportedError, match="HaltCover"):
            await device.halt_cover()
        assert await device.get_cover_state() is CoverState.OPEN
        await device.close_cover()
        assert await device.get_cover_state() is CoverState.CLOSED


class TestAlpacaFlatPanel(CoverCalibratorContract):
    """alpaca-simulators' cover-calibrator 1 of the private simulator: a light without a cover."""

    timeout = 60.0

    @pytest.fixture
    async def contract(self, more_devices_url: str) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _started(AlpacaCoverCalibrator, more_devices_url, device_number=PANEL):
            yield setup


class TestAlpacaObservingConditions(WeatherStationContract):
    timeout = 60.0
    required_sensors = (
        WeatherSensor.TEMPERATURE,
        WeatherSensor.HUMIDITY,
        WeatherSensor.PRESSURE,
        WeatherSensor.WIND_SPEED,
        WeatherSensor.RAIN,
    )

    @pytest.fixture
    async def contract(self, alpaca_simulator: AlpacaSimulator) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _started(AlpacaObservingConditions, alpaca_simulator.url, interval=1.0):
            yield setup


class TestAlpacaSafetyMonitor(WeatherStationContract):
    timeout = 60.0
    required_sensors = (WeatherSensor.SAFE,)

    @pytest.fixture
    async def contract(self, alpaca_simulator: AlpacaSimulator) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _started(AlpacaSafetyMonitor, alpaca_simulator.url, interval=1.0):
            yield setup
