"""Pointing for twilight flats: opposite the Sun at 80° altitude, dithered a little every time."""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.astro import sun_altaz
from nightcrew.errors import ConfigError
from nightcrew.flatfield import antisolar_position
from nightcrew.interfaces import IPointingAltAz, IRunnable
from nightcrew.modules.module import Module

__all__ = ["FlatFieldPointing"]

log = logging.getLogger(__name__)


class FlatFieldPointing(Module, IRunnable):
    """Each :meth:`run` moves the telescope to the flat-field position with the next dither.

    Args:
        telescope: Module offering IPointingAltAz.
        altitude: Altitude in degrees, 80 by default (the most uniform twilight sky).
        dither: Step in arcseconds between successive positions (0: none), so that stars never
            fall on the same pixels twice.
        **kwargs: Module options; ``site`` is required (the Sun's azimuth needs it).
    """

    def __init__(
        self, *, telescope: str | IPointingAltAz, altitude: float = 80.0, dither: float = 120.0, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        if self.site is None:
            raise ConfigError("pointing opposite the Sun needs the observatory site", key="site")
        if not 0.0 < altitude < 90.0:
            raise ConfigError(f"must be within 0..90 degrees, got {altitude}", key="altitude")
        if not 0.0 <= dither <= 3600.0:
            raise ConfigError(f"must be within 0..3600 arcseconds, got {dither}", key="dither")
        self._telescope, self._altitude, self._dither = telescope, float(altitude), float(dither)
        self._index = 0

    async def run(self) -> None:
        assert self.site is not None
        _, sun_azimuth = sun_altaz(self.site, self.clock.time())
        alt, az = antisolar_position(
            sun_azimuth, altitude=self._altitude, index=self._index, dither_arcsec=self._dither
        )
        self._index += 1
        log.info("%s: pointing to alt=%.3f°, az=%.3f° (Sun at az %.2f°)", self.name, alt, az, sun_azimuth)
        await (await self.proxy(self._telescope, IPointingAltAz)).move_altaz(alt, az)

    async def abort(self) -> None:
        """Nothing to stop: a slew is the telescope's to abort."""
