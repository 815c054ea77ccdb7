"""Non-sidereal tracking: a telescope follows a moving target along its ephemeris.

:class:`FollowsEphemerides` is a base of :class:`~.base.BaseTelescope`. ``move_ephemeris`` slews to
the body's topocentric position now (a normal ``move_radec``: limits, events, headers) and then a
background loop keeps the mount on it until anything else moves the mount:

* **By offset rates** where the driver can set them (``_hw_set_tracking_rates`` returns True:
  Alpaca's ``RightAscensionRate``/``DeclinationRate``, INDI's ``TELESCOPE_TRACK_RATE`` with
  ``TRACK_CUSTOM``, the simulated mount): at each update the rates are aimed from where the mount
  reports to point to where the body will be at the next update, so errors do not pile up; updates
  come as often as the path's curvature needs to stay within ``follow_error_limit``.
* **By position updates** otherwise: small moves to the body's position, as often as its motion
  needs to stay within ``follow_error_limit``.

Updates come at least every :data:`MAX_INTERVAL_S` and at most every :data:`MIN_INTERVAL_S` (2 Hz);
a satellite is always updated at 2 Hz. A move, park, stop or init by anyone else ends the following
(and sets the rates back to zero before that motion starts).
"""

from __future__ import annotations

import asyncio
import logging
import math
from abc import abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
from pydantic import Field, TypeAdapter, ValidationError

from nightcrew.astro.elements import TwoLineElements
from nightcrew.astro.ephemeris import Body, Ephemeris, ephemeris
from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.interfaces import FitsCard, INonSidereal, ITelescope, MotionStatus
from nightcrew.modules.motion import BaseMotion
from nightcrew.robotic.tasks import MovingTarget
from nightcrew.robotic.tasks._validation import problems_of
from nightcrew.site import Site

__all__ = [
    "MAX_INTERVAL_S",
    "MIN_INTERVAL_S",
    "FollowsEphemerides",
    "aim_rates",
    "ephemeris_cards",
    "follow_interval",
]

log = logging.getLogger(__name__)

#: Shortest time between two updates, seconds (2 Hz).
MIN_INTERVAL_S = 0.5
#: Longest time between two updates, seconds.
MAX_INTERVAL_S = 300.0
#: Statuses that mean someone else moves (or stops) the mount: following ends.
_OTHER_MOTIONS = frozenset(
    {MotionStatus.SLEWING, MotionStatus.PARKING, MotionStatus.PARKED, MotionStatus.INITIALIZING}
    | {MotionStatus.IDLE, MotionStatus.ERROR}
)
_MOVING_TARGET: TypeAdapter[MovingTarget] = TypeAdapter(Annotated[MovingTarget, Field(discriminator="type")])


def follow_interval(
    rate: float, acceleration: float, error_limit: float, *, by_rates: bool, satellite: bool
) -> float:
    """Seconds until the next update that keep the error below ``error_limit`` (arcsec).

    Args:
        rate: The body's motion on the sky, arcsec/s.
        acceleration: The change of that motion, arcsec/s² (what constant rates miss).
        error_limit: Largest error allowed, arcsec.
        by_rates: Whether the mount follows by offset rates (else by position updates).
        satellite: Satellites are updated at 2 Hz whatever the numbers say.
    """
    if by_rates:
        seconds = math.sqrt(2.0 * error_limit / acceleration) if acceleration > 0 else MAX_INTERVAL_S
    else:
        seconds = error_limit / rate if rate > 0 else MAX_INTERVAL_S
    if satellite:
        seconds = MIN_INTERVAL_S
    return min(MAX_INTERVAL_S, max(MIN_INTERVAL_S, seconds))


def aim_rates(now: tuple[float, float], then: tuple[float, float], seconds: float) -> tuple[float, float]:
    """Rates (arcsec/s of RA and of Dec) that carry the mount from ``now`` to ``then`` in ``seconds``."""
    d_ra = (then[0] - now[0] + 180.0) % 360.0 - 180.0
    return d_ra * 3600.0 / seconds, (then[1] - now[1]) * 3600.0 / seconds


def ephemeris_cards(name: str, found: Ephemeris) -> dict[str, FitsCard]:
    """FITS cards of a followed body's ephemeris at one time (the first of ``found``)."""
    return {
        "MOVOBJ": (name, "Moving target followed along its ephemeris"),
        "EPH-RA": (round(float(found.ra[0]), 7), "Ephemeris RA, astrometric topocentric [deg]"),
        "EPH-DEC": (round(float(found.dec[0]), 7), "Ephemeris Dec, astrometric topocentric [deg]"),
        "EPH-RAR": (round(float(found.ra_rate[0]), 6), "Ephemeris d(RA)/dt*cos(Dec) [arcsec/s]"),
        "EPH-DECR": (round(float(found.dec_rate[0]), 6), "Ephemeris d(Dec)/dt [arcsec/s]"),
        "EPH-DIST": (round(float(found.distance_km[0]), 3), "Ephemeris distance from the site [km]"),
    }


def parse_moving_target(target: Mapping[str, Any]) -> tuple[Body, str]:
    """The body and name of a moving target given as in a task file.

    Raises:
        InvalidArgumentError: Naming the field at fault (``target.tle_line2: checksum ...``).
    """
    try:
        parsed = _MOVING_TARGET.validate_python(dict(target))
    except ValidationError as exc:
        problem = next(iter(problems_of(exc, prefix="target")))
        raise InvalidArgumentError(str(problem)) from None
    return parsed.body(), parsed.name


@dataclass
class _Following:
    body: Body
    name: str
    by_rates: bool
    radec: tuple[float, float]  # the target this loop set last: anything else means someone moved


class FollowsEphemerides(BaseMotion, ITelescope, INonSidereal):
    """Non-sidereal tracking for a telescope (see the module docstring).

    Args:
        follow_error_limit: Largest error allowed while following a moving target, arcsec (> 0).
        **kwargs: Telescope and module options.
    """

    _target_radec: tuple[float, float] | None

    def __init__(self, *, follow_error_limit: float = 1.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not (math.isfinite(follow_error_limit) and follow_error_limit > 0):
            raise ConfigError(f"must be > 0 arcsec, got {follow_error_limit}", key="follow_error_limit")
        self._follow_error_limit = float(follow_error_limit)
        self._following: _Following | None = None
        self._following_starts = False  # our own slew must not end the following
        self._follow_wake = asyncio.Event()
        self._rates = (0.0, 0.0)
        self.add_background_task(self._follow_loop, name="follow")

    # --- hooks for drivers ---------------------------------------------------------------------

    @property
    @abstractmethod
    def observatory(self) -> Site:
        """Where the telescope stands."""

    @abstractmethod
    async def _hw_get_radec(self) -> tuple[float, float]:
        """Where the mount reports to point, ICRS degrees."""

    async def _hw_set_tracking_rates(self, ra_rate: float, dec_rate: float) -> bool:
        """Add (ra_rate, dec_rate) arcsec/s (RA as an angle of right ascension) to sidereal tracking;
        False (the default) when the mount cannot, so it is followed by position updates."""
        return False

    @abstractmethod
    async def _hw_offset_radec(self, ra: float, dec: float) -> None:
        """Move by a little to ICRS (ra, dec) and track (the position updates use it)."""

    # --- INonSidereal --------------------------------------------------------------------------

    async def move_ephemeris(self, target: dict[str, Any]) -> None:
        body, name = parse_moving_target(target)
        await self._set_rates(0.0, 0.0)
        now = self.clock.time()
        ra, dec = _radec(ephemeris(body, self.observatory, now), 0)
        self._following_starts = True
        try:
            await self.move_radec(ra, dec)
        finally:
            self._following_starts = False
        by_rates = await self._hw_set_tracking_rates(0.0, 0.0)
        radec = self._target_radec or (ra, dec)
        self._following = _Following(body, name, by_rates, radec)
        log.info(
            "%s: following %s by %s", self.name, name, "offset rates" if by_rates else "position updates"
        )
        self._follow_wake.set()

    async def get_tracking_rates(self) -> tuple[float, float]:
        return self._rates

    def _following_cards(self) -> dict[str, FitsCard]:
        """The followed body's ephemeris now (none when not following), for the frame's header."""
        following = self._following
        if following is None or self._target_radec is not following.radec:
            return {}
        return ephemeris_cards(following.name, ephemeris(following.body, self.observatory, self.clock.time()))

    # --- the loop ------------------------------------------------------------------------------

    async def _set_motion_status(self, status: MotionStatus) -> None:
        if status in _OTHER_MOTIONS and not self._following_starts and self._following is not None:
            self._following = None
            await self._set_rates(0.0, 0.0)  # before the other motion's hardware call
        await super()._set_motion_status(status)

    async def _set_rates(self, ra_rate: float, dec_rate: float) -> bool:
        """Set the offset rates; False when the mount cannot do these."""
        if self._rates == (ra_rate, dec_rate) == (0.0, 0.0):
            return True
        if not await self._hw_set_tracking_rates(ra_rate, dec_rate):
            return False
        self._rates = (ra_rate, dec_rate)
        return True

    async def _follow_loop(self) -> None:
        while True:
            following = self._following
            if following is None or self._target_radec is not following.radec:
                self._follow_wake.clear()
                await self._follow_wake.wait()
                continue
            seconds = await self._follow_step(following)
            await self.clock.sleep(seconds)

    async def _follow_step(self, following: _Following) -> float:
        """One update; returns the seconds until the next."""
        now = self.clock.time()
        satellite = isinstance(following.body, TwoLineElements)
        probe = ephemeris(following.body, self.observatory, np.array([now, now + 10.0]))
        rate = float(probe.rate[0])
        change = np.hypot(probe.ra_rate[1] - probe.ra_rate[0], probe.dec_rate[1] - probe.dec_rate[0])
        limit, by_rates = self._follow_error_limit, following.by_rates
        seconds = follow_interval(rate, float(change) / 10.0, limit, by_rates=by_rates, satellite=satellite)
        if self._motion.busy:
            return seconds  # someone else's motion runs: it ends the following, or we try again
        target = _radec(probe, 0)
        if following.by_rates:
            then = _radec(ephemeris(following.body, self.observatory, now + seconds), 0)
            if await self._set_rates(*aim_rates(await self._hw_get_radec(), then, seconds)):
                following.radec = self._target_radec = target
                return seconds
            await self._set_rates(0.0, 0.0)  # rates beyond what the mount does: a position update
        target = _radec(ephemeris(following.body, self.observatory, now + seconds / 2.0), 0)
        await self._hw_offset_radec(*target)
        following.radec = target
        self._target_radec = target
        return seconds


def _radec(found: Any, index: int) -> tuple[float, float]:
    return float(found.ra[index]), float(found.dec[index])
