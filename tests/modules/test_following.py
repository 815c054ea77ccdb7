"""Non-sidereal tracking (nightcrew.modules.telescope.following) on the simulated mount."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from nightcrew.astro import angular_separation
from nightcrew.astro.ephemeris import ephemeris
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.sim import SimTelescope
from nightcrew.modules.telescope.following import (
    MAX_INTERVAL_S,
    MIN_INTERVAL_S,
    aim_rates,
    follow_interval,
    parse_moving_target,
)
from nightcrew.testing import Observatory

#: The night of docs/tasks.md's moving-target examples.
EPOCH = "2026-11-10T22:00:00+00:00"
ASTEROID: dict[str, Any] = {
    "type": "ORBITAL_ELEMENTS",
    "scheme": "MPC_MINOR_PLANET",
    "name": "(example) 2026 XA",
    "epochofel": 61354.0,
    "orbinc": 6.0,
    "longascnode": 20.0,
    "argofperih": 10.0,
    "eccentricity": 0.12,
    "meandist": 2.4,
    "meananom": 20.0,
}
SATELLITE: dict[str, Any] = {
    "type": "SATELLITE",
    "name": "example satellite",
    "tle_line1": "1 25544U 98067A   26314.50000000  .00009878  00000-0  18200-3 0  5083",
    "tle_line2": "2 25544  51.6498 270.0000 0003572  55.9686 274.8005 15.49815350868470",
}
STAR = (56.75, 24.12)  # the Pleiades


def error_arcsec(telescope: SimTelescope, radec: tuple[float, float], body: Any) -> float:
    expected = ephemeris(body, telescope.observatory, telescope.clock.time())
    return float(angular_separation(radec[0], radec[1], float(expected.ra[0]), float(expected.dec[0]))) * 3600


def test_updates_come_as_often_as_the_error_limit_needs() -> None:
    # By position updates: 1" at 0.001"/s is 1000 s, capped at 5 min; 1" at 10"/s is 0.1 s, floored at 2 Hz.
    assert follow_interval(0.001, 0.0, 1.0, by_rates=False, satellite=False) == MAX_INTERVAL_S
    assert follow_interval(0.5, 0.0, 1.0, by_rates=False, satellite=False) == 2.0
    assert follow_interval(10.0, 0.0, 1.0, by_rates=False, satellite=False) == MIN_INTERVAL_S
    # By rates: only the path's curvature counts; 0.5 * a * t² = 1" at a = 0.02"/s² is 10 s.
    assert follow_interval(10.0, 0.02, 1.0, by_rates=True, satellite=False) == pytest.approx(10.0)
    assert follow_interval(0.01, 1e-9, 1.0, by_rates=True, satellite=True) == MIN_INTERVAL_S
    assert aim_rates((359.99, 10.0), (0.01, 10.001), 10.0) == pytest.approx((7.2, 0.36))


def test_a_bad_moving_target_names_its_field() -> None:
    with pytest.raises(
        InvalidArgumentError, match=r"^target.tle_line2: checksum is '1', the line's digits give 0$"
    ):
        parse_moving_target(SATELLITE | {"tle_line2": SATELLITE["tle_line2"][:68] + "1"})
    with pytest.raises(InvalidArgumentError, match=r"^target.type: must be one of"):
        parse_moving_target({"type": "STAR", "name": "x"})


async def test_the_simulated_mount_follows_an_asteroid_by_rates() -> None:
    async with Observatory(epoch=EPOCH) as observatory:
        telescope = await observatory.start(SimTelescope, "telescope", drift_rate=0.0, periodic_amplitude=0.0)
        await telescope.init()
        await telescope.move_ephemeris(ASTEROID)
        body, _ = parse_moving_target(ASTEROID)
        assert await telescope.get_motion_status() is MotionStatus.TRACKING
        for _ in range(2):
            await observatory.clock.sleep(900.0)
            assert error_arcsec(telescope, await telescope.get_radec(), body) < 1.0
        header = await telescope.get_fits_header_before()
        expected = ephemeris(body, telescope.observatory, observatory.clock.time())
        assert header["MOVOBJ"][0] == "(example) 2026 XA"
        assert header["EPH-RA"][0] == pytest.approx(expected.ra[0], abs=1e-6)
        assert header["EPH-RAR"][0] == pytest.approx(expected.ra_rate[0], abs=1e-5)
        assert header["EPH-DECR"][0] == pytest.approx(expected.dec_rate[0], abs=1e-5)
        ra_rate, dec_rate = await telescope.get_tracking_rates()
        expected = ephemeris(body, telescope.observatory, observatory.clock.time())
        cos_dec = np.cos(np.radians(expected.dec[0]))
        assert ra_rate * cos_dec == pytest.approx(expected.ra_rate[0], abs=0.002)
        assert dec_rate == pytest.approx(expected.dec_rate[0], abs=0.002)
        await telescope.move_radec(*STAR)  # anything else ends the following: sidereal again
        assert await telescope.get_tracking_rates() == (0.0, 0.0)
        assert "MOVOBJ" not in await telescope.get_fits_header_before()
        before = await telescope.get_radec()
        await observatory.clock.sleep(600.0)
        assert await telescope.get_radec() == pytest.approx(before)


async def test_a_satellite_pass_is_followed_at_two_hertz_within_a_few_arcseconds() -> None:
    async with Observatory(epoch="2026-11-10T18:38:00+00:00") as observatory:
        telescope = await observatory.start(SimTelescope, "telescope", drift_rate=0.0, periodic_amplitude=0.0)
        await telescope.init()
        await telescope.move_ephemeris(SATELLITE)
        body, _ = parse_moving_target(SATELLITE)
        errors = []
        for _ in range(80):
            await observatory.clock.sleep(0.77)  # between the updates, not on them
            errors.append(error_arcsec(telescope, await telescope.get_radec(), body))
        rms = float(np.sqrt(np.mean(np.square(errors))))
        print(f"satellite: RMS error {rms:.2f} arcsec over a minute")
        assert rms < 30.0
        await telescope.park()
        assert await telescope.get_tracking_rates() == (0.0, 0.0)
