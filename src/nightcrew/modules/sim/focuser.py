"""A simulated focuser whose best focus drifts with the temperature (tubes shrink as nights cool)."""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.interfaces import ITemperatures
from nightcrew.interfaces.quantities import Temperature
from nightcrew.modules.focuser import BaseFocuser
from nightcrew.modules.sim.interfaces import ISimFocuserTruth

__all__ = ["SimFocuser"]

log = logging.getLogger(__name__)


class SimFocuser(BaseFocuser, ISimFocuserTruth, ITemperatures):
    """A focuser in the simulated observatory.

    Best focus = ``best_focus`` + ``temperature_coefficient`` * (T - ``reference_temperature``),
    where T is the ambient temperature of ``weather_station`` (via ITemperatures), else ``temperature``.

    Args:
        speed: mm per second.
        best_focus: Best focus in mm at the reference temperature.
        temperature_coefficient: mm per °C.
        reference_temperature: °C.
        temperature: Ambient °C when no weather station is named (or it does not answer).
        weather_station: Module offering ITemperatures with an ``ambient`` reading.
        **kwargs: Focuser options (``min_focus``, ``max_focus``, ``focus``) and module options.
    """

    def __init__(
        self,
        *,
        speed: float = 0.5,
        best_focus: float = 25.0,
        temperature_coefficient: float = -0.05,
        reference_temperature: Temperature = 10.0,
        temperature: Temperature = 10.0,
        weather_station: str | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not speed > 0:
            raise ConfigError(f"must be > 0 mm/s, got {speed}", key="speed")
        self._speed = float(speed)
        self._best_focus = float(best_focus)
        self._coefficient = float(temperature_coefficient)
        self._reference = float(reference_temperature)
        self._temperature = float(temperature)
        self._weather_station = weather_station
        self._position = self._focus

    async def _ambient(self) -> float:
        if self._weather_station:
            try:
                station = await self.proxy(self._weather_station, ITemperatures)
                ambient = (await station.get_temperatures()).get("ambient")
                if ambient is not None:
                    return ambient
            except NightcrewError as exc:
                log.warning("%s: no temperature from %s: %s", self.name, self._weather_station, exc)
        return self._temperature

    async def get_best_focus(self) -> float:
        return self._best_focus + self._coefficient * (await self._ambient() - self._reference)

    async def get_temperatures(self) -> dict[str, float]:
        return {"ambient": await self._ambient()}

    def _hw_travel_time(self, position: float) -> float:
        return abs(position - self._position) / self._speed

    async def _hw_move_focus(self, position: float) -> None:
        start, started = self._position, self.clock.time()
        duration = self._hw_travel_time(position)
        try:
            await self.clock.sleep(duration)
        except asyncio.CancelledError:
            f = min(1.0, (self.clock.time() - started) / duration) if duration > 0 else 1.0
            self._position = start + f * (position - start)
            raise
        self._position = position

    async def _hw_stop(self) -> None:
        """Nothing to do: the motion task already stopped where it was."""
