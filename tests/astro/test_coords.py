"""The fast coordinate functions agree with astropy to about an arcminute, and their array forms
with the single-position forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nightcrew.astro import (
    airmass,
    altaz_to_radec,
    altitudes,
    angular_separation,
    format_dec,
    format_ra,
    julian_date,
    radec_to_altaz,
    separation,
)
from nightcrew.astro.coords import precession_matrix

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
def test_precession_is_erfas_iau_1976(unix_time: float) -> None:
    import erfa  # type: ignore[import-untyped]

    # erfa takes TT; the ~69 s TT-UTC that nightcrew ignores turns the matrix by ~1e-10.
    expected = erfa.pmat76(julian_date(unix_time + 69.184), 0.0)
    assert np.abs(precession_matrix(unix_time) - expected).max() < 1e-8


def test_grid_altitudes_are_the_single_altitudes() -> None:
    ra, dec = (np.array(c, dtype=np.float64) for c in zip(*TARGETS, strict=True))
    times = 1705356000.0 + 1800.0 * np.arange(20, dtype=np.float64)  # a ten-hour night
    grid = altitudes(ra, dec, SITE[0], SITE[1], times)
    assert grid.shape == (len(TARGETS), len(times))
    for k, (r, d) in enumerate(TARGETS):
        single = [radec_to_altaz(r, d, SITE[0], SITE[1], float(t))[0] for t in times]
        # One precession at mid-night instead of one per time: < 0.1" over the night.
        np.testing.assert_allclose(grid[k], single, atol=0.1 / 3600)
    assert altitudes(ra[:0], dec[:0], SITE[0], SITE[1], times).shape == (0, len(times))


def test_separation_broadcasts_and_is_exact_at_tiny_and_large_angles() -> None:
    lon, lat = np.array([0.0, 10.0, 180.0]), np.array([0.0, -5.0, 1e-9])
    grid = separation(lon[:, np.newaxis], lat[:, np.newaxis], lon[np.newaxis, :], lat[np.newaxis, :])
    assert grid.shape == (3, 3)
    for i in range(3):
        for j in range(3):
            # The pair through math, the grid through numpy: equal to the last bits.
            assert grid[i, j] == pytest.approx(angular_separation(lon[i], lat[i], lon[j], lat[j]), abs=1e-12)
    assert math.isclose(angular_separation(0, 0, 90, 0), 90.0)
    assert angular_separation(0.0, 0.0, 0.0, 1e-9) == pytest.approx(1e-9, rel=1e-9)
    assert angular_separation(0.0, 0.0, 180.0, 1e-9) == pytest.approx(180.0 - 1e-9, abs=1e-12)


def test_airmass_and_sexagesimal() -> None:
    assert airmass(90.0) == pytest.approx(1.0, abs=1e-3)
    assert airmass(30.0) == pytest.approx(1.995, abs=0.01)
    assert airmass(0.0) is None
    assert format_ra(83.63308) == "05 34 31.94" and format_ra(359.99999999) == "00 00 00.00"
    assert format_dec(-22.01453) == "-22 00 52.3" and format_dec(0.5) == "+00 30 00.0"
