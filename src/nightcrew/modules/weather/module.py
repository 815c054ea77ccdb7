"""The Weather module: readings from stations, judged by checks, announced as good or bad weather.

Every ``interval`` clock seconds the module reads all stations (combined stations last), runs every
check and feeds the combined verdict to a :class:`~nightcrew.weather.GoodWeatherGate`: bad weather
is announced at once with a BadWeatherEvent naming the failed checks; good weather only after the
verdict stayed good for ``min_good_time`` seconds, with a GoodWeatherEvent. Fail safe: a station
that fails keeps its last readings, which go stale (bad) after a check's ``max_age``; a station that
never answered, a sensor without a value or an error while evaluating is bad weather. A station
module that could not be read is read again at once when it comes online (at start-up, when the
weather module was up first, the verdict does not wait a whole ``interval``).

Example (see ``examples/weather.yaml``)::

    class: nightcrew.modules.weather.Weather
    stations:
      roof: {class: nightcrew.modules.weather.ModuleStation, module: weatherstation}
      sun: {class: nightcrew.modules.weather.SunStation}
    checks:
      roof.rain: {class: nightcrew.weather.Boolean, good_when: false}
      roof.humidity: {class: nightcrew.weather.Schmitt, bad_above: 90, good_below: 85}
      sun.sun_altitude: {class: nightcrew.weather.Switch, bad_above: -6}
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from datetime import UTC, datetime
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.events import BadWeatherEvent, GoodWeatherEvent, ModuleOpenedEvent
from nightcrew.interfaces import (
    FitsCard,
    IFitsHeaderBefore,
    IWeather,
    SensorValue,
    WeatherReport,
    WeatherSensor,
)
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.module import Module
from nightcrew.modules.weather.stations import CombinedStation, ModuleStation, Station, SunStation
from nightcrew.weather import CheckResult, Evaluator, GoodWeatherGate, Reading, SensorCheck, WeatherChange

__all__ = ["FITS_KEYWORDS", "Weather"]

log = logging.getLogger(__name__)

#: Sensor → (FITS keyword, comment) of the cards this module adds to image headers.
FITS_KEYWORDS: dict[str, tuple[str, str]] = {
    "temperature": ("WS-TEMP", "Ambient temperature [degC]"),
    "humidity": ("WS-HUMID", "Relative humidity [%]"),
    "pressure": ("WS-PRESS", "Air pressure [hPa]"),
    "wind_speed": ("WS-WIND", "Wind speed [km/h]"),
    "wind_direction": ("WS-WINDD", "Wind direction [deg E of N]"),
    "rain": ("WS-RAIN", "Rain (1) or dry (0)"),
    "sky_temperature": ("WS-SKYT", "Sky temperature [degC]"),
    "dew_point": ("WS-DEWPT", "Dew point [degC]"),
    "particles": ("WS-PART", "Particles [1/m3]"),
    "sun_altitude": ("WS-SUNAL", "Altitude of the Sun [deg]"),
}


class Weather(Module, IWeather, IFitsHeaderBefore):
    """Judges the weather from several stations and tells everybody when it changes.

    Args:
        stations: Station name → station (ModuleStation, HttpJsonStation, CsvFileStation,
            SunStation, Current, Average). Names must not contain dots.
        checks: ``station.sensor`` → an evaluator or a list of them (Boolean, Switch, Schmitt,
            Valid). Each check is also a Valid(max_age=300) check unless it lists its own Valid.
        interval: Clock seconds between two evaluations, > 0.
        min_good_time: Clock seconds the weather must stay good before it is declared good.
        station_timeout: Clock seconds one station may take to answer.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        stations: dict[str, Station],
        checks: dict[str, Evaluator | list[Evaluator]],
        interval: Period = 30.0,
        min_good_time: float = 900.0,
        station_timeout: float = 20.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        for key, value in (("interval", interval), ("station_timeout", station_timeout)):
            if not value > 0:
                raise ConfigError(f"must be > 0 seconds, got {value}", key=key)
        if not min_good_time >= 0:
            raise ConfigError(f"must be >= 0 seconds, got {min_good_time}", key="min_good_time")
        self._interval = float(interval)
        self._station_timeout = float(station_timeout)
        self._stations = _checked_stations(stations)
        if self.site is None and any(isinstance(s, SunStation) for s in self._stations.values()):
            raise ConfigError("a SunStation needs the observatory's site", key="site")
        self._checks = _checked_checks(checks, self._stations)
        for station in self._stations.values():
            self.add_child(station)
        self._gate = GoodWeatherGate(min_good_time)
        self._readings: dict[str, dict[str, Reading]] = {name: {} for name in self._stations}
        self._results: dict[str, CheckResult] = {}
        self._unread: set[str] = set()  # stations whose last read failed
        self._wake = asyncio.Event()
        self.add_background_task(self._evaluate_loop)

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(ModuleOpenedEvent, self.on_module_opened)

    async def on_module_opened(self, event: ModuleOpenedEvent, sender: str) -> None:
        unread = (self._stations[name] for name in self._unread)
        if any(isinstance(station, ModuleStation) and station.module == sender for station in unread):
            self._wake.set()

    # --- the loop ------------------------------------------------------------------------------

    async def _evaluate_loop(self) -> None:
        while True:
            self._wake.clear()
            await self.evaluate_now()
            with contextlib.suppress(TimeoutError):
                async with self.clock.timeout(self._interval):
                    await self._wake.wait()

    async def evaluate_now(self) -> None:
        """Read every station, run every check and announce a change (what the loop does)."""
        await self._read_stations()
        now = self.clock.time()
        try:
            for check in self._checks:
                reading = self._readings[check.station].get(check.sensor)
                self._results[check.name] = check.evaluate(reading, now, self._results.get(check.name))
            good = all(result.good for result in self._results.values())
        except Exception:  # a bug must not keep the roof open
            log.exception("%s: evaluating the weather failed; taking it as bad", self.name)
            good = False
        await self._announce(self._gate.update(good, now))

    async def _read_stations(self) -> None:
        sources = {n: s for n, s in self._stations.items() if not isinstance(s, CombinedStation)}
        results = await asyncio.gather(*(self._read_one(n, s) for n, s in sources.items()))
        for name, readings in zip(sources, results, strict=True):
            if readings is not None:
                self._readings[name] = readings
        for name, station in self._stations.items():
            if isinstance(station, CombinedStation):
                self._readings[name] = (await self._read_one(name, station)) or {}

    async def _read_one(self, name: str, station: Station) -> dict[str, Reading] | None:
        try:
            async with self.clock.timeout(self._station_timeout):
                readings = await station.read(self._readings)
            self._unread.discard(name)
            return readings
        except Exception as exc:  # keep the last readings: they turn stale, then bad
            self._unread.add(name)
            log.warning("%s: station %s failed: %s", self.name, name, exc or type(exc).__name__)
            return None

    async def _announce(self, change: WeatherChange | None) -> None:
        if change is WeatherChange.BAD:
            reason = self._bad_reason()
            log.warning("%s: weather is bad: %s", self.name, reason)
            await self.comm.send_event(BadWeatherEvent(reason=reason))
        elif change is WeatherChange.GOOD:
            log.info("%s: weather is good", self.name)
            await self.comm.send_event(GoodWeatherEvent(eta=self.clock.now()))

    def _bad_reason(self) -> str:
        failed = [f"{name}: {r.reason}" for name, r in self._results.items() if not r.good]
        return ", ".join(failed) or "evaluation failed"

    # --- IWeather ------------------------------------------------------------------------------

    async def is_weather_good(self) -> bool:
        return self._gate.is_good

    async def get_current_weather(self) -> WeatherReport:
        sensors: dict[str, float | None] = {}
        for check in self._checks:
            reading = self._readings[check.station].get(check.sensor)
            sensors.setdefault(check.sensor, None if reading is None else reading.value)
        return WeatherReport(time=self.clock.now(), good=self._gate.is_good, sensors=sensors)

    async def get_sensor_value(self, station: str, sensor: WeatherSensor) -> SensorValue:
        if station not in self._stations:
            known = ", ".join(sorted(self._stations))
            raise InvalidArgumentError(f"no station '{station}'; known: {known}")
        reading = self._readings[station].get(WeatherSensor(sensor).value)
        if reading is None:
            return SensorValue(time=self.clock.now(), value=None)
        return SensorValue(time=datetime.fromtimestamp(reading.time, tz=UTC), value=reading.value)

    # --- IFitsHeaderBefore ---------------------------------------------------------------------

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        weather = await self.get_current_weather()
        cards: dict[str, FitsCard] = {"WS-GOOD": (weather.good, "Weather declared good")}
        for sensor, value in weather.sensors.items():
            if sensor in FITS_KEYWORDS and value is not None:
                keyword, comment = FITS_KEYWORDS[sensor]
                cards[keyword] = (round(value, 3), comment)
        return cards

    # --- run-time configuration ----------------------------------------------------------------

    def _get_config_min_good_time(self) -> float:
        return self._gate.min_good_time

    def _set_config_min_good_time(self, value: float) -> None:
        if not value >= 0:
            raise InvalidArgumentError(f"min_good_time must be >= 0 seconds, got {value}")
        self._gate.min_good_time = float(value)


def _checked_stations(stations: dict[str, Station]) -> dict[str, Station]:
    if not stations:
        raise ConfigError("name at least one station", key="stations")
    for name, station in stations.items():
        if not name or "." in name:
            raise ConfigError(f"station name {name!r} must be non-empty without dots", key="stations")
        if not isinstance(station, Station):
            raise ConfigError(f"expected a Station, got {type(station).__name__}", key=f"stations.{name}")
        if isinstance(station, CombinedStation):
            for source in station.stations:
                if source not in stations or isinstance(stations[source], CombinedStation):
                    raise ConfigError(
                        f"'{source}' is not a (non-combined) station of this module", key=f"stations.{name}"
                    )
    return dict(stations)


def _checked_checks(
    checks: dict[str, Evaluator | list[Evaluator]], stations: dict[str, Station]
) -> list[SensorCheck]:
    if not checks:
        raise ConfigError("name at least one check (station.sensor: evaluator)", key="checks")
    built = []
    for name, evaluators in checks.items():
        station, _, sensor = name.partition(".")
        if station not in stations or not sensor:
            known = ", ".join(sorted(stations))
            raise ConfigError(f"'{name}' is not station.sensor with a known station ({known})", key="checks")
        listed = evaluators if isinstance(evaluators, list) else [evaluators]
        if not all(isinstance(e, Evaluator) for e in listed):
            raise ConfigError("expected evaluators (Boolean, Switch, Schmitt, Valid)", key=f"checks.{name}")
        built.append(SensorCheck(station, sensor, listed))
    return built
