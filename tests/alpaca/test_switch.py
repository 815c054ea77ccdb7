"""AlpacaSwitch against alpaca-simulators' Switch: the list of switches, on/off and analog values."""

from __future__ import annotations

import asyncio
import math
from collections.abc import AsyncIterator
from dataclasses import replace

import pytest

from nightcrew.clock import RealClock
from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import ISwitch, SwitchInfo
from nightcrew.modules.alpaca.switch import AlpacaSwitch
from nightcrew.testing import EventRecorder, Observatory
from nightcrew.testing.alpaca import AlpacaSimulator


@pytest.fixture
def alpaca_server(alpaca_simulator: AlpacaSimulator) -> str:
    return alpaca_simulator.url


#: alpaca-simulators' switch device 0 as configured in its template.
POWER = SwitchInfo(
    index=0,
    name="Power Switch 1",
    description="Main power switch",
    can_write=True,
    min_value=0.0,
    max_value=1.0,
    step=1.0,
)
DIMMER = SwitchInfo(
    index=1,
    name="Dimmer 1",
    description="Variable brightness control",
    can_write=True,
    min_value=0.0,
    max_value=1.0,
    step=0.1,
)


@pytest.fixture
async def switches(alpaca_server: str) -> AsyncIterator[ISwitch]:
    async with Observatory(clock=RealClock()) as obs:
        probe = await obs.start(EventRecorder, "probe", types=[])
        module = await obs.start(AlpacaSwitch, "switch", server=alpaca_server)
        # Called as another module would, through a proxy: arguments and SwitchInfo travel the comm.
        proxy = await probe.comm.proxy("switch", ISwitch)
        yield proxy
        await module.set_switch(0, False)
        await module.set_switch_value(1, 0.5)


async def test_lists_the_switches_of_the_device(switches: ISwitch) -> None:
    assert await switches.get_switches() == [POWER, DIMMER]


async def test_on_off_switch(switches: ISwitch) -> None:
    await switches.set_switch(0, True)
    assert await switches.get_switch(0) is True
    assert await switches.get_switch_value(0) == 1.0
    await switches.set_switch(0, False)
    assert await switches.get_switch(0) is False
    assert await switches.get_switch_value(0) == 0.0


async def test_analog_value_in_steps(switches: ISwitch) -> None:
    await switches.set_switch_value(1, 0.7)
    assert await switches.get_switch_value(1) == pytest.approx(0.7)
    await switches.set_switch_value(1, 0.0)
    assert await switches.get_switch_value(1) == 0.0
    assert await switches.get_switch(1) is False


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (1.5, r"switch 1 \('Dimmer 1'\): 1.5 is outside 0..1"),
        (-0.1, r"switch 1 \('Dimmer 1'\): -0.1 is outside 0..1"),
        (math.nan, r"argument '\w+': NaN is not a finite number"),  # the RPC wire check refuses it first
        (0.25, r"switch 1 \('Dimmer 1'\): 0.25 is not 0 plus a multiple of the step 0.1"),
    ],
)
async def test_values_outside_range_or_step_are_refused(
    switches: ISwitch, value: float, message: str
) -> None:
    await switches.set_switch_value(1, 0.5)
    with pytest.raises(InvalidArgumentError, match=message):
        await switches.set_switch_value(1, value)
    assert await switches.get_switch_value(1) == pytest.approx(0.5)


async def test_unknown_switch_is_refused_naming_the_range(switches: ISwitch, alpaca_server: str) -> None:
    for index in (2, 7):  # past the device's switches: the device's range is named
        with pytest.raises(InvalidArgumentError, match=f"switch 0 at {alpaca_server} has switches 0..1, not"):
            await switches.get_switch(index)
        with pytest.raises(InvalidArgumentError, match=f"switch 0 at {alpaca_server} has switches 0..1, not"):
            await switches.set_switch(index, True)
    # below any switch: refused by the interface's bound before the device is asked
    with pytest.raises(InvalidArgumentError, match=r"argument 'switch': -1 is out of range \(must be >= 0\)"):
        await switches.get_switch_value(-1)


def test_read_only_switch_is_refused_before_the_device() -> None:
    # The simulators' switches are all writable; a read-only one is refused from the list alone.
    module = AlpacaSwitch(name="switch", server="http://127.0.0.1:1")
    module._switches = [POWER, replace(DIMMER, can_write=False)]
    with pytest.raises(NotSupportedError, match=r"switch 1 \('Dimmer 1'\) is read-only"):
        asyncio.run(module.set_switch_value(1, 0.5))
