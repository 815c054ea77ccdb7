"""A nightcrew telescope as an INDI telescope: where it points, slews, abort, park, tracking.

INDI clients (KStars/Ekos, Stellarium) speak of the equator and equinox of date ("JNow") in
EQUATORIAL_EOD_COORD, RA in hours; nightcrew of J2000/ICRS degrees. Positions are converted both
ways at the server's clock time with :func:`nightcrew.astro.j2000_to_of_date`.

==========================  ======================================================================
property                    nightcrew
==========================  ======================================================================
EQUATORIAL_EOD_COORD        get_radec(); a client's new RA/DEC: move_radec() (Busy until on target)
HORIZONTAL_COORD (ro)       get_altaz()
ON_COORD_SET                TRACK or SLEW: both move_radec() (a nightcrew telescope tracks after it)
TELESCOPE_ABORT_MOTION      stop_motion()
TELESCOPE_PARK              PARK: park(); UNPARK: init()
TELESCOPE_TRACK_STATE       TRACK_ON while TRACKING; ON: move_radec() to where it points, OFF: stop
GEOGRAPHIC_COORD (ro)       the server's ``site`` (longitude 0..360 east), when it has one
==========================  ======================================================================
"""

from __future__ import annotations

from typing import Any

from nightcrew.astro import j2000_to_of_date, of_date_to_j2000
from nightcrew.bridges.indi.server_vectors import (
    NumberMember,
    Permission,
    Property,
    PropertyState,
    SwitchMember,
    SwitchRule,
)
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import ITelescope, MotionStatus
from nightcrew.modules.indi.server_device import MAIN_GROUP, ServedDevice, Values, switch_on

__all__ = ["ServedTelescope"]

_SEXAGESIMAL = "%010.6m"
_MOVING = frozenset({MotionStatus.SLEWING, MotionStatus.PARKING, MotionStatus.INITIALIZING})


class ServedTelescope(ServedDevice[ITelescope]):
    """An ITelescope module as an INDI telescope."""

    interface = ITelescope
    driver_interface = 1

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
            [SwitchMember("TRACK", "Track", True), SwitchMember("SLEW", "Slew")],
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
        ]
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
        else:
            raise InvalidArgumentError(f"{vector.where} cannot be set")

    async def _goto(self, values: Values) -> None:
        """Slew to the client's JNow position; a new target replaces one still being slewed to."""
        ra_hours = float(values.get("RA", self.eod.by_name["RA"].value))
        dec = float(values.get("DEC", self.eod.by_name["DEC"].value))
        ra, dec = of_date_to_j2000((ra_hours * 15.0) % 360.0, dec, self._link.clock.time())
        if self.acting(self.eod):
            await self.device.stop_motion()
        self._start(self.eod, self.device.move_radec(ra % 360.0, dec), replace=True)

    async def _track(self, on: bool) -> None:
        telescope = self.device
        if not on:
            await telescope.stop_motion()
        elif await telescope.get_motion_status() is not MotionStatus.TRACKING:
            await telescope.move_radec(*await telescope.get_radec())
