"""Julian date and sidereal time against their definitions and astropy."""

from __future__ import annotations

from datetime import UTC, datetime

import numpy as np
import pytest

from nightcrew.astro import julian_date, julian_year, local_sidereal_time, modified_julian_date
from nightcrew.astro.time import J2000


def test_julian_date_of_known_instants() -> None:
    assert julian_date(0.0) == 2440587.5  # 1970-01-01 00:00 UTC
    assert julian_date(datetime(2000, 1, 1, 12, tzinfo=UTC).timestamp()) == J2000
    assert modified_julian_date(0.0) == 40587.0
    assert julian_year(datetime(2000, 1, 1, 12, tzinfo=UTC).timestamp()) == 2000.0


@pytest.mark.parametrize("unix_time", [946728000.0, 1705356123.456, 1780000000.0])
def test_modified_julian_date_and_julian_year_match_astropy(unix_time: float) -> None:
    from astropy.time import Time  # type: ignore[import-untyped]

    t = Time(unix_time, format="unix", scale="utc")
    assert modified_julian_date(unix_time) == pytest.approx(t.utc.mjd, abs=1e-9)  # 0.1 ms
    # Julian years count TT: the ignored TT-UTC (~69 s) is 2e-6 yr.
    assert julian_year(unix_time) == pytest.approx(t.tt.jyear, abs=3e-6)


def test_arrays_of_times_give_the_single_values() -> None:
    times = 1705356000.0 + 3600.0 * np.arange(5.0)
    for function in (julian_date, modified_julian_date, julian_year):
        assert list(function(times)) == [function(float(t)) for t in times]
    assert list(local_sidereal_time(times, 9.94)) == [local_sidereal_time(float(t), 9.94) for t in times]


@pytest.mark.parametrize("unix_time", [946728000.0, 1705356000.0, 1780000000.0])
@pytest.mark.parametrize("longitude", [0.0, 9.94, -155.5])
def test_local_sidereal_time_matches_astropy(unix_time: float, longitude: float) -> None:
    from astropy.time import Time

    # astropy's mean sidereal time (IAU 2006, UT1); UT1-UTC < 0.9 s is 0.004°.
    expected = Time(unix_time, format="unix").sidereal_time("mean", longitude=longitude).deg
    difference = (local_sidereal_time(unix_time, longitude) - expected + 180.0) % 360.0 - 180.0
    assert abs(difference) < 0.005
