"""Julian date and sidereal time against their definitions and astropy."""

from __future__ import annotations

from datetime import UTC, datetime

import pytest

from nightcrew.astro import julian_date, local_sidereal_time
from nightcrew.astro.time import J2000


def test_julian_date_of_known_instants() -> None:
    assert julian_date(0.0) == 2440587.5  # 1970-01-01 00:00 UTC
    assert julian_date(datetime(2000, 1, 1, 12, tzinfo=UTC).timestamp()) == J2000


@pytest.mark.parametrize("unix_time", [946728000.0, 1705356000.0, 1780000000.0])
@pytest.mark.parametrize("longitude", [0.0, 9.94, -155.5])
def test_local_sidereal_time_matches_astropy(unix_time: float, longitude: float) -> None:
    from astropy.time import Time  # type: ignore[import-untyped]

    # astropy's mean sidereal time (IAU 2006, UT1); UT1-UTC < 0.9 s is 0.004°.
    expected = Time(unix_time, format="unix").sidereal_time("mean", longitude=longitude).deg
    difference = (local_sidereal_time(unix_time, longitude) - expected + 180.0) % 360.0 - 180.0
    assert abs(difference) < 0.005
