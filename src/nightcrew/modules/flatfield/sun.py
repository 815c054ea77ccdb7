"""The Sun seen from the site, for the flat-field modules (one sun formula: the simulator's ephemeris)."""

from __future__ import annotations

from collections.abc import Callable

from nightcrew.modules.sim.ephemeris import sun_radec
from nightcrew.modules.telescope.coords import radec_to_altaz
from nightcrew.site import Site

__all__ = ["sun_altaz", "sun_altitude_at"]


def sun_altaz(site: Site, unix_time: float) -> tuple[float, float]:
    """(altitude, azimuth) of the Sun in degrees at ``unix_time``, azimuth east of north."""
    return radec_to_altaz(*sun_radec(unix_time), site.latitude, site.longitude, unix_time)


def sun_altitude_at(site: Site) -> Callable[[float], float]:
    """The Sun's altitude at ``site`` as a function of Unix time (what the twilight planner takes)."""
    return lambda unix_time: sun_altaz(site, unix_time)[0]
