"""The Sun: its position against astropy, its crossings of an altitude and astronomical dusk."""

from __future__ import annotations

from datetime import UTC, date, datetime

import pytest

from nightcrew.astro import (
    ASTRONOMICAL_TWILIGHT,
    angular_separation,
    astronomical_dusk,
    local_noon,
    sun_altaz,
    sun_altitude,
    sun_altitude_at,
    sun_crossing,
    sun_radec,
)
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0)
TIMES = [1705356000.0, 1719792000.0, 1780000000.0]  # Jan 2024, Jul 2024, May 2026


@pytest.mark.parametrize("unix_time", TIMES)
def test_sun_is_within_a_hundredth_of_a_degree_of_astropy(unix_time: float) -> None:
    from astropy.coordinates import get_body  # type: ignore[import-untyped]
    from astropy.time import Time  # type: ignore[import-untyped]

    expected = get_body("sun", Time(unix_time, format="unix"))  # GCRS: J2000 axes, from the Earth
    assert angular_separation(*sun_radec(unix_time), expected.ra.deg, expected.dec.deg) < 0.01


@pytest.mark.parametrize("unix_time", TIMES)
def test_sun_altitude_is_within_two_hundredths_of_a_degree_of_astropy(unix_time: float) -> None:
    # Precessing the position twice (of date taken for J2000) put it ~0.36° off in 2026.
    import astropy.units as u  # type: ignore[import-untyped]
    from astropy.coordinates import AltAz, EarthLocation, get_body
    from astropy.time import Time
    from astropy.utils import iers  # type: ignore[import-untyped]

    t = Time(unix_time, format="unix")
    lon, lat, height = SITE.longitude * u.deg, SITE.latitude * u.deg, SITE.elevation * u.m
    location = EarthLocation.from_geodetic(lon, lat, height)
    with iers.conf.set_temp("auto_download", False), iers.conf.set_temp("iers_degraded_accuracy", "ignore"):
        expected = get_body("sun", t, location).transform_to(AltAz(obstime=t, location=location))
    alt, az = sun_altaz(SITE, unix_time)
    assert abs(alt - expected.alt.deg) < 0.02
    assert abs((az - expected.az.deg + 180.0) % 360.0 - 180.0) < 0.03


def test_the_site_forms_agree() -> None:
    t = TIMES[0]
    alt, az = sun_altaz(SITE, t)
    assert alt == sun_altitude(SITE.latitude, SITE.longitude, t, SITE.elevation) == sun_altitude_at(SITE)(t)
    assert 0.0 <= az < 360.0


def test_local_noon_is_when_the_sun_culminates() -> None:
    night = date(2026, 11, 10)
    noon = local_noon(night, SITE.longitude)
    assert noon == datetime(2026, 11, 10, 12, tzinfo=UTC).timestamp() - SITE.longitude / 15.0 * 3600
    # Mean, not true, noon: the equation of time (here about +16 min) shifts the culmination.
    around = [noon + minutes * 60.0 for minutes in range(-40, 41)]
    culmination = max(around, key=lambda t: sun_altitude(SITE.latitude, SITE.longitude, t))
    assert abs(culmination - noon) < 20 * 60


@pytest.mark.parametrize("rising", [False, True])
@pytest.mark.parametrize("altitude", [-3.0, -12.0, -18.0])
def test_a_crossing_is_the_first_second_beyond_the_altitude(rising: bool, altitude: float) -> None:
    noon = local_noon(date(2026, 11, 10), SITE.longitude)
    t = sun_crossing(SITE, noon, altitude, rising=rising)
    assert noon < t < noon + 86400.0
    before, at = (sun_altitude(SITE.latitude, SITE.longitude, x) for x in (t - 1.0, t))
    if rising:
        assert before <= altitude < at
    else:
        assert at <= altitude < before
    # From the near side of another crossing the search starts by getting past it.
    assert sun_crossing(SITE, t, altitude, rising=rising) > t + 12 * 3600


def test_no_crossing_in_the_polar_night() -> None:
    arctic = Site(latitude=78.2, longitude=15.6)
    noon = local_noon(date(2026, 12, 21), arctic.longitude)
    with pytest.raises(ValueError, match=r"the Sun does not cross -3.0° within 24 h"):
        sun_crossing(arctic, noon, -3.0, rising=False)


def test_astronomical_dusk_is_the_evening_crossing_of_minus_18() -> None:
    night = date(2026, 11, 10)
    dusk = astronomical_dusk(night, SITE)
    assert dusk == sun_crossing(SITE, local_noon(night, SITE.longitude), ASTRONOMICAL_TWILIGHT, rising=False)
    assert (
        datetime(2026, 11, 10, 17, tzinfo=UTC).timestamp()
        < dusk
        < datetime(2026, 11, 10, 18, tzinfo=UTC).timestamp()
    )


def test_astronomical_dusk_fails_without_an_astronomical_night() -> None:
    with pytest.raises(ValueError, match=r"no astronomical night on 2026-06-21 at latitude 51.56"):
        astronomical_dusk(date(2026, 6, 21), SITE)
    with pytest.raises(ValueError, match=r"the Sun stays below -18.0° on 2026-12-21 at latitude 85.0"):
        astronomical_dusk(date(2026, 12, 21), Site(latitude=85.0, longitude=0.0))
