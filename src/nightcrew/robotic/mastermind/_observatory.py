"""The observatory as the mastermind senses and drives it: weather, roof, telescope, Sun, temperature.

Everything it cannot find out counts against opening: a weather module that does not answer is bad
weather, a roof that does not answer is UNKNOWN (not open), a telescope that does not answer is not
ready. Without a weather module only weather events count, and until the first GoodWeatherEvent
the weather is unknown, i.e. bad.
"""

from __future__ import annotations

import asyncio
import logging
from datetime import datetime

from nightcrew.astro import sun_altitude
from nightcrew.errors import NightcrewError
from nightcrew.focus.sources import TemperatureSource
from nightcrew.interfaces import IRoof, ITelescope, IWeather, MotionStatus
from nightcrew.object import Object
from nightcrew.robotic.mastermind._decide import Conditions, RoofState
from nightcrew.robotic.mastermind._supervision import all_done
from nightcrew.robotic.temperature_source import read_temperature
from nightcrew.site import Site

__all__ = ["ObservatoryControl"]

log = logging.getLogger(__name__)

#: Telescope states in which it can point.
_POINTING = frozenset({MotionStatus.IDLE, MotionStatus.SLEWING, MotionStatus.TRACKING, MotionStatus.MOVING})
#: Clock seconds ahead at which the Sun is looked at again to tell dusk from dawn.
_SUN_TREND_S = 600.0


class ObservatoryControl:
    """Reads :class:`Conditions` and opens up or closes down, through ``host``'s proxies.

    Args:
        host: The module whose comm and clock are used (and whose name prefixes log lines).
        site: Where the observatory is (for the Sun).
        roof, telescope, weather: Module names (or local objects); weather may be None.
        temperature: Where the temperature for refocusing is read; None: the weather's.
    """

    def __init__(
        self,
        host: Object,
        site: Site,
        *,
        roof: str | IRoof,
        telescope: str | ITelescope,
        weather: str | IWeather | None,
        temperature: TemperatureSource | None = None,
    ) -> None:
        self._host, self._site = host, site
        self._roof, self._telescope, self._weather = roof, telescope, weather
        self._temperature = temperature
        self._temperature_problem: str | None = None  # the last cause of no temperature, logged once
        self._weather_heard: bool | None = None  # the last weather event's verdict
        self._good_from: datetime | None = None  # a GoodWeatherEvent's eta

    @property
    def site(self) -> Site:
        return self._site

    @property
    def _name(self) -> str:
        return self._host.context_name

    # --- weather events ------------------------------------------------------------------------

    def heard_bad_weather(self) -> None:
        """A BadWeatherEvent: bad until a GoodWeatherEvent, whatever a poll says meanwhile."""
        self._weather_heard = False

    def heard_good_weather(self, eta: datetime | None) -> None:
        """A GoodWeatherEvent: good from ``eta`` on (now if None)."""
        self._weather_heard, self._good_from = True, eta

    # --- sensing -------------------------------------------------------------------------------

    async def observe(self) -> Conditions:
        """The world now."""
        clock = self._host.clock
        now, unix = clock.now(), clock.time()
        sun_now = sun_altitude(self._site.latitude, self._site.longitude, unix)
        sun_later = sun_altitude(self._site.latitude, self._site.longitude, unix + _SUN_TREND_S)
        weather_good, roof, telescope_ready = await asyncio.gather(
            self._weather_good(), self._roof_state(), self._telescope_ready()
        )
        if self._good_from is not None and now < self._good_from:
            weather_good = False
        return Conditions(now, sun_now, sun_later > sun_now, weather_good, roof, telescope_ready)

    async def temperature(self) -> float | None:
        """The temperature for focusing (°C): the configured source's, else the weather's; None
        (logged with the cause) when there is none."""
        try:
            if self._temperature is not None:
                value: float | None = await read_temperature(self._host, self._temperature)
            elif self._weather is not None:
                report = await (await self._host.proxy(self._weather, IWeather)).get_current_weather()
                value = report.sensors.get("temperature")
            else:
                return None
        except NightcrewError as exc:
            if str(exc) != self._temperature_problem:  # once per cause, not at every look
                log.warning("%s: no temperature for refocusing: %s", self._name, exc)
            self._temperature_problem = str(exc)
            return None
        self._temperature_problem = None
        return value

    async def pointing(self) -> tuple[float, float] | None:
        """Where the telescope points now, ICRS (ra, dec); None (logged) when it cannot tell."""
        try:
            return await (await self._host.proxy(self._telescope, ITelescope)).get_radec()
        except NightcrewError as exc:
            log.warning("%s: telescope position unknown: %s", self._name, exc)
            return None

    async def _weather_good(self) -> bool:
        if self._weather is None or self._weather_heard is False:
            return self._weather_heard is True
        try:
            return await (await self._host.proxy(self._weather, IWeather)).is_weather_good()
        except NightcrewError as exc:
            log.warning("%s: no weather verdict (%s): taking it as bad", self._name, exc)
            return False

    async def _roof_state(self) -> RoofState:
        try:
            return RoofState.of_motion(await (await self._host.proxy(self._roof, IRoof)).get_motion_status())
        except NightcrewError as exc:
            log.warning("%s: roof status unknown: %s", self._name, exc)
            return RoofState.UNKNOWN

    async def _telescope_ready(self) -> bool:
        try:
            status = await (await self._host.proxy(self._telescope, ITelescope)).get_motion_status()
        except NightcrewError as exc:
            log.warning("%s: telescope status unknown: %s", self._name, exc)
            return False
        return status in _POINTING

    # --- acting --------------------------------------------------------------------------------

    async def open_up(self, conditions: Conditions, point_at: tuple[float, float] | None = None) -> bool:
        """Open the roof and initialise the telescope at the same time; False (logged) if either failed.

        ``point_at``: ICRS (ra, dec) to slew to while the roof opens (where the task or the focus
        will point first), so that the slew does not wait for the roof. A slew that fails is
        only logged: the task's own slew tries again and reports it.
        """

        async def open_roof() -> None:
            await (await self._host.proxy(self._roof, IRoof)).open_roof()

        async def init_telescope() -> None:
            if not conditions.telescope_ready:
                await (await self._host.proxy(self._telescope, ITelescope)).init()
            if point_at is not None:
                try:
                    await self.track(*point_at)
                except NightcrewError as exc:
                    log.warning("%s: could not point while the roof opens: %s", self._name, exc)

        return await all_done(
            {"open the roof": open_roof(), "initialise the telescope": init_telescope()}, who=self._name
        )

    async def track(self, ra: float, dec: float) -> None:
        """Slew to ICRS (ra, dec) and track it; a slew cancelled on the way is stopped.

        Raises:
            NightcrewError: The telescope refused or failed the move.
        """
        telescope = await self._host.proxy(self._telescope, ITelescope)
        try:
            await telescope.move_radec(ra, dec)
        except asyncio.CancelledError:
            # A slew left running would refuse the next task's move (the telescope is busy).
            try:
                await telescope.stop_motion()
            except NightcrewError as exc:
                log.warning("%s: could not stop the slew: %s", self._name, exc)
            raise

    async def close_and_park(self, reason: str) -> bool:
        """Close the roof and park the telescope at the same time; False (logged) if either failed."""
        log.info("%s: closing the roof and parking the telescope: %s", self._name, reason)

        async def close_roof() -> None:
            await (await self._host.proxy(self._roof, IRoof)).close_roof()

        async def park() -> None:
            await (await self._host.proxy(self._telescope, ITelescope)).park()

        return await all_done({"close the roof": close_roof(), "park the telescope": park()}, who=self._name)
