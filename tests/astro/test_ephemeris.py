"""Moving targets' ephemerides (nightcrew.astro.ephemeris) and their orbits' formats (.elements).

Fictitious bodies with realistic orbits for the night of 2026-11-10 at the simulated site (the same
as docs/tasks.md's examples): an asteroid near opposition, a comet before perihelion, a satellite
in a low orbit whose passes rise above 30° in the night.
"""

from __future__ import annotations

import math
from datetime import UTC, datetime

import numpy as np
import pytest

from nightcrew.astro import separation
from nightcrew.astro.elements import (
    ElementsError,
    KeplerElements,
    MajorBody,
    TwoLineElements,
    elements_from_mean_anomaly,
    parse_mpc_line,
    tle_checksum,
)
from nightcrew.astro.ephemeris import ephemeris, position_at
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
NIGHT = datetime(2026, 11, 10, 22, 0, tzinfo=UTC).timestamp()
ASTEROID_LINE = (
    "K26X00A 15.20  0.15 K26BA  20.00000   10.00000   20.00000    6.00000  0.1200000  0.26508626"
    "   2.4000000  0 MPO000000    12   1    3 days 0.40 M-v 3Eh MPCLINUX   0000 (example) 2026 XA"
    "           20261101"
)
COMET_LINE = (
    "    C2026X1   2026 12  6.0000  1.100000  0.950000  150.0000  250.0000   35.0000  20261110"
    "   9.0  4.0  C/2026 X1 (example)"
)
TLE_LINE1 = "1 25544U 98067A   26314.50000000  .00009878  00000-0  18200-3 0  5083"
TLE_LINE2 = "2 25544  51.6498 270.0000 0003572  55.9686 274.8005 15.49815350868470"
ARCSEC = 1 / 3600


def test_an_mpcorb_line_gives_the_same_orbit_as_its_elements() -> None:
    from_line = parse_mpc_line(ASTEROID_LINE)
    from_fields = elements_from_mean_anomaly(
        "(example) 2026 XA",
        semimajor_axis_au=2.4,
        eccentricity=0.12,
        inclination=6.0,
        longitude_of_ascending_node=20.0,
        argument_of_perihelion=10.0,
        mean_anomaly=20.0,
        epoch_jd=2461354.5,  # 2026-11-10.0 TT
    )
    assert from_line.name == "(example) 2026 XA"
    assert from_line.epoch_jd == from_fields.epoch_jd
    a = position_at(from_line, SITE, NIGHT)
    b = position_at(from_fields, SITE, NIGHT)
    assert separation(a[0], a[1], b[0], b[1]) < 0.1 * ARCSEC


def test_a_comet_line_is_read_in_perihelion_form() -> None:
    comet = parse_mpc_line(COMET_LINE)
    assert comet == KeplerElements(
        name="C/2026 X1 (example)",
        perihelion_distance_au=1.1,
        eccentricity=0.95,
        inclination=35.0,
        longitude_of_ascending_node=250.0,
        argument_of_perihelion=150.0,
        perihelion_time_jd=2461380.5,
        epoch_jd=2461354.5,
    )


def test_keplerian_elements_of_mars_follow_de421_to_a_few_arcminutes() -> None:
    # Standish's mean elements of Mars at J2000 (JPL's "Keplerian elements for approximate
    # positions"): a check of the two-body path against the kernel, an independent source.
    mars = elements_from_mean_anomaly(
        "Mars (mean elements)",
        semimajor_axis_au=1.52371034,
        eccentricity=0.09339410,
        inclination=1.84969142,
        longitude_of_ascending_node=49.55953891,
        argument_of_perihelion=-23.94362959 - 49.55953891,
        mean_anomaly=-4.55343205 + 23.94362959,
        epoch_jd=2451545.0,
    )
    when = datetime(2000, 1, 20, tzinfo=UTC).timestamp()
    kepler = position_at(mars, SITE, when)
    kernel = position_at(MajorBody("mars"), SITE, when)
    assert separation(kepler[0], kepler[1], kernel[0], kernel[1]) < 0.05


def test_rates_are_the_motion_on_the_sky_per_second() -> None:
    asteroid = parse_mpc_line(ASTEROID_LINE)
    times = NIGHT + np.array([0.0, 600.0])
    found = ephemeris(asteroid, SITE, times)
    d_ra = (found.ra[1] - found.ra[0]) * math.cos(math.radians(found.dec[0])) * 3600 / 600
    d_dec = (found.dec[1] - found.dec[0]) * 3600 / 600
    assert found.ra_rate[0] == pytest.approx(d_ra, rel=0.01)
    assert found.dec_rate[0] == pytest.approx(d_dec, abs=1e-4)
    assert 0.005 < found.rate[0] < 0.02  # a main-belt asteroid at opposition: ~0.6"/min
    assert found.altitude[0] > 50


def test_a_satellite_pass_rises_and_sets_within_minutes() -> None:
    satellite = TwoLineElements("example satellite", TLE_LINE1, TLE_LINE2)
    pass_start = datetime(2026, 11, 10, 18, 37, 40, tzinfo=UTC).timestamp()
    found = ephemeris(satellite, SITE, pass_start + np.arange(0.0, 180.0, 10.0))
    assert found.altitude.max() > 30 > found.altitude.min() - 1
    assert found.rate.max() > 1000  # arcseconds per second: a low orbit near culmination
    assert np.all(found.distance_km < 2000)


def test_a_tle_with_a_wrong_checksum_is_refused_naming_the_line() -> None:
    broken = TLE_LINE2[:68] + str((tle_checksum(TLE_LINE2) + 1) % 10)
    with pytest.raises(ElementsError, match=r"^line2: checksum is '1', the line's digits give 0$"):
        TwoLineElements("x", TLE_LINE1, broken)


def test_elliptical_elements_need_an_eccentricity_below_one() -> None:
    with pytest.raises(ElementsError, match=r"^eccentricity: must be >= 0 and < 1"):
        elements_from_mean_anomaly(
            "x",
            semimajor_axis_au=2.0,
            eccentricity=1.2,
            inclination=1.0,
            longitude_of_ascending_node=0.0,
            argument_of_perihelion=0.0,
            mean_anomaly=0.0,
            epoch_jd=2461354.5,
        )


def test_a_garbled_mpc_line_names_the_columns() -> None:
    garbled = ASTEROID_LINE[:70] + "0.12x0000" + ASTEROID_LINE[79:]
    with pytest.raises(ElementsError, match=r"^line: eccentricity \(columns 71-79\) is not a number"):
        parse_mpc_line(garbled)
