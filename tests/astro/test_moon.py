"""The Moon against astropy and at known phases."""

from __future__ import annotations

from datetime import UTC, datetime

import pytest

from nightcrew.astro import angular_separation, moon_altitude, moon_illumination, moon_radec, radec_to_altaz

TIMES = [1705356000.0, 1719792000.0, 1780000000.0]  # Jan 2024, Jul 2024, May 2026


@pytest.mark.parametrize("unix_time", TIMES)
def test_moon_is_within_half_a_degree_of_astropy(unix_time: float) -> None:
    from astropy.coordinates import get_body  # type: ignore[import-untyped]
    from astropy.time import Time  # type: ignore[import-untyped]

    moon = get_body("moon", Time(unix_time, format="unix"))  # geocentric (GCRS)
    assert angular_separation(*moon_radec(unix_time), moon.ra.deg, moon.dec.deg) < 0.5


def test_illumination_at_new_and_full_moon() -> None:
    new = datetime(2024, 1, 11, 11, 57, tzinfo=UTC).timestamp()
    full = datetime(2024, 1, 25, 17, 54, tzinfo=UTC).timestamp()
    assert moon_illumination(new) < 0.01
    assert moon_illumination(full) > 0.99
    assert 0.3 < moon_illumination((new + full) / 2) < 0.7


def test_moon_altitude_is_its_position_seen_from_the_site() -> None:
    t = TIMES[0]
    assert moon_altitude(51.56, 9.94, t) == radec_to_altaz(*moon_radec(t), 51.56, 9.94, t)[0]
