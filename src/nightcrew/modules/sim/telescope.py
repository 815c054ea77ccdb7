"""A simulated telescope: slews take time, pointing is imperfect, tracking drifts."""

from __future__ import annotations

import asyncio
import logging
from typing import Any

import numpy as np

from nightcrew.astro import angular_separation
from nightcrew.errors import ConfigError
from nightcrew.interfaces.quantities import Altitude, Azimuth
from nightcrew.modules.sim.interfaces import ISimTelescopeTruth
from nightcrew.modules.telescope import BaseTelescope
from nightcrew.sim.mount import MountErrorModel, SlewError, apply_sky_offset, slew_time

__all__ = ["SimTelescope"]

log = logging.getLogger(__name__)


class SimTelescope(BaseTelescope, ISimTelescopeTruth):
    """A telescope mount in the simulated observatory.

    The mount reports the position it was sent to; where it *really* points (for the simulated
    camera) adds a random miss per slew, a linear drift while tracking and a periodic error.

    Args:
        slew_rate: Degrees per second along the great circle.
        settle_time: Seconds to settle after a slew.
        init_time: Seconds to initialise (unpark).
        park_alt: Altitude of the park position, degrees.
        park_az: Azimuth of the park position, degrees.
        pointing_error: RMS miss per axis after a slew, arcminutes.
        drift_rate: Tracking drift, arcseconds per minute.
        periodic_amplitude: RA periodic error amplitude, arcseconds.
        periodic_period: Worm period, seconds.
        seed: Seed of the random pointing errors (same seed, same night).
        **kwargs: Telescope options (``min_altitude``) and module options.
    """

    def __init__(
        self,
        *,
        slew_rate: float = 4.0,
        settle_time: float = 3.0,
        init_time: float = 10.0,
        park_alt: Altitude = 85.0,
        park_az: Azimuth = 0.0,
        pointing_error: float = 1.0,
        drift_rate: float = 1.0,
        periodic_amplitude: float = 5.0,
        periodic_period: float = 480.0,
        seed: int = 0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not slew_rate > 0:
            raise ConfigError(f"must be > 0 deg/s, got {slew_rate}", key="slew_rate")
        if settle_time < 0 or init_time < 0:
            raise ConfigError("settle_time and init_time must be >= 0 seconds", key="settle_time")
        try:
            self._errors = MountErrorModel(pointing_error, drift_rate, periodic_amplitude, periodic_period)
        except ValueError as exc:
            raise ConfigError(str(exc), key=str(exc).split()[0]) from exc
        self._slew_rate, self._settle_time, self._init_time = (
            float(slew_rate),
            float(settle_time),
            float(init_time),
        )
        self._park = (float(park_alt), float(park_az) % 360.0)
        self._rng = np.random.default_rng(seed)
        # Pointing as the mount reports it: fixed (ra, dec) while tracking, else fixed (alt, az).
        self._tracking: tuple[float, float] | None = None
        self._fixed_altaz = self._park
        self._slew_error = SlewError(0.0, 0.0, 0.0)
        self._settled_at = 0.0
        # Tracking drift accumulates from the moment a new RA/Dec target settled, offsets included.
        self._drifting = False

    # --- where it points -----------------------------------------------------------------------

    def _reported_altaz(self) -> tuple[float, float]:
        return self._altaz_of(*self._tracking) if self._tracking is not None else self._fixed_altaz

    async def _hw_get_radec(self) -> tuple[float, float]:
        if self._tracking is not None:
            return self._tracking
        return self._radec_of(*self._fixed_altaz)

    async def _hw_get_altaz(self) -> tuple[float, float]:
        return self._reported_altaz()

    async def get_true_radec(self) -> tuple[float, float]:
        ra, dec = await self._hw_get_radec()
        now = self.clock.time()
        tracked = now - self._settled_at if self._drifting else 0.0
        east, north = self._errors.offset(self._slew_error, tracked, now)
        return apply_sky_offset(ra, dec, east, north)

    # --- motions -------------------------------------------------------------------------------

    def _hw_slew_time(self, alt: float, az: float) -> float:
        start_alt, start_az = self._reported_altaz()
        return slew_time(angular_separation(start_az, start_alt, az, alt), self._slew_rate, self._settle_time)

    async def _travel(self, alt: float, az: float, *, new_target: bool = True) -> None:
        """Take as long as the slew from here to (alt, az); stopped midway, stay in between.

        A slew to a new target draws a new pointing miss and restarts the drift; an offset
        (``new_target=False``) keeps both, as a real mount's pointing model and tracking do.
        """
        start_alt, start_az = self._reported_altaz()
        duration = self._hw_slew_time(alt, az)
        started = self.clock.time()
        self._fixed_altaz = (start_alt, start_az)  # report where the move starts, not a stale position
        self._tracking = None
        self._drifting = self._drifting and not new_target
        try:
            await self.clock.sleep(duration)
        except asyncio.CancelledError:
            f = min(1.0, (self.clock.time() - started) / duration) if duration > 0 else 1.0
            daz = (az - start_az + 180.0) % 360.0 - 180.0
            self._fixed_altaz = (start_alt + f * (alt - start_alt), (start_az + f * daz) % 360.0)
            raise
        self._fixed_altaz = (alt, az)
        if new_target:
            self._slew_error = self._errors.draw_slew_error(self._rng)
            self._settled_at = self.clock.time()

    async def _hw_init(self) -> None:
        await self.clock.sleep(self._init_time)

    async def _hw_park(self) -> None:
        await self._travel(*self._park)

    async def _hw_move_radec(self, ra: float, dec: float) -> None:
        # Aim where the target will be when we arrive (close enough: where it is now), then track.
        await self._travel(*self._altaz_of(ra, dec))
        self._tracking = (ra, dec)
        self._drifting = True

    async def _hw_move_altaz(self, alt: float, az: float) -> None:
        await self._travel(alt, az)

    async def _hw_offset_radec(self, ra: float, dec: float) -> None:
        await self._travel(*self._altaz_of(ra, dec), new_target=False)
        self._tracking = (ra, dec)

    async def _hw_offset_altaz(self, alt: float, az: float) -> None:
        await self._travel(alt, az, new_target=False)

    async def _hw_stop(self) -> None:
        if self._tracking is not None:
            self._fixed_altaz = self._altaz_of(*self._tracking)
            self._tracking = None
        self._drifting = False

    async def _hw_get_temperatures(self) -> dict[str, float]:
        return {}
