"""The Moon limit is judged on the Moon seen from the site, not from the Earth's centre."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

import numpy as np

from nightcrew.astro import moon_radec, separation
from nightcrew.astro._math import ARRAY
from nightcrew.astro.coords import from_unit_vector, unit_vector
from nightcrew.robotic.scheduler import Constraints, Night, SchedulableBlock, Scheduler, Target
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
#: A waxing gibbous Moon high in the south: its parallax (~0.4°) pulls it towards the horizon.
MIDDLE = datetime(2024, 1, 20, 20, 0, tzinfo=UTC)
NIGHT = Night(datetime(2024, 1, 20, 17, 0, tzinfo=UTC), datetime(2024, 1, 21, 6, 0, tzinfo=UTC), SITE)


def _beyond(start: tuple[float, float], through: tuple[float, float], degrees: float) -> Target:
    """The point ``degrees`` past ``through`` on the great circle from ``start`` through it."""
    a = np.array(unit_vector(np.array(start[0]), np.array(start[1]), ARRAY))
    b = np.array(unit_vector(np.array(through[0]), np.array(through[1]), ARRAY))
    axis = np.cross(a, b)
    axis /= np.linalg.norm(axis)
    angle = np.radians(degrees)
    turned = b * np.cos(angle) + np.cross(axis, b) * np.sin(angle)  # b turned on, away from a
    ra, dec = from_unit_vector((turned[0], turned[1], turned[2]), ARRAY)
    return Target(float(ra), float(dec))


def test_a_block_breaking_its_moon_limit_by_a_tenth_of_a_degree_seen_from_the_site_is_refused() -> None:
    t = MIDDLE.timestamp()
    geocentric, seen = moon_radec(t), moon_radec(t, SITE)
    target = _beyond(geocentric, seen, 29.9)
    edges = np.array([t - 300.0, t, t + 300.0])
    from_centre = separation(target.ra, target.dec, *moon_radec(edges))
    from_site = separation(target.ra, target.dec, *moon_radec(edges, SITE))
    assert np.all(from_centre > 30.2)  # the geocentric Moon would allow it all along ...
    assert np.all((from_site < 30.0) & (from_site > 29.8))  # ... it breaks 30° by ~0.1°
    window = ((MIDDLE - timedelta(minutes=5), MIDDLE + timedelta(minutes=5)),)

    def block(limit: float) -> SchedulableBlock:
        constraints = Constraints(max_airmass=3.0, min_moon_distance=limit)
        return SchedulableBlock("near-moon", 1.0, 480.0, target, constraints, window)

    scheduler = Scheduler(slew_overhead_s=0.0)
    assert scheduler.schedule([block(30.0)], NIGHT).slots == ()
    assert [s.task_id for s in scheduler.schedule([block(29.7)], NIGHT).slots] == ["near-moon"]
