"""Faults every one of the dome, roof, rotator, switch, cover-calibrator, safety-monitor and
observing-conditions modules meets alike: a device the server does not have, and a server that
goes away and comes back (the module goes to ERROR and back to READY by itself)."""

from __future__ import annotations

from collections.abc import AsyncIterator, Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest

from nightcrew.bridges.alpaca.errors import AlpacaReplyError
from nightcrew.clock import RealClock
from nightcrew.config import build_object, load_config, validate_config
from nightcrew.errors import ConfigError
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

from .faulty_server import FaultyServer, value

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


@pytest.fixture
async def faulty() -> AsyncIterator[FaultyServer]:
    """A device server answering what each test sets (and ``true`` to everything else)."""
    server = FaultyServer()
    await server.start()
    try:
        yield server
    finally:
        await server.stop()


Call = Callable[[Any], Awaitable[object]]

#: Sane replies a module needs at connect beyond the server's default ``true``.
_NUMBERS = ("humidity", "pressure", "windspeed", "winddirection", "rainrate", "skytemperature", "dewpoint")
GOOD_REPLIES: dict[type[AlpacaModule], dict[str, object]] = {
    AlpacaDome: {"shutterstatus": 1, "slaved": False},
    AlpacaSwitch: {
        "maxswitch": 1,
        "getswitchname": "relay",
        "getswitchdescription": "a relay",
        "minswitchvalue": 0.0,
        "maxswitchvalue": 1.0,
        "switchstep": 1.0,
    },
    AlpacaCoverCalibrator: {"coverstate": 1},
    AlpacaObservingConditions: {name: 1.0 for name in (*_NUMBERS, "skyquality")},
}


@pytest.mark.parametrize(
    ("cls", "member", "reply", "call", "wanted"),
    [
        (AlpacaRotator, "position", "north", lambda m: m.get_position_angle(), "a finite number"),
        (AlpacaDome, "azimuth", None, lambda m: m.get_azimuth(), "a finite number"),
        (AlpacaSwitch, "getswitch", 1, lambda m: m.get_switch(0), "true or false"),
        (AlpacaCoverCalibrator, "coverstate", 9, lambda m: m.get_cover_state(), r"an ASCOM state \(0..5\)"),
        (AlpacaSafetyMonitor, "issafe", "yes", lambda m: m.read_now(), "true or false"),
        (AlpacaObservingConditions, "temperature", "warm", lambda m: m.read_now(), "a finite number"),
    ],
    ids=lambda v: v.__name__ if isinstance(v, type) else None,
)
async def test_a_malformed_value_is_an_error_naming_device_call_and_value(
    faulty: FaultyServer, cls: type[AlpacaModule], member: str, reply: object, call: Call, wanted: str
) -> None:
    faulty.replies["connecting"] = value(False)
    for name, good in GOOD_REPLIES.get(cls, {}).items():
        faulty.replies[name] = value(good)
    async with Observatory(clock=RealClock()) as obs:
        module = await obs.start(cls, "device", server=faulty.url)
        assert module.state is ModuleState.READY, module._error_string
        faulty.replies[member] = value(reply)
        with pytest.raises(
            AlpacaReplyError, match=f"{cls.device_type} 0 at {faulty.url}: GET {member}: .* is not {wanted}"
        ):
            await call(module)


async def test_a_malformed_reply_at_connect_keeps_the_module_in_error(faulty: FaultyServer) -> None:
    faulty.replies["connecting"] = value(False)
    faulty.replies["shutterstatus"] = value(7)
    async with Observatory(clock=RealClock()) as obs:
        roof = await obs.start(AlpacaRoof, "roof", server=faulty.url, reconnect_interval=0.2)
        assert roof.state is ModuleState.ERROR
        assert "GET shutterstatus: 7 is not an ASCOM ShutterState (0..4)" in await roof.get_error_string()
        faulty.replies["shutterstatus"] = value(1)  # the device is fixed: the module reconnects
        await obs.wait_for(lambda: roof.state is ModuleState.READY, 30.0, message="the roof recovering")


@pytest.mark.parametrize(
    ("yaml", "message"),
    [
        (
            "class: nightcrew.modules.alpaca.AlpacaRoof\nserver: http://127.0.0.1:11111\n"
            "shutter_timeout: 1000\n",
            "module.yaml:3: key 'shutter_timeout': must be within 0..300 seconds (the announced timeout), "
            "got 1000",
        ),
        (
            "class: nightcrew.modules.alpaca.AlpacaCoverCalibrator\nserver: http://127.0.0.1:11111\n"
            "calibrator_timeout: 60\n",
            "module.yaml:3: key 'calibrator_timeout': must be within 0..60 seconds",
        ),
        (
            "class: nightcrew.modules.alpaca.AlpacaDome\nserver: http://127.0.0.1:11111\ndome_radius: 2\n"
            "mount_offset: [3, 0, 0]\n",
            "module.yaml:4: key 'mount_offset': the telescope pivot (3, 0, 0) m east/north/up is 3.000 m",
        ),
        (
            "class: nightcrew.modules.alpaca.AlpacaSwitch\nserver: 127.0.0.1:11111\n",
            "module.yaml:2: key 'server': an Alpaca server URL starts with http://",
        ),
    ],
)
def test_check_reports_a_bad_option_in_one_line(tmp_path: Path, yaml: str, message: str) -> None:
    # What `nightcrew check` runs: validation without building anything.
    path = tmp_path / "module.yaml"
    path.write_text(yaml)
    with pytest.raises(ConfigError) as raised:
        validate_config(load_config(path), Module)
    assert message in str(raised.value)
    assert "\n" not in str(raised.value)
