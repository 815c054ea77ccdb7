"""Keeping the telescope in focus: whether a focus is due, and the auto-focus run under watch.

A failed focus run (e.g. a series whose widths form no clear V) leaves the focus as it was - the
focus module puts the focuser back - and the night goes on with it: observing slightly out of focus
beats not observing. The focus stays due, but is tried again only after ``retry_interval`` clock
seconds, so a sky that cannot be focused on (clouds, too few stars) costs one series per interval
instead of one before every task.

Before a series the telescope is pointed at a :class:`FocusField` and tracks it: the field left by
the flat-field pointing (alt/az, not tracking) drifts by 15"/s, which trails the stars of a 15 s
focus frame by ~225". The field is a direction, not a star field - high up whatever the time of
night and year, so the stars are many and sharp - turned into the (ra, dec) there when the series
starts.
"""

from __future__ import annotations

import asyncio
import logging
import math
from collections.abc import Awaitable, Callable
from dataclasses import dataclass

from nightcrew.astro import altaz_to_radec
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.interfaces import IAutoFocus
from nightcrew.object import Object
from nightcrew.robotic.mastermind._decide import SunLimits
from nightcrew.robotic.mastermind._observatory import ObservatoryControl
from nightcrew.robotic.mastermind._supervision import run_watched
from nightcrew.robotic.mastermind._tasks import focus_due
from nightcrew.site import Site

__all__ = ["FocusField", "FocusKeeper", "focus_field"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class FocusField:
    """Where to focus: the sky at (``altitude``, ``azimuth``) degrees when the series starts."""

    altitude: float
    azimuth: float

    def radec(self, site: Site, unix_time: float) -> tuple[float, float]:
        """The ICRS (ra, dec) of the field at ``site`` and ``unix_time``: the position to track."""
        return altaz_to_radec(self.altitude, self.azimuth, site.latitude, site.longitude, unix_time)


def focus_field(altitude: float | None, azimuth: float | None, site: Site) -> FocusField | None:
    """The mastermind's ``focus_altitude`` and ``focus_azimuth`` as a field (None: no altitude given).

    ``azimuth`` None means the meridian on the equator's side (south of a northern site), where the
    field stays high longest.

    Raises:
        ConfigError: An altitude outside (0, 90] or an azimuth outside [0, 360), naming the key.
    """
    if altitude is None:
        return None
    if not (math.isfinite(altitude) and 0.0 < altitude <= 90.0):
        raise ConfigError(f"must be within (0, 90] degrees, got {altitude}", key="focus_altitude")
    if azimuth is None:
        azimuth = 180.0 if site.latitude >= 0.0 else 0.0
    if not (math.isfinite(azimuth) and 0.0 <= azimuth < 360.0):
        raise ConfigError(f"must be within [0, 360) degrees, got {azimuth}", key="focus_azimuth")
    return FocusField(float(altitude), float(azimuth))


class FocusKeeper:
    """Remembers the last focus (and its temperature) and runs the auto-focus when asked.

    Args:
        host: The module whose comm and clock are used (and whose name prefixes log lines).
        observatory: Where the temperature comes from.
        autofocus: Module offering IAutoFocus (or a local object).
        max_sun_altitude: Highest Sun altitude for focusing, degrees (stars must show).
        refocus_change: Refocus after this temperature change, °C.
        refocus_interval: Refocus after this many clock seconds; None: not for time alone.
        arguments: (count, step, exposure_time) of ``auto_focus``.
        retry_interval: Clock seconds after a failed focus run before the next attempt.
        field: Where to point (and track) before a series; None: where the telescope points.
    """

    def __init__(
        self,
        host: Object,
        observatory: ObservatoryControl,
        autofocus: str | IAutoFocus,
        *,
        max_sun_altitude: float,
        refocus_change: float,
        refocus_interval: float | None = None,
        arguments: tuple[int, float, float],
        retry_interval: float = 1800.0,
        field: FocusField | None = None,
    ) -> None:
        self._host, self._observatory, self._autofocus = host, observatory, autofocus
        self._field = field
        self.limits = SunLimits(high=float(max_sun_altitude))
        self._refocus_change, self._arguments = refocus_change, arguments
        self._refocus_interval = refocus_interval
        self._focused_at = 0.0  # clock time of the last focus
        self._retry_interval = float(retry_interval)
        self._focused = False
        self._temperature: float | None = None
        self._retry_at: float | None = None  # clock time before which a failed focus is not retried

    async def focus_below(self) -> float | None:
        """The highest Sun altitude to focus at if a focus is due, else None."""
        if self._retry_at is not None and self._host.clock.time() < self._retry_at:
            return None
        temperature = await self._observatory.temperature() if self._focused else None
        cause = focus_due(
            focused=self._focused,
            last_temperature=self._temperature,
            temperature=temperature,
            threshold=self._refocus_change,
            since_focus=self._host.clock.time() - self._focused_at,
            interval=self._refocus_interval,
        )
        if cause is not None and self._focused:
            log.debug("%s: focus due: %s", self._host.context_name, cause)
        return self.limits.high if cause is not None else None

    async def focus(
        self,
        check: Callable[[], Awaitable[str | None]],
        *,
        wake: asyncio.Event,
        poll_interval: float,
        abort_timeout: float,
    ) -> None:
        """Run the auto-focus, aborted when ``check`` gives a cause (then it stays due)."""
        name = self._host.context_name
        temperature = await self._observatory.temperature()
        log.info("%s: focusing (temperature %s, last focus at %s)", name, temperature, self._temperature)
        autofocus = await self._host.proxy(self._autofocus, IAutoFocus)
        try:
            cause = await run_watched(
                self._tracked_series(autofocus),
                check,
                wake=wake,
                clock=self._host.clock,
                poll_interval=poll_interval,
                abort_timeout=abort_timeout,
                on_abort=autofocus.abort,
            )
        except NightcrewError as exc:
            self._retry_at = self._host.clock.time() + self._retry_interval
            log.warning(
                "%s: focusing failed (%s); going on with the focus as it is, next try in %.0f s",
                name,
                exc,
                self._retry_interval,
            )
            return
        if cause is not None:
            log.warning("%s: focusing aborted: %s", name, cause)
            return
        self._focused, self._temperature, self._retry_at = True, temperature, None
        self._focused_at = self._host.clock.time()

    def field_radec(self) -> tuple[float, float] | None:
        """The focus field's (ra, dec) now; None without a field (focus wherever it points)."""
        if self._field is None:
            return None
        return self._field.radec(self._observatory.site, self._host.clock.time())

    async def _tracked_series(self, autofocus: IAutoFocus) -> tuple[float, float]:
        field = self._field
        if field is not None:
            ra, dec = field.radec(self._observatory.site, self._host.clock.time())
            log.info(
                "%s: tracking the focus field at alt %.0f°, az %.0f° (ra %.3f°, dec %.3f°)",
                self._host.context_name,
                field.altitude,
                field.azimuth,
                ra,
                dec,
            )
            await self._observatory.track(ra, dec)
        return await autofocus.auto_focus(*self._arguments)
