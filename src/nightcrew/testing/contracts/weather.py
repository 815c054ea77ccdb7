"""The weather-station contract: known sensors in their units, finite or missing values, fresh
readings, the safety verdict as a sensor, and refusals of a weather-station (IWeather) module."""

from __future__ import annotations

import math
from datetime import UTC, datetime
from typing import Any, ClassVar

import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import ITemperatures, IWeather, WeatherReport, WeatherSensor
from nightcrew.testing.contracts._base import ContractSetup, DeviceContract

__all__ = ["WeatherStationContract"]

#: Plausible values of each sensor in nightcrew's units (see WeatherSensor): a value outside is
#: most likely in another unit (°F, m/s, Pa, a fraction instead of percent).
SENSOR_RANGES: dict[WeatherSensor, tuple[float, float]] = {
    WeatherSensor.TEMPERATURE: (-90.0, 65.0),
    WeatherSensor.HUMIDITY: (0.0, 100.0),
    WeatherSensor.PRESSURE: (300.0, 1100.0),
    WeatherSensor.WIND_SPEED: (0.0, 400.0),
    WeatherSensor.WIND_DIRECTION: (0.0, 360.0),
    WeatherSensor.RAIN: (0.0, 1.0),
    WeatherSensor.SKY_TEMPERATURE: (-120.0, 65.0),
    WeatherSensor.DEW_POINT: (-120.0, 65.0),
    WeatherSensor.SUN_ALTITUDE: (-90.0, 90.0),
    WeatherSensor.PARTICLES: (0.0, math.inf),
    WeatherSensor.SKY_BRIGHTNESS: (0.0, 30.0),
    WeatherSensor.SAFE: (0.0, 1.0),
}
#: Sensors that are flags: exactly 0 or 1.
FLAGS = (WeatherSensor.RAIN, WeatherSensor.SAFE)


class WeatherStationContract(DeviceContract):
    """Contract of a weather-station module: an :class:`~nightcrew.interfaces.IWeather` that answers
    for its own sensors (see :mod:`nightcrew.testing`). Give the station a short polling interval:
    the suite waits (up to :attr:`timeout`) for a newer reading.
    """

    interface = IWeather
    #: Sensors the device must report (e.g. ``(WeatherSensor.SAFE,)`` for a safety monitor).
    required_sensors: ClassVar[tuple[WeatherSensor, ...]] = ()
    #: Plausible range of each sensor's values in nightcrew's units.
    sensor_ranges: ClassVar[dict[WeatherSensor, tuple[float, float]]] = SENSOR_RANGES

    async def _report(self, contract: ContractSetup[Any]) -> tuple[IWeather, WeatherReport]:
        """The proxy and a report with sensors in it (that one comes at once: see the next test)."""
        station = await contract.proxy(IWeather)
        reports: list[WeatherReport] = []

        async def with_sensors() -> bool:
            reports.append(await station.get_current_weather())
            return bool(reports[-1].sensors)

        await contract.wait_for(with_sensors, self.timeout, f"{contract.name} reporting any sensor")
        return station, reports[-1]

    async def test_a_ready_station_reports_its_sensors_at_once(self, contract: ContractSetup[Any]) -> None:
        report = await (await contract.proxy(IWeather)).get_current_weather()
        assert report.sensors, f"{contract.name} is ready but reports no sensors (read them before READY)"

    async def test_sensors_are_known_kinds_with_finite_values_in_their_units(
        self, contract: ContractSetup[Any]
    ) -> None:
        _, report = await self._report(contract)
        known = {sensor.value for sensor in WeatherSensor}
        assert set(report.sensors) <= known, f"unknown sensors: {sorted(set(report.sensors) - known)}"
        for name, value in report.sensors.items():
            if value is None:
                continue  # declared missing
            sensor = WeatherSensor(name)
            assert math.isfinite(value), f"{name} = {value}"
            low, high = self.sensor_ranges[sensor]
            assert low <= value <= high, f"{name} = {value}: not within {low}..{high}, a wrong unit?"
            if sensor in FLAGS:
                assert value in (0.0, 1.0), f"{name} = {value}: a flag is 0 or 1"
        missing = [s.value for s in self.required_sensors if report.sensors.get(s.value) is None]
        assert not missing, f"{contract.name} has no value for {missing}"

    async def test_readings_are_timed_and_renewed(self, contract: ContractSetup[Any]) -> None:
        station, first = await self._report(contract)
        assert first.time.tzinfo is not None, "report time without a time zone"
        now = datetime.fromtimestamp(contract.clock.time(), tz=UTC)
        assert (now - first.time).total_seconds() <= self.timeout, f"reading of {first.time} at {now}"

        async def renewed() -> bool:
            return (await station.get_current_weather()).time > first.time

        await contract.wait_for(renewed, self.timeout, f"{contract.name} reading its sensors again")

    async def test_each_sensor_is_asked_for_by_name(self, contract: ContractSetup[Any]) -> None:
        station, report = await self._report(contract)
        for station_name in ("", contract.name):
            for name in report.sensors:
                reading = await station.get_sensor_value(station_name, WeatherSensor(name))
                assert reading.value is None or math.isfinite(reading.value), f"{name} = {reading.value}"
                assert reading.time >= report.time

    async def test_other_stations_and_absent_sensors_are_refused(self, contract: ContractSetup[Any]) -> None:
        station, report = await self._report(contract)
        sensor = WeatherSensor(next(iter(report.sensors)))
        with pytest.raises(InvalidArgumentError):
            await station.get_sensor_value(f"not-{contract.name}", sensor)
        for absent in (s for s in WeatherSensor if s.value not in report.sensors):
            with pytest.raises(InvalidArgumentError):
                await station.get_sensor_value(contract.name, absent)

    async def test_the_verdict_agrees_with_the_safety_sensor(self, contract: ContractSetup[Any]) -> None:
        station = await contract.proxy(IWeather)

        async def agree() -> bool:
            report = await station.get_current_weather()
            good = await station.is_weather_good()
            if (await station.get_current_weather()).time != report.time:
                return False  # a reading came in between: try again
            assert report.good is good, f"{contract.name}: report says good={report.good}, verdict {good}"
            safe = report.sensors.get(WeatherSensor.SAFE.value)
            assert safe is None or good is False or safe == 1.0, f"{contract.name}: good while unsafe"
            rain = report.sensors.get(WeatherSensor.RAIN.value)
            assert rain != 1.0 or good is False, f"{contract.name}: good while it rains"
            return True

        await contract.wait_for(agree, self.timeout, "two reports of the same reading")

    async def test_the_ambient_temperature_is_the_temperature_sensor(
        self, contract: ContractSetup[Any]
    ) -> None:
        assert isinstance(contract.module, ITemperatures), f"{contract.name} gives no temperatures"
        temperatures = await contract.proxy(ITemperatures)
        station = await contract.proxy(IWeather)

        async def agree() -> bool:
            before = await station.get_current_weather()
            ambient = (await temperatures.get_temperatures()).get("ambient")
            after = await station.get_current_weather()
            if after.time != before.time:
                return False  # a reading came in between: try again
            assert ambient == before.sensors.get(WeatherSensor.TEMPERATURE.value)
            return True

        await contract.wait_for(agree, self.timeout, "two readings of the same time")
