"""The Alpaca modules pass nightcrew's device contract suites against alpaca-simulators (real time)."""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from typing import Any

import pytest

from nightcrew.clock import RealClock
from nightcrew.interfaces import IFilters, IFocuser
from nightcrew.modules.alpaca import AlpacaCamera, AlpacaFilterWheel, AlpacaFocuser, AlpacaTelescope
from nightcrew.testing import (
    CameraContract,
    ContractProbe,
    ContractSetup,
    FilterWheelContract,
    FocuserContract,
    Observatory,
    TelescopeContract,
)
from nightcrew.testing.alpaca import SIMULATOR_SITE, AlpacaSimulator


class TestAlpacaTelescope(TelescopeContract):
    timeout = 60.0

    @pytest.fixture
    async def contract(self, alpaca_simulator: AlpacaSimulator) -> AsyncIterator[ContractSetup[Any]]:
        async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
            probe = await obs.start(ContractProbe, "probe")
            telescope = await obs.start(
                AlpacaTelescope, "telescope", server=alpaca_simulator.url, slew_timeout=60.0
            )
            yield ContractSetup(telescope, probe)


class TestAlpacaCamera(CameraContract):
    cooled = True
    timeout = 60.0
    long_exposure_time = 10.0

    @pytest.fixture
    async def contract(
        self, start_alpaca_simulator: Callable[..., AlpacaSimulator]
    ) -> AsyncIterator[ContractSetup[Any]]:
        # A private server per test: alpaca-simulators keeps computing an aborted frame and
        # publishes it as ready later, which would pass for the next test's frame.
        simulator = start_alpaca_simulator()
        async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
            probe = await obs.start(ContractProbe, "probe")
            camera = await obs.start(AlpacaCamera, "camera", server=simulator.url)
            yield ContractSetup(camera, probe)


async def _started(module_class: type[Any], name: str, url: str) -> AsyncIterator[ContractSetup[Any]]:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        probe = await obs.start(ContractProbe, "probe")
        yield ContractSetup(await obs.start(module_class, name, server=url), probe)


class TestAlpacaFocuser(FocuserContract):
    timeout = 60.0
    focus_start = 10.0  # mm: alpaca-simulators' best focus (step 10000 at 1 µm per step)

    @pytest.fixture
    async def contract(self, alpaca_simulator: AlpacaSimulator) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _started(AlpacaFocuser, "focuser", alpaca_simulator.url):
            yield setup

    # alpaca-simulators' focuser arrives in the same call (IsMoving is never true), so no move can
    # be caught under way; what holds instead: a long move arrives at once and the next one works.
    async def test_a_second_move_while_moving_is_busy(self, contract: ContractSetup[Any]) -> None:
        await self._moves_at_once(contract)

    async def test_stop_motion_stops_a_move(self, contract: ContractSetup[Any]) -> None:
        await self._moves_at_once(contract)
        await (await contract.proxy(IFocuser)).stop_motion()
        assert await contract.module.device.get("ismoving") is False

    async def _moves_at_once(self, contract: ContractSetup[Any]) -> None:
        focuser, start = await self._start(contract)
        await focuser.set_focus(start + self.long_focus_move)
        assert await contract.module.device.get("ismoving") is False
        assert await contract.module.device.get("position") == round((start + self.long_focus_move) * 1000)
        await focuser.set_focus(start)
        assert await focuser.get_focus() == pytest.approx(start, abs=self.focus_tolerance)


class TestAlpacaFilterWheel(FilterWheelContract):
    timeout = 60.0

    @pytest.fixture
    async def contract(self, alpaca_simulator: AlpacaSimulator) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _started(AlpacaFilterWheel, "filters", alpaca_simulator.url):
            yield setup

    async def test_a_second_change_while_moving_is_busy(self, contract: ContractSetup[Any]) -> None:
        # alpaca-simulators' wheel reports the new slot in the same call: no change can be caught
        # under way. What holds instead: the device is at the new slot as soon as the call returns.
        wheel, names, current = await self._wheel(contract)
        other = self._other(names, current)
        await wheel.set_filter(other)
        assert await contract.module.device.get("position") == names.index(other)
        assert isinstance(contract.module, IFilters)
