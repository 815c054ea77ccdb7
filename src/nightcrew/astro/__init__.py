"""Pure astronomical formulas: time scales, coordinates, the Sun and the Moon.

Fast low-precision functions (no astropy at run time, no clock, no I/O), shared by the devices,
the simulator, the scheduler, the mastermind and the reports, so each formula exists once:

- :mod:`.time`: Julian date, modified Julian date, Julian year and local sidereal time.
- :mod:`.coords`: precession, (ra, dec) ↔ (alt, az), separations, airmass, sexagesimal text.
- :mod:`.sun`: the Sun's position and altitude, its crossings of an altitude, astronomical dusk.
- :mod:`.moon`: the Moon's position, altitude and illuminated fraction.

All angles in degrees, azimuth east of north, times as Unix seconds (UTC). Every function of time
takes one time (a float: computed with ``math``, a few microseconds) or a numpy array of times (one
vectorised call instead of a loop); both run the same formula (:mod:`._math`).
"""

from nightcrew.astro.coords import (
    airmass,
    altaz_to_radec,
    altitudes,
    angular_separation,
    format_dec,
    format_ra,
    j2000_to_of_date,
    of_date_to_j2000,
    radec_to_altaz,
    separation,
)
from nightcrew.astro.moon import moon_altitude, moon_illumination, moon_radec
from nightcrew.astro.sun import (
    ASTRONOMICAL_TWILIGHT,
    astronomical_dusk,
    local_noon,
    sun_altaz,
    sun_altitude,
    sun_altitude_at,
    sun_crossing,
    sun_radec,
)
from nightcrew.astro.time import julian_date, julian_year, local_sidereal_time, modified_julian_date

__all__ = [
    "ASTRONOMICAL_TWILIGHT",
    "airmass",
    "altaz_to_radec",
    "altitudes",
    "angular_separation",
    "astronomical_dusk",
    "format_dec",
    "format_ra",
    "j2000_to_of_date",
    "julian_date",
    "julian_year",
    "local_noon",
    "local_sidereal_time",
    "modified_julian_date",
    "moon_altitude",
    "moon_illumination",
    "moon_radec",
    "of_date_to_j2000",
    "radec_to_altaz",
    "separation",
    "sun_altaz",
    "sun_altitude",
    "sun_altitude_at",
    "sun_crossing",
    "sun_radec",
]
