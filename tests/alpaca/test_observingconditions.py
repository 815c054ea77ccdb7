"""AlpacaObservingConditions against alpaca-simulators' ObservingConditions: sensors in nightcrew's
units, changes seen at the next reading."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from nightcrew.bridges.alpaca import AlpacaClient, AlpacaDevice
from nightcrew.clock import RealClock
from nightcrew.interfaces import WeatherSensor
from nightcrew.modules.alpaca.observingconditions import AlpacaObservingConditions
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import AlpacaSimulator


@pytest.fixture
def alpaca_server(alpaca_simulator: AlpacaSimulator) -> str:
    return alpaca_simulator.url


#: What the test sets on the simulator (its own test API: PUT of each property), in Alpaca units.
SET = {"temperature": 12.5, "humidity": 71.0, "windspeed": 5.0, "rainrate": 0.0, "skyquality": 20.5}


@pytest.fixture
async def conditions_device(alpaca_server: str) -> AsyncIterator[AlpacaDevice]:
    async with AlpacaClient(alpaca_server) as client:
        device = client.device("observingconditions", 0)
        before = {member: await device.get(member) for member in SET}
        for member, value in SET.items():
            await device.put(member, **{_parameter(member): value})
        yield device
        for member, value in before.items():
            await device.put(member, **{_parameter(member): value})


def _parameter(member: str) -> str:
    return {
        "temperature": "Temperature",
        "humidity": "Humidity",
        "windspeed": "WindSpeed",
        "rainrate": "RainRate",
        "skyquality": "SkyQuality",
    }[member]


async def test_sensors_in_nightcrew_units(alpaca_server: str, conditions_device: AlpacaDevice) -> None:
    async with Observatory(clock=RealClock()) as obs:
        station = await obs.start(
            AlpacaObservingConditions, "conditions", server=alpaca_server, interval=60.0
        )
        report = await station.get_current_weather()
        assert report.sensors["temperature"] == 12.5
        assert report.sensors["humidity"] == 71.0
        assert report.sensors["wind_speed"] == pytest.approx(18.0)  # 5 m/s in km/h
        assert report.sensors["rain"] == 0.0
        assert report.sensors["sky_brightness"] == 20.5
        # The simulator implements every mapped property; those without a nightcrew sensor are not read.
        assert set(report.sensors) == {
            "temperature",
            "humidity",
            "pressure",
            "wind_speed",
            "wind_direction",
            "rain",
            "sky_temperature",
            "dew_point",
            "sky_brightness",
        }
        assert report.good is True  # fresh and dry
        assert await station.get_temperatures() == {"ambient": 12.5}


async def test_rain_is_seen_at_the_next_reading(alpaca_server: str, conditions_device: AlpacaDevice) -> None:
    async with Observatory(clock=RealClock()) as obs:
        station = await obs.start(AlpacaObservingConditions, "conditions", server=alpaca_server, interval=0.2)
        await conditions_device.put("rainrate", RainRate=2.5)

        async def raining() -> bool:
            return (await station.get_sensor_value("conditions", WeatherSensor.RAIN)).value == 1.0

        await obs.wait_for(raining, 10.0, message="the station reporting rain")
        assert await station.is_weather_good() is False
