"""Faults every one of the dome, roof, rotator, switch, cover-calibrator, safety-monitor and
observing-conditions modules meets alike: a device the server does not have, and a server that
goes away and comes back (the module goes to ERROR and back to READY by itself)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from nightcrew.clock import RealClock
from nightcrew.config import build_object, load_config, validate_config
from nightcrew.interfaces import ModuleState
from nightcrew.modules.alpaca.covercalibrator import AlpacaCoverCalibrator
from nightcrew.modules.alpaca.device import AlpacaModule
from nightcrew.modules.alpaca.dome import AlpacaDome
from nightcrew.modules.alpaca.observingconditions import AlpacaObservingConditions
from nightcrew.modules.alpaca.roof import AlpacaRoof
from nightcrew.modules.alpaca.rotator import AlpacaRotator
from nightcrew.modules.alpaca.safetymonitor import AlpacaSafetyMonitor
from nightcrew.modules.alpaca.switch import AlpacaSwitch
from nightcrew.modules.module import Module
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import AlpacaSimulator

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "alpaca"
#: The example of each module, by file name.
EXAMPLE_FILES = {
    "dome.yaml": AlpacaDome,
    "roof.yaml": AlpacaRoof,
    "rotator.yaml": AlpacaRotator,
    "switch.yaml": AlpacaSwitch,
    "covercalibrator.yaml": AlpacaCoverCalibrator,
    "safetymonitor.yaml": AlpacaSafetyMonitor,
    "observingconditions.yaml": AlpacaObservingConditions,
}

MODULES: list[type[AlpacaModule]] = [
    AlpacaDome,
    AlpacaRoof,
    AlpacaRotator,
    AlpacaSwitch,
    AlpacaCoverCalibrator,
    AlpacaSafetyMonitor,
    AlpacaObservingConditions,
]


@pytest.mark.parametrize("cls", MODULES, ids=lambda cls: cls.__name__)
async def test_a_device_the_server_lacks_is_an_error_naming_device_and_call(
    cls: type[AlpacaModule], alpaca_simulator: AlpacaSimulator
) -> None:
    async with Observatory(clock=RealClock()) as obs:
        module = await obs.start(cls, "device", server=alpaca_simulator.url, device_number=9)
        assert module.state is ModuleState.ERROR
        error = await module.get_error_string()
        assert f"{cls.device_type} 9 at {alpaca_simulator.url}: PUT connected" in error
        assert f"Device {cls.device_type}:9 not found" in error


async def test_modules_recover_when_the_server_restarts(
    start_alpaca_simulator: Callable[..., AlpacaSimulator],
) -> None:
    simulator = start_alpaca_simulator()
    async with Observatory(clock=RealClock()) as obs:
        options: dict[str, Any] = {"server": simulator.url, "reconnect_interval": 0.2, "timeout": 2.0}
        modules = [await obs.start(cls, cls.__name__.lower(), **options) for cls in MODULES]
        assert [m.state for m in modules] == [ModuleState.READY] * len(modules)

        simulator.stop()
        await obs.wait_for(
            lambda: all(m.state is ModuleState.ERROR for m in modules), 30.0, message="every module noticing"
        )
        assert all(simulator.url in m._error_string for m in modules)

        simulator.start()
        await obs.wait_for(
            lambda: all(m.state is ModuleState.READY for m in modules),
            30.0,
            message="every module recovering",
        )
        roof = obs.module("alpacaroof", AlpacaRoof)
        await roof.close_roof()  # and they work again
        switch = obs.module("alpacaswitch", AlpacaSwitch)
        assert len(await switch.get_switches()) == 2


@pytest.mark.parametrize(("file", "cls"), EXAMPLE_FILES.items(), ids=list(EXAMPLE_FILES))
async def test_example_builds_and_drives_the_simulator(
    file: str, cls: type[AlpacaModule], alpaca_simulator: AlpacaSimulator
) -> None:
    config = load_config(EXAMPLES / file)
    validate_config(config, Module)
    # The examples name the usual port 11111; here the session's simulator stands in for it.
    module = build_object(
        {**config, "name": file.removesuffix(".yaml"), "server": alpaca_simulator.url}, Module
    )
    assert type(module) is cls
    try:
        await module.open()
        assert module.state is ModuleState.READY, module._error_string
    finally:
        await module.close()


def test_weather_example_takes_the_safety_monitor_as_a_station() -> None:
    config = load_config(EXAMPLES / "weather-safetymonitor.yaml")
    validate_config(config, Module)
    weather = build_object({**config, "name": "weather"}, Module)
    assert {check.name for check in weather._checks} >= {"safety.safe", "conditions.rain"}
