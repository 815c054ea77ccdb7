"""A telescope mount behind an INDI driver (standard telescope properties).

INDI mounts take and report ``EQUATORIAL_EOD_COORD`` (RA in hours, Dec in degrees) on the mean
equator and equinox of date ("JNow"); nightcrew speaks ICRS/J2000 degrees. The conversion is
:func:`nightcrew.astro.j2000_to_of_date` and its inverse, at the clock's time. Moves use
``ON_COORD_SET`` TRACK (RA/Dec targets) or SLEW (Alt/Az positions, not tracking), ``SYNC`` for
:meth:`IndiTelescope.sync_radec`; park and unpark ``TELESCOPE_PARK``; stop
``TELESCOPE_ABORT_MOTION``; tracking ``TELESCOPE_TRACK_STATE``; a moving target's offset rates
``TELESCOPE_TRACK_RATE`` with ``TELESCOPE_TRACK_MODE`` TRACK_CUSTOM (INDI's RA rate is the RA
axis's: the sidereal rate less the body's motion in RA, and at most the sidereal rate, as a mount
does not reverse its RA axis while tracking; the DE rate turns the declination axis, whose sense on
the sky flips with the pier side, as the telescope simulator shows). A slew ends when the coordinate
vector leaves Busy. Slews started by another INDI client are reported too (SLEWING, then TRACKING
or IDLE). The pier side (IPierSide) is ``TELESCOPE_PIER_SIDE`` (PIER_EAST, PIER_WEST: ASCOM's sides) where
the driver has it; INDI has no destination side, so that is UNKNOWN.

Example (``examples/indi/telescope.yaml``)::

    class: nightcrew.modules.indi.IndiTelescope
    host: 192.168.1.20
    device: Telescope Simulator
"""

from __future__ import annotations

import logging
from functools import partial
from typing import Any

from nightcrew.astro import angular_separation, j2000_to_of_date, of_date_to_j2000
from nightcrew.bridges.indi import IndiUpdate, PropertyState, Vector
from nightcrew.errors import InvalidArgumentError, MoveError
from nightcrew.interfaces import ISyncRaDec, MotionStatus, PierSide
from nightcrew.modules.indi.link import IndiModule
from nightcrew.modules.telescope import BaseTelescope

__all__ = ["IndiTelescope"]

log = logging.getLogger(__name__)

_COORD = "EQUATORIAL_EOD_COORD"
#: A coordinate update closer than this (degrees) to the target counts as arrived even without Busy.
_ON_TARGET = 0.01
#: Slews towards one target before the mount's own idea of "there" is accepted.
_APPROACHES = 3
#: INDI's sidereal tracking rate in RA, arcsec/s.
_SIDEREAL_RATE = 15.041067


class IndiTelescope(IndiModule, BaseTelescope, ISyncRaDec):
    """An INDI mount.

    Args:
        set_site: Send nightcrew's site to the mount (``GEOGRAPHIC_COORD``) on every connection,
            so that both compute the same Alt/Az.
        **kwargs: INDI options (``host``, ``port``, ``device`` ...) and telescope options.
    """

    indi_needs = (_COORD, "ON_COORD_SET", "TELESCOPE_PARK", "TELESCOPE_ABORT_MOTION")

    def __init__(self, *, set_site: bool = True, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._set_site = bool(set_site)

    # --- connection ----------------------------------------------------------------------------

    async def _on_indi_ready(self) -> None:
        indi = self._indi
        if self._set_site and indi.has("GEOGRAPHIC_COORD"):
            site = self.observatory
            await indi.send(
                "GEOGRAPHIC_COORD",
                {"LAT": site.latitude, "LONG": site.longitude % 360.0, "ELEV": site.elevation},
                wait=indi.connect_timeout,
            )
        await self._restore_pointing()  # before the status is read from the (restarted) device
        if not self._motion.busy:
            await self._set_motion_status(self._device_status())

    def _device_status(self) -> MotionStatus:
        park = self._indi.client.vector(self._indi.device, "TELESCOPE_PARK")
        if park.members.get("PARK"):
            return MotionStatus.PARKED
        coord = self._indi.client.vector(self._indi.device, _COORD)
        if coord.state is PropertyState.BUSY:
            return MotionStatus.SLEWING
        if coord.state is PropertyState.ALERT:
            return MotionStatus.ERROR
        return MotionStatus.TRACKING if self._tracking() else MotionStatus.IDLE

    def _tracking(self) -> bool:
        track = self._indi.client.properties.get((self._indi.device, "TELESCOPE_TRACK_STATE"))
        return track is not None and bool(track.members.get("TRACK_ON"))

    async def _on_indi_update(self, update: IndiUpdate) -> None:
        """Follow motions we did not start (another client, the hand box)."""
        if update.name not in (_COORD, "TELESCOPE_PARK") or self._motion.busy:
            return
        await self._set_motion_status(self._device_status())

    # --- hooks ---------------------------------------------------------------------------------

    async def _hw_init(self) -> None:
        park = self._indi.vector("TELESCOPE_PARK")
        if park.members.get("PARK"):
            await self._indi.send(
                "TELESCOPE_PARK",
                {"PARK": False, "UNPARK": True},
                wait=self._move_timeout,
                done=lambda v: v.members.get("UNPARK") is True,
            )

    async def _hw_at_park(self) -> bool:
        return bool(self._indi.vector("TELESCOPE_PARK").members.get("PARK"))

    async def _hw_park(self) -> None:
        await self._indi.send(
            "TELESCOPE_PARK",
            {"PARK": True, "UNPARK": False},
            wait=self._move_timeout,
            done=lambda v: v.members.get("PARK") is True,
        )

    async def _goto(self, ra: float, dec: float, mode: str) -> None:
        """Slew to ICRS (ra, dec) with ON_COORD_SET ``mode`` (TRACK, SLEW or SYNC).

        A mount may end a long slew short of the target (the simulator aims at the hour angle of
        the slew's start, so the sky has moved on when it arrives): then it slews again, at most
        :data:`_APPROACHES` times in all.
        """
        await self._indi.switch("ON_COORD_SET", mode, wait=self._indi.connect_timeout)
        for _ in range(_APPROACHES):
            ra_now, dec_now = j2000_to_of_date(ra, dec, self.clock.time())

            arrived = partial(_near, ra_now, dec_now)
            vector = await self._indi.send(
                _COORD, {"RA": ra_now / 15.0, "DEC": dec_now}, wait=self._move_timeout, done=arrived
            )
            if mode == "SYNC" or arrived(vector):
                return
            log.info("%s: %s ended off the target; approaching again", self.name, mode)

    async def _hw_move_radec(self, ra: float, dec: float) -> None:
        await self._goto(ra, dec, "TRACK")
        if self._indi.has("TELESCOPE_TRACK_STATE") and not self._tracking():
            # ON_COORD_SET TRACK does not switch tracking back on everywhere (the simulator).
            await self._indi.switch("TELESCOPE_TRACK_STATE", "TRACK_ON", wait=self._indi.connect_timeout)

    async def _hw_set_tracking_rates(self, ra_rate: float, dec_rate: float) -> bool:
        indi = self._indi
        if not (indi.has("TELESCOPE_TRACK_RATE") and indi.has("TELESCOPE_TRACK_MODE")):
            return False
        if "TRACK_CUSTOM" not in indi.vector("TELESCOPE_TRACK_MODE").members:
            return False
        if ra_rate == dec_rate == 0.0:
            await indi.switch("TELESCOPE_TRACK_MODE", "TRACK_SIDEREAL", wait=indi.connect_timeout)
            return True
        axis_ra = _SIDEREAL_RATE - ra_rate
        if axis_ra <= 0.0:
            return False
        axis_de = -dec_rate if await self._hw_get_pier_side() is PierSide.WEST else dec_rate
        await indi.switch("TELESCOPE_TRACK_MODE", "TRACK_CUSTOM", wait=indi.connect_timeout)
        rates: dict[str, float | bool | str] = {"TRACK_RATE_RA": axis_ra, "TRACK_RATE_DE": axis_de}
        await indi.send("TELESCOPE_TRACK_RATE", rates, wait=indi.connect_timeout)
        return True

    async def _hw_move_altaz(self, alt: float, az: float) -> None:
        await self._goto(*self._radec_of(alt, az), "SLEW")
        if self._tracking():  # some drivers (the simulator) track after any slew: stay at (alt, az)
            await self._indi.switch("TELESCOPE_TRACK_STATE", "TRACK_OFF", wait=self._indi.connect_timeout)

    async def _hw_get_radec(self) -> tuple[float, float]:
        coord = self._indi.vector(_COORD)
        return of_date_to_j2000(coord.number("RA") * 15.0, coord.number("DEC"), self.clock.time())

    async def _hw_stop(self) -> None:
        await self._indi.abort("TELESCOPE_ABORT_MOTION")

    async def _hw_get_pier_side(self) -> PierSide:
        if not self._indi.has("TELESCOPE_PIER_SIDE"):
            return PierSide.UNKNOWN
        members = self._indi.vector("TELESCOPE_PIER_SIDE").members
        if members.get("PIER_EAST"):
            return PierSide.EAST
        return PierSide.WEST if members.get("PIER_WEST") else PierSide.UNKNOWN

    # --- beyond ITelescope ---------------------------------------------------------------------

    async def sync_radec(self, ra: float, dec: float) -> None:
        """Tell the mount it points at ICRS (ra, dec) now (after a plate solve); nothing moves."""
        if not (0.0 <= ra < 360.0 and -90.0 <= dec <= 90.0):
            raise InvalidArgumentError(f"ra must be within 0..360 and dec within -90..90, got ({ra}, {dec})")
        self._check_can_move("sync")
        await self._guarded(self._goto(ra, dec, "SYNC"), "sync failed", MoveError)

    async def set_tracking(self, enabled: bool) -> None:
        """Switch sidereal tracking on or off (TELESCOPE_TRACK_STATE)."""
        if not self._indi.has("TELESCOPE_TRACK_STATE"):
            raise MoveError(f"{self._indi.where} has no TELESCOPE_TRACK_STATE")
        self._check_can_move("change tracking")
        await self._guarded(
            self._indi.switch("TELESCOPE_TRACK_STATE", "TRACK_ON" if enabled else "TRACK_OFF", wait=30.0),
            "changing tracking failed",
        )
        await self._set_motion_status(MotionStatus.TRACKING if enabled else MotionStatus.IDLE)


def _near(ra: float, dec: float, vector: Vector) -> bool:
    """Whether the coordinate vector (JNow, RA in hours) reports (ra, dec) (JNow, degrees)."""
    return bool(angular_separation(vector.number("RA") * 15.0, vector.number("DEC"), ra, dec) < _ON_TARGET)
