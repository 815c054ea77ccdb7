"""The Moon against astropy (geocentric and seen from a site) and at known phases."""

from __future__ import annotations

from datetime import UTC, datetime

import numpy as np
import pytest

from nightcrew.astro import angular_separation, moon_altitude, moon_illumination, moon_radec, radec_to_altaz
from nightcrew.site import Site

TIMES = [1705356000.0, 1719792000.0, 1780000000.0]  # Jan 2024, Jul 2024, May 2026
#: A high southern site: the parallax is largest for a low Moon, and the elevation counts.
SITE = Site(latitude=-30.17, longitude=-70.80, elevation=2200.0)


@pytest.mark.parametrize("unix_time", TIMES)
def test_the_geocentric_moon_is_within_a_hundredth_of_a_degree_of_astropy(unix_time: float) -> None:
    from astropy.coordinates import get_body  # type: ignore[import-untyped]
    from astropy.time import Time  # type: ignore[import-untyped]

    moon = get_body("moon", Time(unix_time, format="unix"))  # geocentric (GCRS)
    assert angular_separation(*moon_radec(unix_time), moon.ra.deg, moon.dec.deg) < 0.01


def test_the_moon_seen_from_the_site_is_within_a_hundredth_of_a_degree_of_astropy() -> None:
    from astropy import units  # type: ignore[import-untyped]
    from astropy.coordinates import EarthLocation, get_body
    from astropy.time import Time

    times = 1.7e9 + np.arange(0.0, 30 * 86400.0, 7.3 * 3600.0)  # a month, every phase and altitude
    where = EarthLocation.from_geodetic(
        SITE.longitude * units.deg, SITE.latitude * units.deg, SITE.elevation * units.m
    )
    moon = get_body("moon", Time(times, format="unix"), where)  # topocentric (GCRS at the site)
    ra, dec = moon_radec(times, SITE)
    assert np.max(angular_separation(ra, dec, moon.ra.deg, moon.dec.deg)) < 0.01
    # ... where the geocentric Moon is up to a degree away: the parallax matters.
    assert np.max(angular_separation(*moon_radec(times), ra, dec)) > 0.9


def test_illumination_at_new_and_full_moon() -> None:
    new = datetime(2024, 1, 11, 11, 57, tzinfo=UTC).timestamp()
    full = datetime(2024, 1, 25, 17, 54, tzinfo=UTC).timestamp()
    assert moon_illumination(new) < 0.01
    assert moon_illumination(full) > 0.99
    assert 0.3 < moon_illumination((new + full) / 2) < 0.7


def test_moon_altitude_is_its_position_seen_from_the_site() -> None:
    t = TIMES[0]
    site = Site(51.56, 9.94)
    assert moon_altitude(51.56, 9.94, t) == radec_to_altaz(*moon_radec(t, site), 51.56, 9.94, t)[0]
    assert isinstance(moon_altitude(51.56, 9.94, t), float)
