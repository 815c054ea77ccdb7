"""A simulated weather station playing a scripted or seeded random scenario."""

from __future__ import annotations

import math
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.interfaces import ModuleState, WeatherSensor
from nightcrew.modules.sim.interfaces import ISimWeatherTruth
from nightcrew.modules.weatherstation import BaseWeatherStation
from nightcrew.sim.weather import WeatherScenario, WeatherState, random_scenario

__all__ = ["SimWeatherStation"]


class SimWeatherStation(BaseWeatherStation, ISimWeatherTruth):
    """A weather station in the simulated observatory; time 0 of the scenario is when it opens.

    Args:
        scenario: Timed states (see :mod:`nightcrew.sim.weather`); without one, a random night.
        seed: Seed of the random night.
        duration: Seconds the random night lasts (the weather stays as it is afterwards).
        **kwargs: Station options (``interval``) and module options.
    """

    def __init__(
        self,
        *,
        scenario: list[dict[str, Any]] | None = None,
        seed: int = 0,
        duration: float = 43200.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        try:
            self._scenario = (
                WeatherScenario.from_config(scenario)
                if scenario
                else random_scenario(seed, duration=duration)
            )
        except (ValueError, TypeError) as exc:
            raise ConfigError(str(exc), key="scenario" if scenario else "duration") from exc
        self._started = math.nan

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        self._started = self.clock.time()
        await super().open()

    def _state_now(self) -> WeatherState:
        started = self._started if math.isfinite(self._started) else self.clock.time()
        return self._scenario.state_at(self.clock.time() - started)

    async def _hw_read_sensors(self) -> dict[WeatherSensor, float | None]:
        return {WeatherSensor(name): value for name, value in self._state_now().sensors().items()}

    async def get_cloud_cover(self) -> float:
        return self._state_now().clouds
