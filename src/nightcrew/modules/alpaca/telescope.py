"""AlpacaTelescope: an ASCOM Alpaca telescope (mount) on the telescope base.

Slews use the Async methods (``SlewToCoordinatesAsync``, ``SlewToAltAzAsync``) and poll
``Slewing`` until it is false, bounded by ``slew_timeout``; a slew that is aborted (park,
stop_motion) sends ``AbortSlew``. Alpaca right ascension is in hours, nightcrew's in degrees.
RA/Dec slews switch tracking on first and Alt/Az slews switch it off (the Alpaca spec refuses
RA/Dec slews without tracking and Alt/Az slews with it).

Coordinates: nightcrew's are ICRS. A mount whose ``EquatorialSystem`` is 1 (topocentric, "JNow")
gets and reports positions on the mean equator of date (IAU 1976 precession; nutation and
aberration, < 30", are left to the mount's pointing model); any other system is taken as J2000.

Beyond ITelescope, run-time config options (IConfig) give the mount's own controls:
``tracking`` (on/off), ``tracking_rate`` (sidereal, lunar, solar, king), ``pier_side`` (read only),
and ISyncRaDec's ``sync_radec`` tells the mount where it points. IPierSide reads ``SideOfPier`` and
``DestinationSideOfPier`` (the latter with the target on the mount's equator, RA in hours); a mount
that implements neither reports UNKNOWN.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

import numpy as np

from nightcrew.astro.coords import precession_matrix
from nightcrew.errors import ConfigError, InvalidArgumentError, MoveError, NotSupportedError
from nightcrew.interfaces import ISyncRaDec, PierSide
from nightcrew.modules.alpaca.device import AlpacaModule
from nightcrew.modules.telescope import BaseTelescope

__all__ = ["AlpacaTelescope"]

log = logging.getLogger(__name__)

#: Alpaca DriveRates, by the names nightcrew uses.
TRACKING_RATES = {"sidereal": 0, "lunar": 1, "solar": 2, "king": 3}
#: Alpaca EquatorialCoordinateType of a mount on the equator of date.
_TOPOCENTRIC = 1
#: SI seconds in a sidereal second.
SIDEREAL_SECOND = 0.9972695663
#: Alpaca PierSide values.
PIER_SIDES = {-1: PierSide.UNKNOWN, 0: PierSide.EAST, 1: PierSide.WEST}


class AlpacaTelescope(AlpacaModule, BaseTelescope, ISyncRaDec):
    """A telescope mount reached over ASCOM Alpaca.

    Args:
        slew_timeout: Wall seconds a slew, park or unpark may take before it fails (below the 300 s
            the interfaces announce).
        **kwargs: ``server``, ``device_number`` and the other Alpaca options (AlpacaModule), and
            the telescope's (``min_altitude``, ``site``, ...).
    """

    device_type = "telescope"

    def __init__(self, *, slew_timeout: float = 240.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not slew_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {slew_timeout}", key="slew_timeout")
        self._slew_timeout = float(slew_timeout)
        self._can: dict[str, bool] = {}
        self._of_date = False  # the mount works on the equator of date (EquatorialSystem 1)

    async def _on_connected(self) -> None:
        for capability in (
            *("canpark", "canunpark", "cansettracking", "cansync", "canslewasync"),
            *("cansetrightascensionrate", "cansetdeclinationrate"),
        ):
            self._can[capability] = bool(await self._get(capability))
        try:
            self._of_date = await self._get("equatorialsystem") == _TOPOCENTRIC
        except NotSupportedError:
            self._of_date = False
        site = self.observatory
        latitude, longitude = await self._get("sitelatitude"), await self._get("sitelongitude")
        if abs(latitude - site.latitude) > 0.01 or abs((longitude - site.longitude + 180) % 360 - 180) > 0.01:
            log.warning(
                "%s: the mount's site (%.4f, %.4f) differs from the observatory's (%.4f, %.4f)",
                self.name,
                latitude,
                longitude,
                site.latitude,
                site.longitude,
            )
        await self._restore_pointing()

    # --- motions -------------------------------------------------------------------------------

    async def _wait_slewing_done(self, what: str) -> None:
        try:
            await self._poll_until(
                "slewing", lambda slewing: slewing is False, self._slew_timeout, what, MoveError
            )
        except asyncio.CancelledError:
            # Aborted (park, stop_motion, pre-emption): the mount must not finish the slew on its own.
            await asyncio.shield(self._put_best_effort("abortslew"))
            raise

    async def _hw_init(self) -> None:
        if await self._get("atpark"):
            if not self._can.get("canunpark", True):
                raise NotSupportedError(f"{self.device.name} is parked and cannot unpark")
            await self._put("unpark")
            await self._poll_until(
                "atpark", lambda parked: parked is False, self._slew_timeout, "unpark", MoveError
            )

    async def _hw_at_park(self) -> bool:
        return bool(await self._get("atpark"))

    async def _hw_park(self) -> None:
        if not self._can.get("canpark", True):
            raise NotSupportedError(f"{self.device.name} cannot park")
        await self._put("park")
        await self._poll_until("atpark", lambda parked: parked is True, self._slew_timeout, "park", MoveError)

    async def _set_tracking(self, on: bool) -> None:
        if self._can.get("cansettracking", True) and await self._get("tracking") is not on:
            await self._put("tracking", Tracking=on)

    async def _hw_move_radec(self, ra: float, dec: float) -> None:
        await self._set_tracking(True)
        mount_ra, mount_dec = self._to_mount(ra, dec)
        await self._put("slewtocoordinatesasync", RightAscension=mount_ra / 15.0, Declination=mount_dec)
        await self._wait_slewing_done(f"slew to RA {ra:.4f}°, Dec {dec:.4f}°")

    async def _hw_set_tracking_rates(self, ra_rate: float, dec_rate: float) -> bool:
        if not (self._can.get("cansetrightascensionrate") and self._can.get("cansetdeclinationrate")):
            return False
        # ASCOM: RightAscensionRate in seconds of RA per sidereal second, DeclinationRate in arcsec
        # per SI second.
        await self._put("rightascensionrate", RightAscensionRate=ra_rate / 15.0 * SIDEREAL_SECOND)
        await self._put("declinationrate", DeclinationRate=dec_rate)
        return True

    async def _hw_move_altaz(self, alt: float, az: float) -> None:
        await self._set_tracking(False)
        await self._put("slewtoaltazasync", Azimuth=az, Altitude=alt)
        await self._wait_slewing_done(f"slew to Alt {alt:.4f}°, Az {az:.4f}°")

    async def _hw_stop(self) -> None:
        await self._put_best_effort("abortslew")

    async def _hw_get_radec(self) -> tuple[float, float]:
        ra_hours, dec = await self._get("rightascension"), await self._get("declination")
        return self._from_mount((float(ra_hours) * 15.0) % 360.0, float(dec))

    def _to_mount(self, ra: float, dec: float) -> tuple[float, float]:
        return of_date(ra, dec, self.clock.time()) if self._of_date else (ra, dec)

    def _from_mount(self, ra: float, dec: float) -> tuple[float, float]:
        return of_date(ra, dec, self.clock.time(), inverse=True) if self._of_date else (ra, dec)

    async def _hw_get_altaz(self) -> tuple[float, float]:
        return float(await self._get("altitude")), float(await self._get("azimuth")) % 360.0

    async def _hw_get_pier_side(self) -> PierSide:
        try:
            return PIER_SIDES.get(int(await self._get("sideofpier")), PierSide.UNKNOWN)
        except NotSupportedError:
            return PierSide.UNKNOWN

    async def _hw_get_destination_pier_side(self, ra: float, dec: float) -> PierSide:
        mount_ra, mount_dec = self._to_mount(ra, dec)
        try:
            side = await self._get(
                "destinationsideofpier", RightAscension=mount_ra / 15.0, Declination=mount_dec
            )
        except NotSupportedError:
            return PierSide.UNKNOWN
        return PIER_SIDES.get(int(side), PierSide.UNKNOWN)

    # --- the mount's own controls --------------------------------------------------------------

    async def sync_radec(self, ra: float, dec: float) -> None:
        """Tell the mount it points at ICRS (ra, dec) degrees (it must be tracking)."""
        if not (0.0 <= ra < 360.0 and -90.0 <= dec <= 90.0):
            raise InvalidArgumentError(
                f"ra must be within 0..360 and dec within -90..90 degrees, got ({ra}, {dec})"
            )
        if not self._can.get("cansync", True):
            raise NotSupportedError(f"{self.device.name} cannot sync")
        self._motion.check_idle()
        mount_ra, mount_dec = self._to_mount(ra, dec)
        await self._put("synctocoordinates", RightAscension=mount_ra / 15.0, Declination=mount_dec)

    async def _get_config_tracking(self) -> bool:
        return bool(await self._get("tracking"))

    async def _set_config_tracking(self, value: bool) -> None:
        if not self._can.get("cansettracking", True):
            raise NotSupportedError(f"{self.device.name} cannot switch tracking")
        await self._put("tracking", Tracking=bool(value))

    async def _get_config_tracking_rate(self) -> str:
        rate = await self._get("trackingrate")
        return next((name for name, value in TRACKING_RATES.items() if value == rate), f"unknown ({rate})")

    async def _set_config_tracking_rate(self, value: str) -> None:
        if value not in TRACKING_RATES:
            raise InvalidArgumentError(f"unknown tracking rate {value!r}; known: {', '.join(TRACKING_RATES)}")
        await self._put("trackingrate", TrackingRate=TRACKING_RATES[value])

    async def _get_config_options_tracking_rate(self) -> list[str]:
        offered = await self._get("trackingrates")
        return [name for name, value in TRACKING_RATES.items() if value in offered]

    async def _get_config_pier_side(self) -> str:
        return str(await self._hw_get_pier_side())


def of_date(ra: float, dec: float, unix_time: float, *, inverse: bool = False) -> tuple[float, float]:
    """J2000 (ra, dec) degrees on the mean equator of date at ``unix_time``, or back with ``inverse``."""
    r, d = np.radians(ra), np.radians(dec)
    vector = np.array([np.cos(d) * np.cos(r), np.cos(d) * np.sin(r), np.sin(d)])
    matrix = precession_matrix(unix_time)
    x, y, z = (matrix.T if inverse else matrix) @ vector
    return float(np.degrees(np.arctan2(y, x)) % 360.0), float(np.degrees(np.arcsin(np.clip(z, -1.0, 1.0))))
