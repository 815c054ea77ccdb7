"""Moved to :mod:`nightcrew.astro`; this name goes once its last users are updated."""

from nightcrew.astro.coords import *  # noqa: F403
from nightcrew.astro.moon import moon_radec as moon_radec
from nightcrew.astro.time import julian_date as julian_date
from nightcrew.astro.time import local_sidereal_time as local_sidereal_time
