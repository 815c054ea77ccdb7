"""Where the Weather module's readings come from: one class per kind of station.

A station is a child object of the Weather module (it shares its clock, comm, VFS and site) whose
:meth:`Station.read` returns the latest readings by sensor name (``temperature``, ``rain``,
``sun_altitude`` ...). A station that fails raises; the module keeps its last readings, which turn
stale and so bad after a check's ``max_age``. :class:`Current` and :class:`Average` read nothing
themselves: they combine the readings of other stations of the same module.
"""

from __future__ import annotations

import logging
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from typing import Any

from nightcrew.astro import sun_altitude
from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.interfaces import IModule, IWeather, ModuleState
from nightcrew.object import Object
from nightcrew.weather import (
    DEFAULT_MAX_AGE,
    Reading,
    average_reading,
    json_pointer,
    last_csv_row,
    latest_reading,
    parse_number,
    parse_time,
)

__all__ = [
    "Average",
    "CombinedStation",
    "CsvFileStation",
    "HttpJsonStation",
    "ModuleStation",
    "Station",
    "SunStation",
]

log = logging.getLogger(__name__)

#: Readings of all stations: station name → sensor name → reading.
StationReadings = Mapping[str, Mapping[str, Reading]]


class Station(Object, ABC):
    """A source of readings; subclasses implement :meth:`read`."""

    @abstractmethod
    async def read(self, others: StationReadings) -> dict[str, Reading]:
        """The latest readings by sensor name; ``others`` holds the other stations' latest ones."""


def _check_fields(fields: Mapping[str, str], key: str) -> dict[str, str]:
    if not fields:
        raise ConfigError("name at least one sensor", key=key)
    return dict(fields)


#: Clock seconds between two looks at a station module that is still starting.
_STARTING_LOOK = 0.5


class ModuleStation(Station):
    """Another module offering IWeather, e.g. a SimWeatherStation or a hardware station driver.

    Args:
        module: Name of the module; one call of its ``get_current_weather()`` per reading.
    """

    def __init__(self, *, module: str) -> None:
        super().__init__()
        if not module:
            raise ConfigError("name the weather station module", key="module")
        self.module = module

    async def read(self, others: StationReadings) -> dict[str, Reading]:
        # Just online, it may still be starting: wait for it (bounded by the module's station_timeout).
        while await (await self.proxy(self.module, IModule)).get_state() is ModuleState.STARTING:
            await self.clock.sleep(_STARTING_LOOK)
        station = await self.proxy(self.module, IWeather)
        report = await station.get_current_weather()
        when = report.time.timestamp()
        return {name: Reading(when, value) for name, value in report.sensors.items()}


class HttpJsonStation(Station):
    """A station publishing a JSON document over HTTP (GET).

    Args:
        url: Where to get the document.
        fields: Sensor name → JSON pointer of its value, e.g. ``{temperature: /current/temp_c}``;
            numbers, numeric strings, booleans (rain) and null (no value) are understood.
        time_field: JSON pointer of the measurement time (Unix seconds or ISO 8601); without it,
            the time of the request.
        timeout: Wall seconds a request may take.
        headers: Extra request headers (e.g. an API key).
    """

    def __init__(
        self,
        *,
        url: str,
        fields: dict[str, str],
        time_field: str | None = None,
        timeout: float = 10.0,
        headers: dict[str, str] | None = None,
    ) -> None:
        super().__init__()
        if not url.startswith(("http://", "https://")):
            raise ConfigError(f"must be an http:// or https:// URL, got {url!r}", key="url")
        self.url = url
        self.fields = _check_fields(fields, "fields")
        for sensor, pointer in self.fields.items():
            if not pointer.startswith("/"):
                raise ConfigError(
                    f"JSON pointer must start with '/', got {pointer!r}", key=f"fields.{sensor}"
                )
        self.time_field = time_field
        if not timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {timeout}", key="timeout")
        self.timeout = float(timeout)
        self.headers = dict(headers or {})

    async def read(self, others: StationReadings) -> dict[str, Reading]:
        import aiohttp  # imported on use: only stations on the network need it

        async with (
            aiohttp.ClientSession(timeout=aiohttp.ClientTimeout(total=self.timeout)) as session,
            session.get(self.url, headers=self.headers) as response,
        ):
            if response.status != 200:
                raise InvalidArgumentError(f"{self.url} answered HTTP {response.status}")
            document = await response.json(content_type=None)
        when = parse_time(json_pointer(document, self.time_field)) if self.time_field else self.clock.time()
        return _parse_fields(lambda key: json_pointer(document, key), self.fields, when, self.url)


class CsvFileStation(Station):
    """A CSV log with a header line that a station program appends to; the last row counts.

    Args:
        path: VFS path of the file (mount its directory as a LocalFile root).
        columns: Sensor name → column, e.g. ``{temperature: T_out, rain: rain_flag}``.
        time_column: Column with the measurement time (Unix seconds or ISO 8601); without it, the
            time the file was read.
    """

    def __init__(self, *, path: str, columns: dict[str, str], time_column: str | None = None) -> None:
        super().__init__()
        if not path.startswith("/"):
            raise ConfigError(f"must be an absolute VFS path like /weather/log.csv, got {path!r}", key="path")
        self.path = path
        self.columns = _check_fields(columns, "columns")
        self.time_column = time_column

    async def read(self, others: StationReadings) -> dict[str, Reading]:
        row = last_csv_row(await self.vfs.read_bytes(self.path))
        if self.time_column is not None and self.time_column not in row:
            raise InvalidArgumentError(f"{self.path}: no column {self.time_column!r}")
        when = parse_time(row[self.time_column]) if self.time_column else self.clock.time()
        return _parse_fields(lambda column: row[column], self.columns, when, self.path)


def _parse_fields(
    get: Callable[[str], Any], fields: Mapping[str, str], when: float, where: str
) -> dict[str, Reading]:
    """Readings of every field; one unreadable field has no value, the others still count."""
    readings = {}
    for sensor, key in fields.items():
        try:
            value = parse_number(get(key))
        except (InvalidArgumentError, KeyError) as exc:
            log.warning("%s: %s: %s", where, sensor, exc)
            value = None
        readings[sensor] = Reading(when, value)
    return readings


class SunStation(Station):
    """The Sun's altitude at the observatory's site (``sun_altitude``, degrees), computed from the clock."""

    async def read(self, others: StationReadings) -> dict[str, Reading]:
        if self.site is None:
            raise ConfigError("the Sun's altitude needs the observatory's site", key="site")
        now = self.clock.time()
        return {"sun_altitude": Reading(now, sun_altitude(self.site.latitude, self.site.longitude, now))}


class CombinedStation(Station):
    """Combines, sensor by sensor, the readings of other stations of the same Weather module.

    Args:
        stations: Names of the stations to combine (not combined ones themselves).
    """

    def __init__(self, *, stations: list[str]) -> None:
        super().__init__()
        if not stations:
            raise ConfigError("name at least one station to combine", key="stations")
        self.stations = list(stations)

    async def read(self, others: StationReadings) -> dict[str, Reading]:
        sensors = sorted({sensor for name in self.stations for sensor in others.get(name, {})})
        combined = {}
        for sensor in sensors:
            reading = self.combine([others.get(name, {}).get(sensor) for name in self.stations])
            if reading is not None:
                combined[sensor] = reading
        return combined

    @abstractmethod
    def combine(self, readings: list[Reading | None]) -> Reading | None:
        """One reading from the stations' readings of one sensor; None if there is none."""


class Current(CombinedStation):
    """The newest reading of each sensor among ``stations``."""

    def combine(self, readings: list[Reading | None]) -> Reading | None:
        return latest_reading(readings)


class Average(CombinedStation):
    """The mean of each sensor over ``stations``, of readings at most ``max_age`` seconds old.

    Args:
        stations: Names of the stations to average.
        max_age: Older readings are left out of the mean.
    """

    def __init__(self, *, stations: list[str], max_age: float = DEFAULT_MAX_AGE) -> None:
        super().__init__(stations=stations)
        if not max_age > 0:
            raise ConfigError(f"must be > 0 seconds, got {max_age}", key="max_age")
        self.max_age = float(max_age)

    def combine(self, readings: list[Reading | None]) -> Reading | None:
        return average_reading(readings, self.clock.time(), self.max_age)
