"""nightcrew's Alpaca modules pass the device contract suites against AlpacaServer.

The chain: contract suite → AlpacaTelescope/AlpacaFocuser/AlpacaFilterWheel (the Alpaca client
modules) → HTTP → AlpacaServer → proxies → the simulated devices, all in real time. Whatever the
suites demand of a device (states, events, refusals, busy while moving, stop, park) must survive
the trip through Alpaca and back.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import pytest

from nightcrew.modules.alpaca import AlpacaFilterWheel, AlpacaFocuser, AlpacaTelescope
from nightcrew.modules.alpaca.dome import AlpacaDome
from nightcrew.testing import (
    SITE,
    ContractProbe,
    ContractSetup,
    DomeContract,
    FilterWheelContract,
    FocuserContract,
    Observatory,
    TelescopeContract,
)

from .served import served_observatory


async def _client(module_class: type[Any], name: str, **options: Any) -> AsyncIterator[ContractSetup[Any]]:
    # Motions of seconds, so the suites catch them under way even on a loaded machine.
    served_devices = served_observatory(
        slew_rate=10.0, focuser_speed=2.0, filter_change_time=2.0, dome_time=4.0
    )
    # The client's clock is the simulator's (real-time rate, a dark night): both sides must agree
    # on the sky, or a target the suite picks high up may be below the simulated horizon.
    async with served_devices as served, Observatory(clock=served.observatory.clock, site=SITE) as obs:
        probe = await obs.start(ContractProbe, "probe")
        module = await obs.start(module_class, name, server=served.url, **options)
        yield ContractSetup(module, probe)


class TestServedTelescope(TelescopeContract):
    timeout = 60.0

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _client(AlpacaTelescope, "telescope", slew_timeout=60.0):
            yield setup


class TestServedFocuser(FocuserContract):
    timeout = 60.0
    focus_start = 20.0

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _client(AlpacaFocuser, "focuser"):
            yield setup


class TestServedFilterWheel(FilterWheelContract):
    timeout = 60.0

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _client(AlpacaFilterWheel, "filters"):
            yield setup


class TestServedDome(DomeContract):
    timeout = 60.0

    @pytest.fixture
    async def contract(self) -> AsyncIterator[ContractSetup[Any]]:
        async for setup in _client(AlpacaDome, "dome"):
            yield setup
