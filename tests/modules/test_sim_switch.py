"""BaseSwitch through SimSwitch: the switch list, on/off, analog values and what is refused."""

from __future__ import annotations

from collections.abc import Awaitable, Callable

import pytest

from nightcrew.config import build_object
from nightcrew.errors import ConfigError, InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import ISwitch, SwitchInfo
from nightcrew.modules.sim import SimSwitch
from nightcrew.testing import EventRecorder, Observatory

SWITCHES = [
    {"name": "Mount power"},
    {"name": "Dew heater", "description": "Secondary mirror", "max_value": 100, "step": 5, "value": 20},
    {
        "name": "Supply voltage",
        "can_write": False,
        "min_value": 0,
        "max_value": 15,
        "step": 0.1,
        "value": 12.3,
    },
]


@pytest.fixture
async def switches(observatory: Observatory) -> ISwitch:
    probe = await observatory.start(EventRecorder, "probe", types=[])
    await observatory.start(SimSwitch, "switch", switches=SWITCHES)
    return await probe.comm.proxy("switch", ISwitch)


async def test_the_list_says_names_ranges_and_steps(switches: ISwitch) -> None:
    infos = await switches.get_switches()
    assert infos[0] == SwitchInfo(0, "Mount power", "", True, 0.0, 1.0, 1.0)
    assert infos[1] == SwitchInfo(1, "Dew heater", "Secondary mirror", True, 0.0, 100.0, 5.0)
    assert infos[2].can_write is False and infos[2].index == 2


async def test_on_off_is_maximum_and_minimum(switches: ISwitch) -> None:
    assert await switches.get_switch(0) is False
    await switches.set_switch(0, True)
    assert await switches.get_switch(0) is True and await switches.get_switch_value(0) == 1.0
    await switches.set_switch(1, True)
    assert await switches.get_switch_value(1) == 100.0
    await switches.set_switch_value(1, 35.0)
    assert await switches.get_switch_value(1) == 35.0 and await switches.get_switch(1) is True
    await switches.set_switch(1, False)
    assert await switches.get_switch_value(1) == 0.0


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (
            lambda s: s.set_switch_value(1, 101.0),
            InvalidArgumentError,
            r"'Dew heater'\): 101.0 is outside 0..100",
        ),
        (lambda s: s.set_switch_value(1, 33.0), InvalidArgumentError, "not 0 plus a multiple of the step 5"),
        (
            lambda s: s.set_switch_value(2, 12.0),
            NotSupportedError,
            r"switch 2 \('Supply voltage'\) is read-only",
        ),
        (lambda s: s.set_switch(2, True), NotSupportedError, "read-only"),
        (lambda s: s.get_switch(3), InvalidArgumentError, "switch has switches 0..2, not 3"),
    ],
)
async def test_refusals(
    switches: ISwitch, call: Callable[[ISwitch], Awaitable[object]], error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match=message):
        await call(switches)
    assert await switches.get_switch_value(1) == 20.0


@pytest.mark.parametrize(
    ("switch", "key"),
    [
        ({"description": "no name"}, "switches[0].name"),
        ({"name": "x", "min_value": 2, "max_value": 1}, "switches[0]"),
        ({"name": "x", "step": 3}, "switches[0].step"),
        ({"name": "x", "value": 5}, "switches[0].value"),
        ({"name": "x", "colour": "red"}, "switches[0]"),
    ],
)
def test_bad_switch_configs_name_the_key(switch: dict[str, object], key: str) -> None:
    with pytest.raises(ConfigError) as raised:
        build_object({"class": "nightcrew.modules.sim.SimSwitch", "name": "switch", "switches": [switch]})
    assert raised.value.key == key
