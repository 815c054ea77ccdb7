"""AlpacaSafetyMonitor against alpaca-simulators' SafetyMonitor, as an input of the Weather module:
an unsafe device closes the observatory (BadWeatherEvent), a safe one lets it open again."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from nightcrew.bridges.alpaca import AlpacaClient, AlpacaDevice
from nightcrew.clock import RealClock
from nightcrew.events import BadWeatherEvent, GoodWeatherEvent
from nightcrew.interfaces import WeatherSensor
from nightcrew.modules.alpaca.safetymonitor import AlpacaSafetyMonitor
from nightcrew.modules.weather import ModuleStation, Weather
from nightcrew.testing import EventRecorder, Observatory
from nightcrew.testing.alpaca import AlpacaSimulator
from nightcrew.weather import Boolean


@pytest.fixture
def alpaca_server(alpaca_simulator: AlpacaSimulator) -> str:
    return alpaca_simulator.url


@pytest.fixture
async def safety_device(alpaca_server: str) -> AsyncIterator[AlpacaDevice]:
    """The simulator's safety monitor, to make it safe or unsafe (its own test API: PUT issafe)."""
    async with AlpacaClient(alpaca_server) as client:
        device = client.device("safetymonitor", 0)
        await device.put("issafe", IsSafe=True)
        yield device
        await device.put("issafe", IsSafe=True)


async def test_is_safe_is_the_verdict_and_the_safe_sensor(
    alpaca_server: str, safety_device: AlpacaDevice
) -> None:
    async with Observatory(clock=RealClock()) as obs:
        monitor = await obs.start(AlpacaSafetyMonitor, "safety", server=alpaca_server, interval=60.0)
        assert await monitor.is_weather_good() is True
        assert (await monitor.get_sensor_value("safety", WeatherSensor.SAFE)).value == 1.0
        await safety_device.put("issafe", IsSafe=False)
        await monitor.read_now()
        assert await monitor.is_weather_good() is False
        report = await monitor.get_current_weather()
        assert report.good is False and report.sensors == {"safe": 0.0}


async def test_unsafe_device_makes_the_weather_module_announce_bad_weather(
    alpaca_server: str, safety_device: AlpacaDevice
) -> None:
    async with Observatory(clock=RealClock()) as obs:
        recorder = await obs.start(EventRecorder, "recorder", types=[BadWeatherEvent, GoodWeatherEvent])
        await obs.start(AlpacaSafetyMonitor, "safety", server=alpaca_server, interval=0.2)
        weather = await obs.start(
            Weather,
            "weather",
            stations={"alpaca": ModuleStation(module="safety")},
            checks={"alpaca.safe": Boolean(good_when=True)},
            interval=0.2,
            min_good_time=0.0,
        )
        await recorder.wait_for_event(GoodWeatherEvent, 10.0, sender="weather")
        await safety_device.put("issafe", IsSafe=False)
        bad = await recorder.wait_for_event(BadWeatherEvent, 10.0, sender="weather")
        assert "alpaca.safe" in bad.reason
        assert await weather.is_weather_good() is False
        await safety_device.put("issafe", IsSafe=True)
        recorder.clear()
        await recorder.wait_for_event(GoodWeatherEvent, 10.0, sender="weather")
