"""Moved to :mod:`nightcrew.astro`; this name goes once its last users are updated."""

from nightcrew.astro.sun import sun_altaz as sun_altaz
from nightcrew.astro.sun import sun_altitude_at as sun_altitude_at
