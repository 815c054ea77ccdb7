"""A nightcrew telescope as an INDI telescope: where it points, slews, abort, park, tracking.

INDI clients (KStars/Ekos, Stellarium) speak of the equator and equinox of date ("JNow") in
EQUATORIAL_EOD_COORD, RA in hours; nightcrew of J2000/ICRS degrees. Positions are converted both
ways at the server's clock time with :func:`nightcrew.astro.j2000_to_of_date`.

==========================  ======================================================================
property                    nightcrew
==========================  ======================================================================
EQUATORIAL_EOD_COORD        get_radec(); a client's new RA/DEC: move_radec() (Busy until on target)
HORIZONTAL_COORD (ro)       get_altaz()
ON_COORD_SET                TRACK or SLEW: both move_radec() (a nightcrew telescope tracks after it);
                            SYNC: sync_radec() (ISyncRaDec; else the request ends in Alert)
TELESCOPE_PIER_SIDE (ro)    get_pier_side() (IPierSide): PIER_EAST/PIER_WEST, both Off if unknown
TELESCOPE_INFO              apertures and focal lengths (mm) a client sets and reads; kept here
TIME_UTC                    the server's clock (UTC, OFFSET 0); a client's time is answered Ok and
                            not applied: nightcrew keeps its own clock
motion, slew rates, guiding see :mod:`.server_guiding` (IOffsetsRaDec; GUIDER bit 4 of the
                            driver interface)
TELESCOPE_ABORT_MOTION      stop_motion()
TELESCOPE_PARK              PARK: park(); UNPARK: init()
TELESCOPE_TRACK_STATE       TRACK_ON while TRACKING; ON: move_radec() to where it points, OFF: stop
GEOGRAPHIC_COORD (ro)       the server's ``site`` (longitude 0..360 east), when it has one
==========================  ======================================================================
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from nightcrew.astro import j2000_to_of_date, of_date_to_j2000
from nightcrew.bridges.indi.server_vectors import (
    NumberMember,
    Permission,
    Property,
    PropertyState,
    SwitchMember,
    SwitchRule,
    TextMember,
)
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import IOffsetsRaDec, IPierSide, ISyncRaDec, ITelescope, MotionStatus, PierSide
from nightcrew.modules.indi.server_guiding import HandControls
from nightcrew.modules.served.device_indi import MAIN_GROUP, ServedDevice, Values, switch_on

__all__ = ["ServedTelescope"]

_SEXAGESIMAL = "%010.6m"
_MOVING = frozenset({MotionStatus.SLEWING, MotionStatus.PARKING, MotionStatus.INITIALIZING})


class ServedTelescope(ServedDevice[ITelescope]):
    """An ITelescope module as an INDI telescope."""

    interface = ITelescope
    driver_interface = 1
    pier_side: Property[SwitchMember] | None = None
    hand: HandControls | None = None

    async def _build(self) -> list[Property[Any]]:
        name = self.name
        self.eod = Property(
            name,
            "EQUATORIAL_EOD_COORD",
            "Eq. Coordinates",
            MAIN_GROUP,
            [
                NumberMember("RA", "RA (hh:mm:ss)", 0.0, 0.0, 24.0, 0.0, _SEXAGESIMAL),
                NumberMember("DEC", "DEC (dd:mm:ss)", 0.0, -90.0, 90.0, 0.0, _SEXAGESIMAL),
            ],
            timeout=300.0,
        )
        self.horizontal = Property(
            name,
            "HORIZONTAL_COORD",
            "Horizontal Coordinates",
            MAIN_GROUP,
            [
                NumberMember("ALT", "Alt (dd:mm:ss)", 0.0, -90.0, 90.0, 0.0, _SEXAGESIMAL),
                NumberMember("AZ", "Az (dd:mm:ss)", 0.0, 0.0, 360.0, 0.0, _SEXAGESIMAL),
            ],
            perm=Permission.READ_ONLY,
        )
        self.coord_set = Property(
            name,
            "ON_COORD_SET",
            "On Set",
            MAIN_GROUP,
            [
                SwitchMember("TRACK", "Track", True),
                SwitchMember("SLEW", "Slew"),
                SwitchMember("SYNC", "Sync"),
            ],
            state=PropertyState.OK,
        )
        self.abort = Property(
            name, "TELESCOPE_ABORT_MOTION", "Abort Motion", MAIN_GROUP, [SwitchMember("ABORT", "Abort")]
        )
        self.abort.rule = SwitchRule.AT_MOST_ONE
        self.park = Property(
            name,
            "TELESCOPE_PARK",
            "Parking",
            MAIN_GROUP,
            [SwitchMember("PARK", "Park(ed)", True), SwitchMember("UNPARK", "UnPark(ed)")],
            timeout=300.0,
        )
        self.info = Property(
            name,
            "TELESCOPE_INFO",
            "Scope Properties",
            "Options",
            [
                NumberMember(key, label, 0.0, 0.0, 100000.0, 0.0, "%g")
                for key, label in (
                    ("TELESCOPE_APERTURE", "Aperture (mm)"),
                    ("TELESCOPE_FOCAL_LENGTH", "Focal Length (mm)"),
                    ("GUIDER_APERTURE", "Guider Aperture (mm)"),
                    ("GUIDER_FOCAL_LENGTH", "Guider Focal Length (mm)"),
                )
            ],
            state=PropertyState.OK,
        )
        self.time_utc = Property(
            name,
            "TIME_UTC",
            "UTC",
            "Site Management",
            [TextMember("UTC", "UTC Time"), TextMember("OFFSET", "UTC Offset", "0.00")],
            state=PropertyState.OK,
        )
        self.track = Property(
            name,
            "TELESCOPE_TRACK_STATE",
            "Tracking",
            MAIN_GROUP,
            [SwitchMember("TRACK_ON", "On"), SwitchMember("TRACK_OFF", "Off", True)],
            timeout=300.0,
        )
        vectors: list[Property[Any]] = [
            self.eod,
            self.horizontal,
            self.coord_set,
            self.abort,
            self.park,
            self.track,
            self.info,
            self.time_utc,
        ]
        self.pier_side = None
        if isinstance(self.device, IPierSide):
            self.pier_side = Property(
                name,
                "TELESCOPE_PIER_SIDE",
                "Pier Side",
                MAIN_GROUP,
                [
                    SwitchMember("PIER_WEST", "West (pointing east)"),
                    SwitchMember("PIER_EAST", "East (pointing west)"),
                ],
                perm=Permission.READ_ONLY,
                rule=SwitchRule.AT_MOST_ONE,
            )
            vectors.append(self.pier_side)
        self.hand = None
        if isinstance(self.device, IOffsetsRaDec):
            self.hand = HandControls(name, self._link)
            vectors += self.hand.vectors
            self.driver_info.by_name["DRIVER_INTERFACE"].value = str(self.driver_interface | 4)  # + GUIDER
        site = self._link.site
        if site is not None:
            vectors.append(
                Property(
                    name,
                    "GEOGRAPHIC_COORD",
                    "Location",
                    "Site Management",
                    [
                        NumberMember("LAT", "Lat (dd:mm:ss)", site.latitude, -90.0, 90.0, 0.0, _SEXAGESIMAL),
                        NumberMember(
                            "LONG", "Lon (dd:mm:ss)", site.longitude % 360.0, 0.0, 360.0, 0.0, _SEXAGESIMAL
                        ),
                        NumberMember("ELEV", "Elevation (m)", site.elevation, -200.0, 10000.0, 0.0, "%g"),
                    ],
                    perm=Permission.READ_ONLY,
                    state=PropertyState.OK,
                )
            )
        return vectors

    async def _update(self) -> None:
        telescope = self.device
        status = await telescope.get_motion_status()
        ra, dec = await telescope.get_radec()
        alt, az = await telescope.get_altaz()
        ra_date, dec_date = j2000_to_of_date(ra, dec, self._link.clock.time())
        self.eod.by_name["RA"].value = round(ra_date / 15.0, 7)
        self.eod.by_name["DEC"].value = round(dec_date, 6)
        self.horizontal.by_name["ALT"].value = round(alt, 6)
        self.horizontal.by_name["AZ"].value = round(az, 6)
        failed = status is MotionStatus.ERROR
        self._follow(self.eod, busy=status is MotionStatus.SLEWING, failed=failed)
        self.horizontal.state = PropertyState.BUSY if status in _MOVING else PropertyState.OK
        switch_on(self.park, "PARK" if status is MotionStatus.PARKED else "UNPARK")
        self._follow(
            self.park, busy=status in (MotionStatus.PARKING, MotionStatus.INITIALIZING), failed=failed
        )
        switch_on(self.track, "TRACK_ON" if status is MotionStatus.TRACKING else "TRACK_OFF")
        self._follow(self.track, busy=False, failed=failed)
        now = datetime.fromtimestamp(self._link.clock.time(), UTC)
        self.time_utc.by_name["UTC"].value = now.strftime("%Y-%m-%dT%H:%M:%S")
        if self.pier_side is not None and isinstance(telescope, IPierSide):
            side = await telescope.get_pier_side()
            self.pier_side.by_name["PIER_EAST"].on = side is PierSide.EAST
            self.pier_side.by_name["PIER_WEST"].on = side is PierSide.WEST
            self.pier_side.state = PropertyState.OK if side is not PierSide.UNKNOWN else PropertyState.IDLE

    async def _request(self, vector: Property[Any], values: Values) -> None:
        telescope = self.device
        if vector is self.eod:
            await self._goto(values)
        elif vector is self.coord_set:
            switch_on(self.coord_set, next(name for name, on in values.items() if on))
            self.coord_set.state = PropertyState.OK
            self._link.publish(self.coord_set)
        elif vector is self.abort:
            self.abort.by_name["ABORT"].on = False
            if values.get("ABORT"):
                self._start(self.abort, telescope.stop_motion())
        elif vector is self.park:
            self._start(self.park, telescope.park() if values.get("PARK") else telescope.init(), replace=True)
        elif vector is self.track:
            self._start(self.track, self._track(bool(values.get("TRACK_ON"))))
        elif vector is self.info:
            for key, value in values.items():
                self.info.by_name[key].value = float(value)
            self.info.state = PropertyState.OK
            self._link.publish(self.info)
        elif vector is self.time_utc:
            self.time_utc.state = PropertyState.OK
            self.time_utc.message = "nightcrew keeps its own clock; the time sent is not applied"
            self._link.publish(self.time_utc)
        elif self.hand is not None and isinstance(telescope, IOffsetsRaDec):
            await self._hand_request(self.hand, telescope, vector, values)
        else:
            raise InvalidArgumentError(f"{vector.where} cannot be set")

    async def _hand_request(
        self, hand: HandControls, telescope: IOffsetsRaDec, vector: Property[Any], values: Values
    ) -> None:
        if vector in (hand.slew_rate, hand.guide_rate):
            hand.set_rate(vector, values)
        elif vector in (hand.motion_ns, hand.motion_we):
            await hand.motion(telescope, vector, values)
        elif vector in (hand.guide_ns, hand.guide_we):
            self._start(vector, hand.pulse(telescope, vector, values))
        else:
            raise InvalidArgumentError(f"{vector.where} cannot be set")

    async def close(self) -> None:
        if self.hand is not None:
            await self.hand.close()
        await super().close()

    async def _goto(self, values: Values) -> None:
        """Slew to (or with ON_COORD_SET SYNC: sync on) the client's JNow position.

        A new target replaces one still being slewed to.
        """
        ra_hours = float(values.get("RA", self.eod.by_name["RA"].value))
        dec = float(values.get("DEC", self.eod.by_name["DEC"].value))
        ra, dec = of_date_to_j2000((ra_hours * 15.0) % 360.0, dec, self._link.clock.time())
        if self.coord_set.by_name["SYNC"].on:
            telescope = self.device
            if not isinstance(telescope, ISyncRaDec):
                raise InvalidArgumentError(
                    f"{self.eod.where}: ON_COORD_SET is SYNC, "
                    f"but {self.name} cannot sync (it offers no ISyncRaDec)"
                )
            self._start(self.eod, telescope.sync_radec(ra % 360.0, dec))
            return
        if self.acting(self.eod):
            await self.device.stop_motion()
        self._start(self.eod, self.device.move_radec(ra % 360.0, dec), replace=True)

    async def _track(self, on: bool) -> None:
        telescope = self.device
        if not on:
            await telescope.stop_motion()
        elif await telescope.get_motion_status() is not MotionStatus.TRACKING:
            await telescope.move_radec(*await telescope.get_radec())
