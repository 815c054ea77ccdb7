"""Moved to :mod:`nightcrew.astro`; this name goes once its last users are updated."""

from nightcrew.astro.moon import moon_altitude as moon_altitude
from nightcrew.astro.moon import moon_illumination as moon_illumination
from nightcrew.astro.sun import *  # noqa: F403
