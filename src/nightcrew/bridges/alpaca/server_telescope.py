"""A nightcrew telescope (ITelescope) served as an Alpaca Telescope.

Alpaca gives right ascension in hours, nightcrew in degrees; both use ICRS/J2000 coordinates
(EquatorialSystem 2). Slews, park and unpark run in the background (``Slewing`` is true while the
nightcrew move runs), the synchronous SlewTo* members wait for the move. Unpark is nightcrew's
``init()``; the mount tracks after an RA/Dec slew and stops tracking after an Alt/Az slew, so
Tracking is read-only (CanSetTracking false). PulseGuide moves the module's RA/Dec offsets
(IOffsetsRaDec) by the guide rate times the pulse's length; IsPulseGuiding stays true for the
pulse's length (wall time) after the offset is applied. Members the interface cannot serve (sync,
axis rates, pier side) answer NotImplemented; the site members need the server's site.
"""

from __future__ import annotations

import asyncio
from typing import Any

from nightcrew.astro import local_sidereal_time
from nightcrew.bridges.alpaca.errors import AlpacaValueNotSetError
from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest
from nightcrew.errors import DeviceBusyError, InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import IOffsetsRaDec, ITelescope, MotionStatus
from nightcrew.site import Site

__all__ = ["GUIDE_RATE", "ServedTelescope"]

#: EquatorialSystem: J2000 (nightcrew works in ICRS, which agrees with J2000 to milliarcseconds).
_J2000 = 2
#: DriveRates: sidereal.
_SIDEREAL = 0
_MOVING = frozenset({MotionStatus.SLEWING, MotionStatus.PARKING, MotionStatus.INITIALIZING})
#: Guide rate in degrees per second on both axes: half the sidereal rate, as most mounts default.
GUIDE_RATE = 0.5 * 360.0 / 86164.0905
#: GuideDirections (north, south, east, west) → signs of the (RA, Dec) offset; east is +RA.
_GUIDE_DIRECTIONS = {0: (0.0, 1.0), 1: (0.0, -1.0), 2: (1.0, 0.0), 3: (-1.0, 0.0)}
#: The longest pulse accepted, ms (a guide pulse is seconds at most; this bounds a typo).
_MAX_PULSE_MS = 60_000


class ServedTelescope(ServedDevice):
    """Alpaca Telescope (ITelescopeV4 members) on a nightcrew ITelescope module."""

    device_type = "telescope"
    type_name = "Telescope"
    interface_version = 4  # ITelescopeV4 (Platform 7)
    state_members = (
        "Altitude",
        "AtHome",
        "AtPark",
        "Azimuth",
        "Declination",
        "IsPulseGuiding",
        "RightAscension",
        "SideOfPier",
        "SiderealTime",
        "Slewing",
        "Tracking",
        "UTCDate",
    )
    interface = ITelescope

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._pulses: dict[str, asyncio.Future[None]] = {}
        self._target_ra_hours: float | None = None
        self._target_dec: float | None = None

    async def _telescope(self) -> ITelescope:
        return await self.proxy(ITelescope)

    def _site(self, member: str) -> Site:
        site = self.owner.site
        if site is None:
            raise NotSupportedError(f"{member}: the Alpaca server has no site configured")
        return site

    # --- position ------------------------------------------------------------------------------

    async def get_rightascension(self, request: AlpacaRequest) -> float:
        ra, _ = await (await self._telescope()).get_radec()
        return ra / 15.0

    async def get_declination(self, request: AlpacaRequest) -> float:
        _, dec = await (await self._telescope()).get_radec()
        return dec

    async def get_altitude(self, request: AlpacaRequest) -> float:
        alt, _ = await (await self._telescope()).get_altaz()
        return alt

    async def get_azimuth(self, request: AlpacaRequest) -> float:
        _, az = await (await self._telescope()).get_altaz()
        return az

    async def get_equatorialsystem(self, request: AlpacaRequest) -> int:
        return _J2000

    async def get_siderealtime(self, request: AlpacaRequest) -> float:
        site = self._site("siderealtime")
        return float(local_sidereal_time(self.owner.clock.time(), site.longitude)) / 15.0

    async def get_sitelatitude(self, request: AlpacaRequest) -> float:
        return self._site("sitelatitude").latitude

    async def get_sitelongitude(self, request: AlpacaRequest) -> float:
        return self._site("sitelongitude").longitude

    async def get_siteelevation(self, request: AlpacaRequest) -> float:
        return self._site("siteelevation").elevation

    async def get_utcdate(self, request: AlpacaRequest) -> str:
        return self.owner.clock.now().strftime("%Y-%m-%dT%H:%M:%S.%fZ")

    # --- state ---------------------------------------------------------------------------------

    async def _status(self) -> MotionStatus:
        return await (await self._telescope()).get_motion_status()

    async def get_slewing(self, request: AlpacaRequest) -> bool:
        self.action.raise_failure()
        return self.action.running or await self._status() in _MOVING

    async def get_tracking(self, request: AlpacaRequest) -> bool:
        return await self._status() is MotionStatus.TRACKING

    async def put_tracking(self, request: AlpacaRequest) -> None:
        request.boolean("Tracking")
        raise NotSupportedError("tracking: nightcrew tracks after an RA/Dec slew; CanSetTracking is false")

    async def get_atpark(self, request: AlpacaRequest) -> bool:
        self.action.raise_failure()
        return await self._status() is MotionStatus.PARKED

    async def get_athome(self, request: AlpacaRequest) -> bool:
        return False

    async def get_trackingrate(self, request: AlpacaRequest) -> int:
        return _SIDEREAL

    async def get_trackingrates(self, request: AlpacaRequest) -> list[int]:
        return [_SIDEREAL]

    async def get_rightascensionrate(self, request: AlpacaRequest) -> float:
        return 0.0

    async def get_declinationrate(self, request: AlpacaRequest) -> float:
        return 0.0

    async def get_ispulseguiding(self, request: AlpacaRequest) -> bool:
        return any(not pulse.done() for pulse in self._pulses.values())

    # --- pulse guiding: a pulse is an offset of the module's IOffsetsRaDec ---------------------

    async def get_canpulseguide(self, request: AlpacaRequest) -> bool:
        return await self.optional(IOffsetsRaDec) is not None

    async def get_guideraterightascension(self, request: AlpacaRequest) -> float:
        return GUIDE_RATE

    get_guideratedeclination = get_guideraterightascension

    async def put_pulseguide(self, request: AlpacaRequest) -> None:
        direction, duration = request.integer("Direction"), request.integer("Duration")
        if direction not in _GUIDE_DIRECTIONS:
            raise InvalidArgumentError(
                f"direction must be 0 (north), 1 (south), 2 (east) or 3 (west), got {direction}"
            )
        if not 0 <= duration <= _MAX_PULSE_MS:
            raise InvalidArgumentError(f"duration must be within 0..{_MAX_PULSE_MS} ms, got {duration}")
        offsets = await self.optional(IOffsetsRaDec)
        if offsets is None:
            raise NotSupportedError(
                f"pulseguide: module {self.module} has no RA/Dec offsets (CanPulseGuide is false)"
            )
        if self.action.running:
            raise DeviceBusyError(f"pulseguide: {self.describe()} is busy with {self.action.current}")
        axis = "dec" if direction < 2 else "ra"
        running = self._pulses.get(axis)
        if running is not None and not running.done():
            raise DeviceBusyError(f"pulseguide: a pulse on the {axis} axis is still running")
        ra_sign, dec_sign = _GUIDE_DIRECTIONS[direction]
        step = GUIDE_RATE * duration / 1000.0
        dra, ddec = await offsets.get_offsets_radec()
        await offsets.set_offsets_radec(dra + ra_sign * step, ddec + dec_sign * step)
        # The offset is applied at once; IsPulseGuiding then stays true for the pulse's length (wall
        # time), as clients that time their guiding expect. AbortSlew ends it.
        self._pulses[axis] = asyncio.get_running_loop().create_task(asyncio.sleep(duration / 1000.0))

    async def get_doesrefraction(self, request: AlpacaRequest) -> bool:
        return False

    # --- capabilities --------------------------------------------------------------------------

    async def get_canslew(self, request: AlpacaRequest) -> bool:
        return True

    get_canslewasync = get_canslewaltaz = get_canslewaltazasync = get_canslew
    get_canpark = get_canunpark = get_canslew

    async def get_cansync(self, request: AlpacaRequest) -> bool:
        return False

    get_cansyncaltaz = get_canfindhome = get_cansettracking = get_cansync
    get_cansetpark = get_cansetpierside = get_cansetguiderates = get_cansync
    get_cansetrightascensionrate = get_cansetdeclinationrate = get_cansync

    async def get_canmoveaxis(self, request: AlpacaRequest) -> bool:
        axis = request.integer("Axis")
        if axis not in (0, 1, 2):
            raise InvalidArgumentError(f"canmoveaxis: Axis must be 0, 1 or 2, got {axis}")
        return False

    # --- targets -------------------------------------------------------------------------------

    async def get_targetrightascension(self, request: AlpacaRequest) -> float:
        if self._target_ra_hours is None:
            raise AlpacaValueNotSetError("targetrightascension has not been set")
        return self._target_ra_hours

    async def put_targetrightascension(self, request: AlpacaRequest) -> None:
        self._target_ra_hours = _hours(request.number("TargetRightAscension"))

    async def get_targetdeclination(self, request: AlpacaRequest) -> float:
        if self._target_dec is None:
            raise AlpacaValueNotSetError("targetdeclination has not been set")
        return self._target_dec

    async def put_targetdeclination(self, request: AlpacaRequest) -> None:
        self._target_dec = _declination(request.number("TargetDeclination"))

    # --- motions -------------------------------------------------------------------------------

    def _radec(self, request: AlpacaRequest) -> tuple[float, float]:
        ra_hours = _hours(request.number("RightAscension"))
        dec = _declination(request.number("Declination"))
        self._target_ra_hours, self._target_dec = ra_hours, dec
        return ra_hours * 15.0, dec

    def _target(self, member: str) -> tuple[float, float]:
        if self._target_ra_hours is None or self._target_dec is None:
            raise InvalidArgumentError(f"{member}: set TargetRightAscension and TargetDeclination first")
        return self._target_ra_hours * 15.0, self._target_dec

    async def _start_radec(self, action: str, ra: float, dec: float) -> None:
        telescope = await self._telescope()
        self.action.start(action, lambda: telescope.move_radec(ra, dec))
        await self.action.settle(self.settle_time)

    async def put_slewtocoordinatesasync(self, request: AlpacaRequest) -> None:
        await self._start_radec("slewtocoordinatesasync", *self._radec(request))

    async def put_slewtotargetasync(self, request: AlpacaRequest) -> None:
        await self._start_radec("slewtotargetasync", *self._target("slewtotargetasync"))

    async def put_slewtoaltazasync(self, request: AlpacaRequest) -> None:
        alt, az = _altaz(request)
        telescope = await self._telescope()
        self.action.start("slewtoaltazasync", lambda: telescope.move_altaz(alt, az))
        await self.action.settle(self.settle_time)

    async def put_slewtocoordinates(self, request: AlpacaRequest) -> None:
        await (await self._telescope()).move_radec(*self._radec(request))

    async def put_slewtotarget(self, request: AlpacaRequest) -> None:
        await (await self._telescope()).move_radec(*self._target("slewtotarget"))

    async def put_slewtoaltaz(self, request: AlpacaRequest) -> None:
        await (await self._telescope()).move_altaz(*_altaz(request))

    async def put_abortslew(self, request: AlpacaRequest) -> None:
        telescope = await self._telescope()
        await telescope.stop_motion()
        await self.action.cancel()
        for pulse in self._pulses.values():
            pulse.cancel()

    async def put_park(self, request: AlpacaRequest) -> None:
        telescope = await self._telescope()
        self.action.start("park", telescope.park, preempt=True)  # parking always wins
        await self.action.settle(self.settle_time)

    async def put_unpark(self, request: AlpacaRequest) -> None:
        telescope = await self._telescope()
        self.action.start("unpark", telescope.init)
        await self.action.settle(self.settle_time)


def _hours(value: float) -> float:
    if not 0.0 <= value < 24.0:
        raise InvalidArgumentError(f"right ascension must be within 0..24 hours, got {value}")
    return value


def _declination(value: float) -> float:
    if not -90.0 <= value <= 90.0:
        raise InvalidArgumentError(f"declination must be within -90..90 degrees, got {value}")
    return value


def _altaz(request: AlpacaRequest) -> tuple[float, float]:
    """(alt, az) of a SlewToAltAz request, range-checked."""
    alt, az = request.number("Altitude"), request.number("Azimuth")
    if not -90.0 <= alt <= 90.0:
        raise InvalidArgumentError(f"altitude must be within -90..90 degrees, got {alt}")
    if not 0.0 <= az < 360.0:
        raise InvalidArgumentError(f"azimuth must be within 0..360 degrees, got {az}")
    return alt, az
