"""A simulated telescope: slews take time, pointing is imperfect, tracking drifts.

With ``gem`` set it is a German-equatorial mount: it slews to the side of the pier where the
counterweight hangs down (ASCOM's DestinationSideOfPier), keeps that side while it tracks, times
slews by its two axes (so a flip, a slew to the same target from the other side, goes through the
pole and takes its time), refuses targets beyond its hour-angle limits, and records a pier
collision (logged at ERROR) when tracking carries it past a limit.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Mapping
from typing import Any

import numpy as np

from nightcrew.astro import angular_separation
from nightcrew.astro.pier import (
    SIDEREAL_RATE,
    GemLimits,
    destination_side,
    hour_angle,
    limit_edge,
    limit_violation,
    mechanical_axes,
)
from nightcrew.astro.pointing import PointingModelError
from nightcrew.errors import ConfigError, MoveError
from nightcrew.interfaces import PierSide
from nightcrew.interfaces.quantities import Altitude, Azimuth
from nightcrew.modules.sim.interfaces import ISimTelescopeTruth
from nightcrew.modules.telescope import BaseTelescope
from nightcrew.sim.mount import (
    MountErrorModel,
    PierCollision,
    SlewError,
    apply_sky_offset,
    axes_slew_time,
    pointing_terms_model,
    slew_time,
)

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
        gem: German-equatorial mode with these limits (keys of :class:`GemLimits`: ``east``,
            ``west`` hour angles and ``counterweight_up``, degrees); None: a mount without sides.
        pointing_terms: Pointing errors as TPoint terms in arcsec (``{IH: 600, MA: -300}``; see
            :mod:`nightcrew.astro.pointing`): the truth a pointing model fitted to this mount should
            find. None: no systematic errors.
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
        gem: Mapping[str, float] | None = None,
        pointing_terms: Mapping[str, float] | None = None,
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
        self._gem = _gem_limits(gem)
        try:
            self._terms = (
                None
                if pointing_terms is None
                else pointing_terms_model(self.name, self.observatory.latitude, dict(pointing_terms))
            )
        except (PointingModelError, TypeError, ValueError) as exc:
            raise ConfigError(str(exc), key="pointing_terms") from exc
        self._side: PierSide | None = None  # None: where the park position puts it
        self._limit_at: float | None = None  # clock time tracking passes a limit (GEM only)
        self._collisions: list[PierCollision] = []
        self._rng = np.random.default_rng(seed)
        # Pointing as the mount reports it: fixed (ra, dec) while tracking, else fixed (alt, az).
        self._tracking: tuple[float, float] | None = None
        self._fixed_altaz = self._park
        self._slew_error = SlewError(0.0, 0.0, 0.0)
        self._settled_at = 0.0
        # Tracking drift accumulates from the moment a new RA/Dec target settled, offsets included.
        self._drifting = False
        # Offset rates (arcsec/s of RA and Dec) added to sidereal tracking since a clock time.
        self._rates, self._rates_since = (0.0, 0.0), 0.0
        self._followed_target: dict[str, Any] | None = None  # what move_ephemeris was given last

    # --- where it points -----------------------------------------------------------------------

    def _tracked(self) -> tuple[float, float] | None:
        """The (ra, dec) tracked now: the target moved along the offset rates."""
        if self._tracking is None:
            return None
        seconds = self.clock.time() - self._rates_since
        ra, dec = self._tracking
        ra_rate, dec_rate = self._rates
        return (ra + ra_rate * seconds / 3600.0) % 360.0, max(
            -90.0, min(90.0, dec + dec_rate * seconds / 3600.0)
        )

    def _reported_altaz(self) -> tuple[float, float]:
        tracked = self._tracked()
        return self._altaz_of(*tracked) if tracked is not None else self._fixed_altaz

    async def _hw_get_radec(self) -> tuple[float, float]:
        self._note_collision()
        tracked = self._tracked()
        if tracked is not None:
            return tracked
        return self._radec_of(*self._fixed_altaz)

    async def _hw_set_tracking_rates(self, ra_rate: float, dec_rate: float) -> bool:
        self._tracking = self._tracked()  # the rates so far brought it here
        self._rates, self._rates_since = (ra_rate, dec_rate), self.clock.time()
        return True

    async def _hw_get_altaz(self) -> tuple[float, float]:
        self._note_collision()
        return self._reported_altaz()

    async def get_true_radec(self) -> tuple[float, float]:
        ra, dec = await self._hw_get_radec()
        now = self.clock.time()
        tracked = now - self._settled_at if self._drifting else 0.0
        east, north = self._errors.offset(self._slew_error, tracked, now)
        if self._terms is not None:
            ra, dec = self._terms.to_sky_icrs(ra, dec, self.observatory.longitude, now)
        return apply_sky_offset(ra, dec, east, north)

    async def move_ephemeris(self, target: dict[str, Any]) -> None:
        await super().move_ephemeris(target)
        self._followed_target = dict(target)

    async def get_true_motion(self) -> tuple[tuple[float, float], dict[str, Any] | None]:
        following = self._following is not None and self._tracking is not None
        return self._rates, (self._followed_target if following else None)

    # --- German-equatorial mode ----------------------------------------------------------------

    def _hour_angle_at(self, alt: float, az: float) -> tuple[float, float]:
        """(hour angle, dec) of the position (alt, az) now."""
        ra, dec = self._radec_of(alt, az)
        return hour_angle(ra, dec, self.observatory.longitude, self.clock.time()), dec

    def _current_side(self) -> PierSide:
        if self._gem is None:
            return PierSide.UNKNOWN
        if self._side is None:  # as parked at start-up: counterweight down
            self._side = destination_side(self._hour_angle_at(*self._park)[0])
        return self._side

    def _note_collision(self) -> None:
        """Record the collision once tracking has carried the mount past a limit (an exact time on
        the clock, found when anyone next looks at the mount or it moves)."""
        if self._limit_at is None or self._tracking is None or self.clock.time() < self._limit_at:
            return
        limits, side, at = self._gem, self._current_side(), self._limit_at
        assert limits is not None  # _limit_at is only set in GEM mode
        self._limit_at = None
        ha = hour_angle(*self._tracking, self.observatory.longitude, at)
        reason = limit_violation(ha + 1e-6, side, limits) or "a limit"
        self._collisions.append(PierCollision(time=at, hour_angle=ha, side=side, reason=reason))
        log.error("%s: pier limit passed while tracking: %s", self.name, reason)

    def _start_tracking(self, ra: float, dec: float) -> None:
        self._tracking, self._rates_since = (ra, dec), self.clock.time()
        if self._gem is not None:
            self._limit_at = self._limit_time(ra, dec)

    def _limit_time(self, ra: float, dec: float) -> float:
        """Clock time at which tracking (ra, dec) passes a limit on the current side (now if it has)."""
        assert self._gem is not None
        side, longitude, at = self._current_side(), self.observatory.longitude, self.clock.time()
        if limit_violation(hour_angle(ra, dec, longitude, at), side, self._gem) is not None:
            return at
        edge = limit_edge(side, self._gem)
        # Precession makes the hour angle of ICRS coordinates run a hair off the sidereal rate:
        # a few corrections find the crossing to far below a second.
        for _ in range(3):
            at += (edge - hour_angle(ra, dec, longitude, at)) / SIDEREAL_RATE
        return at

    def _hw_check_radec(self, ra: float, dec: float) -> None:
        if self._gem is None:
            return
        ha = hour_angle(ra, dec, self.observatory.longitude, self.clock.time())
        problem = limit_violation(ha, destination_side(ha), self._gem)
        if problem is not None:
            raise MoveError(f"target ra={ra:.4f}°, dec={dec:.4f}° is beyond the mount's limits: {problem}")

    async def _hw_get_pier_side(self) -> PierSide:
        self._note_collision()
        return self._current_side()

    async def _hw_get_destination_pier_side(self, ra: float, dec: float) -> PierSide:
        if self._gem is None:
            return PierSide.UNKNOWN
        return destination_side(hour_angle(ra, dec, self.observatory.longitude, self.clock.time()))

    async def get_pier_collisions(self) -> list[PierCollision]:
        self._note_collision()
        return list(self._collisions)

    def _slew_seconds(self, start: tuple[float, float], end: tuple[float, float], side: PierSide) -> float:
        """Seconds from (alt, az) ``start`` to ``end``: along the great circle, or on a GEM axis by
        axis from the current side to ``side``."""
        if self._gem is None:
            distance = angular_separation(start[1], start[0], end[1], end[0])
            return slew_time(distance, self._slew_rate, self._settle_time)
        south = self.observatory.latitude < 0.0
        here = mechanical_axes(*self._hour_angle_at(*start), self._current_side(), south=south)
        there = mechanical_axes(*self._hour_angle_at(*end), side, south=south)
        return axes_slew_time(here, there, self._slew_rate, self._settle_time)

    # --- motions -------------------------------------------------------------------------------

    def _hw_slew_time(self, alt: float, az: float) -> float:
        return self._slew_seconds(self._reported_altaz(), (alt, az), self._side_after_slew(alt, az))

    def _side_after_slew(self, alt: float, az: float) -> PierSide:
        """The pier side a slew to (alt, az) ends on: counterweight down on a GEM."""
        if self._gem is None:
            return self._current_side()
        return destination_side(self._hour_angle_at(alt, az)[0])

    async def _travel(
        self, alt: float, az: float, *, new_target: bool = True, keep_side: bool = False
    ) -> None:
        """Take as long as the slew from here to (alt, az); stopped midway, stay in between.

        A slew to a new target draws a new pointing miss and restarts the drift; an offset
        (``new_target=False``) keeps both, as a real mount's pointing model and tracking do. A GEM
        ends on the side with the counterweight down, unless ``keep_side`` (offsets).
        """
        self._note_collision()
        start_alt, start_az = self._reported_altaz()
        side = self._current_side() if keep_side else self._side_after_slew(alt, az)
        duration = self._slew_seconds((start_alt, start_az), (alt, az), side)
        started = self.clock.time()
        self._fixed_altaz = (start_alt, start_az)  # report where the move starts, not a stale position
        self._tracking, self._limit_at = None, None
        self._drifting = self._drifting and not new_target
        try:
            await self.clock.sleep(duration)
        except asyncio.CancelledError:
            f = min(1.0, (self.clock.time() - started) / duration) if duration > 0 else 1.0
            daz = (az - start_az + 180.0) % 360.0 - 180.0
            self._fixed_altaz = (start_alt + f * (alt - start_alt), (start_az + f * daz) % 360.0)
            if f >= 0.5 and self._gem is not None:  # a flip stopped past the pole: on the new side
                self._side = side
            raise
        self._fixed_altaz = (alt, az)
        if self._gem is not None:
            self._side = side
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
        self._rates = (0.0, 0.0)  # a new target: sidereal until told otherwise
        self._start_tracking(ra, dec)
        self._drifting = True

    async def _hw_move_altaz(self, alt: float, az: float) -> None:
        await self._travel(alt, az)

    async def _hw_offset_radec(self, ra: float, dec: float) -> None:
        await self._travel(*self._altaz_of(ra, dec), new_target=False, keep_side=True)
        self._start_tracking(ra, dec)

    async def _hw_offset_altaz(self, alt: float, az: float) -> None:
        await self._travel(alt, az, new_target=False, keep_side=True)

    async def _hw_stop(self) -> None:
        self._note_collision()
        tracked = self._tracked()
        if tracked is not None:
            self._fixed_altaz = self._altaz_of(*tracked)
            self._tracking, self._limit_at = None, None
        self._rates = (0.0, 0.0)
        self._drifting = False

    async def _hw_get_temperatures(self) -> dict[str, float]:
        return {}


def _gem_limits(gem: Mapping[str, float] | None) -> GemLimits | None:
    """The GEM limits from the ``gem`` option, or ConfigError naming the key at fault."""
    if gem is None:
        return None
    if not isinstance(gem, Mapping):
        raise ConfigError(
            f"must be a mapping of limits (east, west, counterweight_up), got {gem!r}", key="gem"
        )
    unknown = sorted(set(gem) - {"east", "west", "counterweight_up"})
    if unknown:
        raise ConfigError(
            f"unknown limit(s) {', '.join(unknown)}; known: east, west, counterweight_up", key="gem"
        )
    try:
        return GemLimits(**{name: float(value) for name, value in gem.items()})
    except (TypeError, ValueError) as exc:
        raise ConfigError(str(exc), key=f"gem.{str(exc).split()[0]}") from exc
