"""The fast coordinate functions agree with astropy to about an arcminute."""

from __future__ import annotations

import math

import pytest

from nightcrew.errors import ConfigError
from nightcrew.interfaces import FitsValue
from nightcrew.modules.telescope.coords import (
    airmass,
    altaz_to_radec,
    angular_separation,
    format_dec,
    format_ra,
    moon_radec,
    radec_to_altaz,
)
from nightcrew.vfs.filenames import check_filename_pattern, format_filename

SITE = (51.56, 9.94, 201.0)
TIMES = [1705356000.0, 1719792000.0, 1780000000.0]  # Jan 2024, Jul 2024, May 2026
TARGETS = [(10.0, 20.0), (200.0, -30.0), (83.6, 22.0), (300.0, 60.0), (37.95, 89.26)]


@pytest.mark.parametrize("unix_time", TIMES)
def test_radec_to_altaz_matches_astropy(unix_time: float) -> None:
    import astropy.units as u  # type: ignore[import-untyped]
    from astropy.coordinates import AltAz, EarthLocation, SkyCoord  # type: ignore[import-untyped]
    from astropy.time import Time  # type: ignore[import-untyped]

    location = EarthLocation(lat=SITE[0] * u.deg, lon=SITE[1] * u.deg, height=SITE[2] * u.m)
    frame = AltAz(obstime=Time(unix_time, format="unix"), location=location)
    for ra, dec in TARGETS:
        expected = SkyCoord(ra * u.deg, dec * u.deg).transform_to(frame)
        alt, az = radec_to_altaz(ra, dec, SITE[0], SITE[1], unix_time)
        assert angular_separation(az, alt, expected.az.deg, expected.alt.deg) < 1.0 / 60.0


@pytest.mark.parametrize("unix_time", TIMES)
def test_altaz_to_radec_inverts_radec_to_altaz(unix_time: float) -> None:
    for ra, dec in TARGETS:
        back = altaz_to_radec(
            *radec_to_altaz(ra, dec, SITE[0], SITE[1], unix_time), SITE[0], SITE[1], unix_time
        )
        assert angular_separation(ra, dec, *back) < 1e-8


@pytest.mark.parametrize("unix_time", TIMES)
def test_moon_is_within_half_a_degree_of_astropy(unix_time: float) -> None:
    from astropy.coordinates import get_body
    from astropy.time import Time

    moon = get_body("moon", Time(unix_time, format="unix"))  # geocentric (GCRS)
    assert angular_separation(*moon_radec(unix_time), moon.ra.deg, moon.dec.deg) < 0.5


def test_airmass_and_sexagesimal() -> None:
    assert airmass(90.0) == pytest.approx(1.0, abs=1e-3)
    assert airmass(30.0) == pytest.approx(1.995, abs=0.01)
    assert airmass(0.0) is None
    assert format_ra(83.63308) == "05 34 31.94" and format_ra(359.99999999) == "00 00 00.00"
    assert format_dec(-22.01453) == "-22 00 52.3" and format_dec(0.5) == "+00 30 00.0"
    assert math.isclose(angular_separation(0, 0, 90, 0), 90.0)


def test_filename_pattern_is_checked_and_values_cannot_escape() -> None:
    with pytest.raises(ConfigError, match="must be an absolute VFS file path"):
        check_filename_pattern("cache/{DATE-OBS}.fits")
    with pytest.raises(ConfigError, match=r"placeholder \{date\} .* is not a FITS keyword"):
        check_filename_pattern("/cache/{date}.fits")
    header: dict[str, FitsValue] = {"OBJECT": "../../etc/passwd", "FILTER": "..", "FOCUS": 25.123456}
    assert format_filename("/cache/{OBJECT}-{FILTER}-{FOCUS:.2f}-{MISSING}.fits", header) == (
        "/cache/etc-passwd-_-25.12-none.fits"
    )
