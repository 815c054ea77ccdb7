"""The base of all telescope mounts: checks, states, events and headers; drivers do the moving.

Decisions (documented for drivers and callers):

* A telescope starts PARKED. Moves and offsets while parked (or after a motion error) are refused
  with MoveError: call ``init()`` first. ``park()`` and ``stop_motion()`` always work and abort a
  running slew; any other command while a motion runs gets DeviceBusyError.
* Targets below ``min_altitude`` are refused with MoveError before anything moves.
* Offsets: RA/Dec offsets apply while tracking an RA/Dec target, Alt/Az offsets while pointing at an
  Alt/Az position; a new move resets both.
* A mount that comes back from a restart of its server is put back where the module had it
  before the module is ready (drivers call ``_restore_pointing``): tracking its RA/Dec target,
  at its Alt/Az position (unparked first, as a mount comes back parked), or parked again when the
  module had parked it and the mount came back unparked.
* Pointing model: with ``pointing_model: FILE`` RA/Dec moves and offsets go to the position the
  model says the mount must be sent to, and the reported RA/Dec is where it really points (see
  nightcrew.modules.telescope.pointing_model).
* Pier side (IPierSide): German-equatorial drivers report the mount's side (ASCOM's SideOfPier)
  and the side a slew would end on; others report UNKNOWN. Frames get a PIERSIDE card (EAST or
  WEST) whenever the side is known.
* On BadWeatherEvent and on SafetyAlarmEvent (the safety watchdog's) the telescope parks by itself
  (aborting any slew), and so it does after ``park_when_offline`` clock seconds (default 300)
  without a connection to the other modules, and, with ``watchdog`` set, after
  ``park_when_watchdog_silent`` clock seconds without the watchdog's heartbeat (the dead-man's
  switch; see nightcrew.modules.motion.base).
"""

from __future__ import annotations

import logging
import math
from abc import abstractmethod
from collections.abc import Awaitable, Callable
from typing import Any

from nightcrew.astro import altaz_to_radec, radec_to_altaz
from nightcrew.config import DataPath
from nightcrew.errors import (
    ConfigError,
    InitError,
    InvalidArgumentError,
    MoveError,
    ParkError,
)
from nightcrew.events import (
    BadWeatherEvent,
    MoveAltAzEvent,
    MoveRaDecEvent,
    OffsetsAltAzEvent,
    OffsetsRaDecEvent,
    SafetyAlarmEvent,
)
from nightcrew.interfaces import (
    FitsCard,
    IFitsHeaderBefore,
    IOffsetsAltAz,
    IOffsetsRaDec,
    IPierSide,
    IPointingAltAz,
    IPointingRaDec,
    ITemperatures,
    ModuleState,
    MotionStatus,
    PierSide,
)
from nightcrew.interfaces.quantities import Altitude
from nightcrew.modules.telescope.following import FollowsEphemerides
from nightcrew.modules.telescope.headers import pier_side_cards, pointing_cards
from nightcrew.modules.telescope.pointing_model import TelescopePointingModel
from nightcrew.site import Site
from nightcrew.timeout import timeout

__all__ = ["BaseTelescope"]

log = logging.getLogger(__name__)

_NEEDS_INIT = frozenset({MotionStatus.PARKED, MotionStatus.ERROR, MotionStatus.UNKNOWN})


class BaseTelescope(
    FollowsEphemerides, IOffsetsRaDec, IOffsetsAltAz, IPierSide, ITemperatures, IFitsHeaderBefore
):
    """A telescope mount; a driver implements the ``_hw_*`` hooks.

    Args:
        min_altitude: Lowest altitude in degrees the telescope may be sent to (0..90).
        park_when_offline: Clock seconds without a connection to the other modules (the XMPP
            server) after which the telescope parks by itself; None: never.
        pointing_model: File of the mount's pointing model (see
            nightcrew.modules.telescope.pointing_model); None: no model.
        **kwargs: Module options (see BaseMotion; ``watchdog`` and ``park_when_watchdog_silent``
            arm the dead-man's switch); ``site`` is required (coordinates need it);
            ``follow_error_limit`` bounds the error following a moving target (see .following).
    """

    initial_status = MotionStatus.PARKED

    def __init__(
        self,
        *,
        min_altitude: Altitude = 10.0,
        park_when_offline: float | None = 300.0,
        pointing_model: DataPath | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(park_when_offline=park_when_offline, **kwargs)
        if not 0.0 <= min_altitude < 90.0:
            raise ConfigError(
                f"min_altitude must be within 0..90 degrees, got {min_altitude}", key="min_altitude"
            )
        if self.site is None:
            raise ConfigError("a telescope needs the observatory site to convert coordinates", key="site")
        self._min_altitude = float(min_altitude)
        self._target_radec: tuple[float, float] | None = None
        self._target_altaz: tuple[float, float] | None = None
        self._offsets_radec = (0.0, 0.0)
        self._offsets_altaz = (0.0, 0.0)
        self._parked_here = False  # parked by park(), not merely found parked at start-up
        self._pointing_model = TelescopePointingModel(pointing_model, self.name, self.observatory)

    @property
    def observatory(self) -> Site:
        site = self.site
        assert site is not None  # checked in the constructor
        return site

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(BadWeatherEvent, self.on_bad_weather)
        await self.comm.register_event(SafetyAlarmEvent, self.on_safety_alarm)

    # --- hooks for drivers ---------------------------------------------------------------------

    @abstractmethod
    async def _hw_init(self) -> None:
        """Unpark and home; return when the mount is ready to move."""

    @abstractmethod
    async def _hw_park(self) -> None:
        """Drive to the park position and stop tracking; return when there."""

    @abstractmethod
    async def _hw_move_radec(self, ra: float, dec: float) -> None:
        """Slew to ICRS (ra, dec) (offsets included) and track; return when on target."""

    @abstractmethod
    async def _hw_move_altaz(self, alt: float, az: float) -> None:
        """Slew to (alt, az) (offsets included), not tracking; return when there."""

    def _hw_slew_time(self, alt: float, az: float) -> float | None:
        """Clock seconds a slew from here to (alt, az) takes, settling included (part of the
        timeout a move announces); None (the default) when the driver does not know its rates."""
        return None

    @abstractmethod
    async def _hw_get_radec(self) -> tuple[float, float]:
        """Where the mount reports to point, ICRS degrees."""

    async def _hw_offset_radec(self, ra: float, dec: float) -> None:
        """Move to the offset position (ra, dec) of the current target and track.

        A move by default; a mount with its own offset command (which keeps its pointing model
        and tracking, unlike a slew to a new target) overrides this.
        """
        await self._hw_move_radec(ra, dec)

    async def _hw_offset_altaz(self, alt: float, az: float) -> None:
        """Move to the offset position (alt, az) of the current target; a move by default."""
        await self._hw_move_altaz(alt, az)

    async def _hw_get_altaz(self) -> tuple[float, float]:
        """Where the mount reports to point as (alt, az); converted from RA/Dec unless overridden."""
        return self._altaz_of(*await self._hw_get_radec())

    async def _hw_get_temperatures(self) -> dict[str, float]:
        """Thermometers of the mount (none by default)."""
        return {}

    async def _hw_get_pier_side(self) -> PierSide:
        """The mount's pointing state (German-equatorial mounts); UNKNOWN unless overridden."""
        return PierSide.UNKNOWN

    async def _hw_get_destination_pier_side(self, ra: float, dec: float) -> PierSide:
        """The side a slew to ICRS (ra, dec) would end on now; UNKNOWN unless overridden."""
        return PierSide.UNKNOWN

    def _hw_check_radec(self, ra: float, dec: float) -> None:
        """Raise MoveError if the mount cannot reach ICRS (ra, dec) now (its own limits); called
        before anything moves. Nothing to check by default."""

    async def _hw_at_park(self) -> bool | None:
        """Whether the mount says it is parked; None if it cannot tell (then a mount that came back
        from a restart is not parked again)."""
        return None

    # --- helpers -------------------------------------------------------------------------------

    async def _restore_pointing(self) -> None:
        """Put the mount back where this module had it, e.g. after its server restarted and it came
        back parked (or unparked): the RA/Dec target tracked, the Alt/Az position (each with its
        offsets), or parked. Drivers call this after reading the device, before they report ready."""
        if self._motion.busy:
            return
        status, radec, altaz = self._motion_status, self._target_radec, self._target_altaz
        if status is MotionStatus.TRACKING and radec is not None:
            dra, ddec = self._offsets_radec
            ra, dec = (radec[0] + dra) % 360.0, max(-90.0, min(90.0, radec[1] + ddec))
            log.warning("%s: the mount came back: tracking RA %.4f°, Dec %.4f° again", self.name, ra, dec)
            await self._hw_init()
            await self._hw_move_radec(*self._pointing_model.to_mount(ra, dec, self.clock.time()))
        elif status is MotionStatus.IDLE and altaz is not None:
            dalt, daz = self._offsets_altaz
            alt, az = altaz[0] + dalt, (altaz[1] + daz) % 360.0
            log.warning("%s: the mount came back: pointing at Alt %.3f°, Az %.3f° again", self.name, alt, az)
            await self._hw_init()
            await self._hw_move_altaz(alt, az)
        elif status is MotionStatus.PARKED and self._parked_here and await self._hw_at_park() is False:
            log.warning("%s: the mount came back unparked: parking it again", self.name)
            await self._hw_park()

    def _altaz_of(self, ra: float, dec: float) -> tuple[float, float]:
        site = self.observatory
        return radec_to_altaz(ra, dec, site.latitude, site.longitude, self.clock.time())

    def _radec_of(self, alt: float, az: float) -> tuple[float, float]:
        site = self.observatory
        return altaz_to_radec(alt, az, site.latitude, site.longitude, self.clock.time())

    def _check_can_move(self, what: str) -> None:
        if self._motion_status in _NEEDS_INIT:
            raise MoveError(f"cannot {what}: telescope is {self._motion_status}; call init() first")
        self._motion.check_idle()

    def _check_altitude(self, alt: float, what: str) -> None:
        if alt < self._min_altitude:
            raise MoveError(f"{what} is at altitude {alt:.2f}°, below the limit of {self._min_altitude:g}°")

    async def _slew(self, action: str, move: Callable[[], Awaitable[None]], final: MotionStatus) -> None:
        async def motion() -> None:
            await self._set_motion_status(MotionStatus.SLEWING)
            await self._guarded(move(), f"{action} failed")
            await self._set_motion_status(final)

        await self._run_motion(action, motion())

    # --- IMotion -------------------------------------------------------------------------------

    async def init(self) -> None:
        if self._motion_status not in _NEEDS_INIT and not self._motion.busy:
            return

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.INITIALIZING)
            self._parked_here = False
            await self._guarded(self._hw_init(), "init failed", InitError)
            await self._set_motion_status(MotionStatus.IDLE)

        await self._run_motion("init", motion())

    async def park(self) -> None:
        if self._motion_status is MotionStatus.PARKED and not self._motion.busy:
            return
        if self._motion.action == "park":  # e.g. bad weather while someone else parks: wait for it
            await self._motion.join()
            if self._motion_status is not MotionStatus.PARKED:
                raise ParkError(f"park failed: telescope is {self._motion_status}")
            return

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.PARKING)
            self._target_radec = self._target_altaz = None
            self._offsets_radec = self._offsets_altaz = (0.0, 0.0)
            await self._guarded(self._hw_park(), "park failed", ParkError)
            self._parked_here = True
            await self._set_motion_status(MotionStatus.PARKED)

        await self._run_motion("park", motion(), preempt=True)

    async def stop_motion(self, device: str | None = None) -> None:
        await super().stop_motion(device)
        self._target_radec = self._target_altaz = None

    def _status_after_stop(self) -> MotionStatus:
        return MotionStatus.PARKED if self._motion_status is MotionStatus.PARKED else MotionStatus.IDLE

    # --- pointing ------------------------------------------------------------------------------

    # Announced: the slew's length at the mount's rates where the driver knows them (else 300 s).
    @timeout(
        lambda self, ra, dec, **_: self._announced_move_timeout(
            lambda: self._hw_slew_time(*self._altaz_of(ra, dec)), IPointingRaDec.move_radec
        )
    )
    async def move_radec(self, ra: float, dec: float) -> None:
        _check_radec(ra, dec)
        self._check_can_move("move")
        alt, _ = self._altaz_of(ra, dec)
        self._check_altitude(alt, f"target ra={ra:.4f}°, dec={dec:.4f}°")
        self._hw_check_radec(ra, dec)
        self._target_radec, self._target_altaz = (ra, dec), None
        self._offsets_radec = self._offsets_altaz = (0.0, 0.0)
        await self.comm.send_event(MoveRaDecEvent(ra=ra, dec=dec))
        mount = self._pointing_model.to_mount(ra, dec, self.clock.time())
        await self._slew("move_radec", lambda: self._hw_move_radec(*mount), MotionStatus.TRACKING)

    @timeout(
        lambda self, alt, az, **_: self._announced_move_timeout(
            lambda: self._hw_slew_time(alt, az % 360.0), IPointingAltAz.move_altaz
        )
    )
    async def move_altaz(self, alt: float, az: float) -> None:
        if not (math.isfinite(alt) and -90.0 <= alt <= 90.0 and math.isfinite(az)):
            raise InvalidArgumentError(f"alt must be within -90..90 degrees and az finite, got ({alt}, {az})")
        az %= 360.0
        self._check_can_move("move")
        self._check_altitude(alt, f"target alt={alt:.4f}°, az={az:.4f}°")
        self._target_radec, self._target_altaz = None, (alt, az)
        self._offsets_radec = self._offsets_altaz = (0.0, 0.0)
        await self.comm.send_event(MoveAltAzEvent(alt=alt, az=az))
        await self._slew("move_altaz", lambda: self._hw_move_altaz(alt, az), MotionStatus.IDLE)

    async def get_radec(self) -> tuple[float, float]:
        return self._pointing_model.to_sky(*await self._hw_get_radec(), self.clock.time())

    async def get_altaz(self) -> tuple[float, float]:
        return await self._hw_get_altaz()

    # --- offsets -------------------------------------------------------------------------------

    async def set_offsets_radec(self, dra: float, ddec: float) -> None:
        if not (math.isfinite(dra) and math.isfinite(ddec) and abs(dra) <= 10.0 and abs(ddec) <= 10.0):
            raise InvalidArgumentError(f"offsets must be finite and within ±10 degrees, got ({dra}, {ddec})")
        self._check_can_move("offset")
        if self._target_radec is None:
            raise MoveError("no RA/Dec target to offset from; call move_radec() first")
        ra, dec = (self._target_radec[0] + dra) % 360.0, max(-90.0, min(90.0, self._target_radec[1] + ddec))
        self._check_altitude(self._altaz_of(ra, dec)[0], "offset position")
        self._offsets_radec = (dra, ddec)
        await self.comm.send_event(OffsetsRaDecEvent(dra=dra, ddec=ddec))
        mount = self._pointing_model.to_mount(ra, dec, self.clock.time())
        await self._slew("set_offsets_radec", lambda: self._hw_offset_radec(*mount), MotionStatus.TRACKING)

    async def get_offsets_radec(self) -> tuple[float, float]:
        return self._offsets_radec

    async def set_offsets_altaz(self, dalt: float, daz: float) -> None:
        if not (math.isfinite(dalt) and math.isfinite(daz) and abs(dalt) <= 10.0 and abs(daz) <= 10.0):
            raise InvalidArgumentError(f"offsets must be finite and within ±10 degrees, got ({dalt}, {daz})")
        self._check_can_move("offset")
        if self._target_altaz is None:
            raise MoveError("no Alt/Az target to offset from; call move_altaz() first")
        alt, az = self._target_altaz[0] + dalt, (self._target_altaz[1] + daz) % 360.0
        self._check_altitude(alt, "offset position")
        self._offsets_altaz = (dalt, daz)
        await self.comm.send_event(OffsetsAltAzEvent(dalt=dalt, daz=daz))
        await self._slew("set_offsets_altaz", lambda: self._hw_offset_altaz(alt, az), MotionStatus.IDLE)

    async def get_offsets_altaz(self) -> tuple[float, float]:
        return self._offsets_altaz

    # --- pier side ------------------------------------------------------------------------------

    async def get_pier_side(self) -> PierSide:
        return await self._hw_get_pier_side()

    async def get_destination_pier_side(self, ra: float, dec: float) -> PierSide:
        _check_radec(ra, dec)
        return await self._hw_get_destination_pier_side(ra, dec)

    # --- sensors and headers -------------------------------------------------------------------

    async def get_temperatures(self) -> dict[str, float]:
        return await self._hw_get_temperatures()

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        mount_radec = await self._hw_get_radec()
        radec = self._pointing_model.to_sky(*mount_radec, self.clock.time())
        cards = pointing_cards(
            radec=radec,
            altaz=await self._hw_get_altaz(),
            target=self._target_radec,
            offsets_radec=self._offsets_radec,
            offsets_altaz=self._offsets_altaz,
            site=self.observatory,
            unix_time=self.clock.time(),
        )
        return (
            cards
            | pier_side_cards(await self._hw_get_pier_side())
            | self._pointing_model.cards(mount_radec)
            | self._following_cards()
        )

    # --- safety --------------------------------------------------------------------------------

    async def on_bad_weather(self, event: BadWeatherEvent, sender: str) -> None:
        """Park by ourselves: the weather module's verdict must not depend on a mastermind."""
        if self._motion_status is MotionStatus.PARKED and not self._motion.busy:
            return
        log.warning("%s: bad weather (%s): parking", self.name, event.reason or "no reason given")
        await self.park()

    async def on_safety_alarm(self, event: SafetyAlarmEvent, sender: str) -> None:
        """Park by ourselves: the watchdog acts when the mastermind may not."""
        if self._motion_status is MotionStatus.PARKED and not self._motion.busy:
            return
        log.warning("%s: safety alarm (%s): parking", self.name, event.reason or f"raised by {sender}")
        await self.park()


def _check_radec(ra: float, dec: float) -> None:
    if not (math.isfinite(ra) and 0.0 <= ra < 360.0 and math.isfinite(dec) and -90.0 <= dec <= 90.0):
        raise InvalidArgumentError(
            f"ra must be within 0..360 and dec within -90..90 degrees, got ({ra}, {dec})"
        )
