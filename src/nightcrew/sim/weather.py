"""Simulated weather over time: scripted scenarios (a list of timed states) or seeded random ones.

A scenario is a list of states at times in seconds since it started. Between two states, smooth
quantities (temperature, humidity, pressure, wind, clouds) are interpolated linearly; rain switches
at the state's time. A state names only what changes; the rest carries over from the one before::

    - {at: 0, temperature: 8, humidity: 60, clouds: 0.1}
    - {at: 3600, humidity: 95, clouds: 0.9}
    - {at: 5400, rain: true}          # it rains from 1.5 h on
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["WeatherScenario", "WeatherState", "random_scenario"]


@dataclass(frozen=True)
class WeatherState:
    """The weather at one moment (units as in WeatherSensor; clouds: fraction of sky covered)."""

    temperature: float = 10.0
    humidity: float = 50.0
    pressure: float = 1013.0
    wind_speed: float = 10.0
    wind_direction: float = 270.0
    clouds: float = 0.0
    rain: bool = False

    def __post_init__(self) -> None:
        if not 0.0 <= self.humidity <= 100.0:
            raise ValueError(f"humidity must be within 0..100 %, got {self.humidity}")
        if not 0.0 <= self.clouds <= 1.0:
            raise ValueError(f"clouds must be within 0..1, got {self.clouds}")
        if self.wind_speed < 0:
            raise ValueError(f"wind_speed must be >= 0 km/h, got {self.wind_speed}")

    @property
    def dew_point(self) -> float:
        """Dew point in °C (Magnus formula)."""
        a, b = 17.62, 243.12
        gamma = math.log(max(self.humidity, 0.1) / 100.0) + a * self.temperature / (b + self.temperature)
        return b * gamma / (a - gamma)

    @property
    def sky_temperature(self) -> float:
        """What an IR cloud sensor sees: ~30 °C below ambient when clear, near ambient when overcast."""
        return self.temperature - 30.0 * (1.0 - self.clouds)

    def sensors(self) -> dict[str, float]:
        """Sensor name (a WeatherSensor value) → reading."""
        return {
            "temperature": self.temperature,
            "humidity": self.humidity,
            "pressure": self.pressure,
            "wind_speed": self.wind_speed,
            "wind_direction": self.wind_direction % 360.0,
            "rain": 1.0 if self.rain else 0.0,
            "sky_temperature": round(self.sky_temperature, 2),
            "dew_point": round(self.dew_point, 2),
        }


_FIELDS = tuple(f.name for f in dataclasses.fields(WeatherState))
_SMOOTH = tuple(name for name in _FIELDS if name != "rain")


class WeatherScenario:
    """States at times; :meth:`state_at` gives the weather at any time.

    Args:
        states: (seconds since start, state) pairs; times ascending, the first at 0.
    """

    def __init__(self, states: Sequence[tuple[float, WeatherState]]) -> None:
        if not states:
            raise ValueError("a scenario needs at least one state")
        times = [t for t, _ in states]
        if times[0] != 0 or any(b <= a for a, b in itertools.pairwise(times)):
            raise ValueError(f"state times must start at 0 and increase, got {times}")
        self._states = list(states)

    @classmethod
    def from_config(cls, entries: Sequence[Mapping[str, Any]]) -> WeatherScenario:
        """A scenario from a list of mappings with ``at`` (seconds) and the fields that change."""
        states: list[tuple[float, WeatherState]] = []
        current = WeatherState()
        for index, entry in enumerate(entries):
            unknown = sorted(set(entry) - {"at", *_FIELDS})
            if unknown:
                raise ValueError(f"entry {index}: unknown keys {unknown}; known: at, {', '.join(_FIELDS)}")
            if "at" not in entry:
                raise ValueError(f"entry {index}: missing 'at' (seconds since the scenario started)")
            changes: dict[str, Any] = {
                k: (bool(v) if k == "rain" else float(v)) for k, v in entry.items() if k != "at"
            }
            try:
                current = dataclasses.replace(current, **changes)
            except ValueError as exc:
                raise ValueError(f"entry {index}: {exc}") from exc
            states.append((float(entry["at"]), current))
        return cls(states)

    @property
    def duration(self) -> float:
        """Time of the last state; the weather stays as it is afterwards."""
        return self._states[-1][0]

    def state_at(self, seconds: float) -> WeatherState:
        """The weather ``seconds`` after the start."""
        if seconds <= 0:
            return self._states[0][1]
        for (t0, s0), (t1, s1) in itertools.pairwise(self._states):
            if t0 <= seconds < t1:
                f = (seconds - t0) / (t1 - t0)
                smooth = {
                    name: getattr(s0, name) + f * (getattr(s1, name) - getattr(s0, name)) for name in _SMOOTH
                }
                return WeatherState(**smooth, rain=s0.rain)
        return self._states[-1][1]


def random_scenario(seed: int, duration: float = 43200.0, step: float = 600.0) -> WeatherScenario:
    """A plausible night: slowly cooling, humidity and clouds wandering, rain only under thick clouds."""
    if not (duration > 0 and step > 0):
        raise ValueError(f"duration and step must be > 0, got {duration} and {step}")
    rng = np.random.default_rng(seed)
    count = math.ceil(duration / step) + 1
    temperature, humidity = float(rng.uniform(0, 20)), float(rng.uniform(30, 80))
    clouds, wind = float(rng.uniform(0, 0.5)), 10.0
    states: list[tuple[float, WeatherState]] = []
    for index in range(count):
        rain = clouds > 0.9 and humidity > 90 and bool(rng.random() < 0.5)
        states.append(
            (
                index * step,
                WeatherState(
                    temperature=round(temperature, 2),
                    humidity=round(humidity, 1),
                    wind_speed=round(wind, 1),
                    wind_direction=float(rng.uniform(0, 360)),
                    clouds=round(clouds, 3),
                    rain=rain,
                ),
            )
        )
        temperature += float(rng.normal(-0.2, 0.3))
        humidity = float(np.clip(humidity + rng.normal(0.5, 4.0), 5.0, 100.0))
        clouds = float(np.clip(clouds + rng.normal(0.0, 0.08), 0.0, 1.0))
        wind = float(np.clip(wind + rng.normal(0.0, 3.0), 0.0, 120.0))
    return WeatherScenario(states)
