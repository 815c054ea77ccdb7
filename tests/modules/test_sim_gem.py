"""SimTelescope as a German-equatorial mount: pier side, PIERSIDE card, limits, collisions, the flip."""

from __future__ import annotations

import logging

import pytest

from nightcrew.astro import local_sidereal_time
from nightcrew.astro.pier import SIDEREAL_RATE, hour_angle
from nightcrew.errors import ConfigError, MoveError
from nightcrew.interfaces import IPierSide, MotionStatus, PierSide
from nightcrew.modules.sim import SimTelescope
from nightcrew.testing import SITE, Observatory

GEM = {"east": -100.0, "west": 100.0, "counterweight_up": 10.0}
DEC = 30.0


def _ra_at(ha: float, unix_time: float) -> float:
    """The ICRS right ascension that stands at hour angle ``ha`` (dec :data:`DEC`) at the time."""
    ra = (local_sidereal_time(unix_time, SITE.longitude) - ha) % 360.0
    return (ra + hour_angle(ra, DEC, SITE.longitude, unix_time) - ha) % 360.0


async def _gem(observatory: Observatory, **kwargs: object) -> SimTelescope:
    telescope = await observatory.start(SimTelescope, "telescope", gem=GEM, settle_time=3.0, **kwargs)
    await telescope.init()
    return telescope


async def test_a_slew_ends_on_the_side_with_the_counterweight_down_and_headers_say_so(
    observatory: Observatory,
) -> None:
    telescope = await _gem(observatory)
    assert isinstance(telescope, IPierSide)
    now = observatory.clock.time()
    east_target, west_target = _ra_at(-30.0, now), _ra_at(30.0, now)
    assert await telescope.get_destination_pier_side(east_target, DEC) is PierSide.WEST
    assert await telescope.get_destination_pier_side(west_target, DEC) is PierSide.EAST
    await telescope.move_radec(east_target, DEC)
    assert await telescope.get_pier_side() is PierSide.WEST
    assert (await telescope.get_fits_header_before())["PIERSIDE"][0] == "WEST"
    await telescope.move_radec(_ra_at(30.0, observatory.clock.time()), DEC)
    assert await telescope.get_pier_side() is PierSide.EAST
    assert (await telescope.get_fits_header_before())["PIERSIDE"][0] == "EAST"


async def test_a_mount_without_gem_has_no_side_and_no_card(observatory: Observatory) -> None:
    telescope = await observatory.start(SimTelescope, "telescope")
    assert await telescope.get_pier_side() is PierSide.UNKNOWN
    assert await telescope.get_destination_pier_side(10.0, DEC) is PierSide.UNKNOWN
    assert "PIERSIDE" not in await telescope.get_fits_header_before()
    assert await telescope.get_pier_collisions() == []


async def test_tracking_past_the_counterweight_limit_is_a_collision_logged_at_error(
    observatory: Observatory, caplog: pytest.LogCaptureFixture
) -> None:
    telescope = await _gem(observatory)
    await telescope.move_radec(_ra_at(-5.0, observatory.clock.time()), DEC)
    ra, _ = await telescope.get_radec()
    tracking_from = observatory.clock.time()
    ha_then = hour_angle(ra, DEC, SITE.longitude, tracking_from)
    await observatory.clock.sleep(3600.0 * 1.5)  # 5° to the meridian, 10° beyond: 1 h; wait 1.5 h
    with caplog.at_level(logging.ERROR):
        collisions = await telescope.get_pier_collisions()
    assert len(collisions) == 1
    (collision,) = collisions
    assert collision.side is PierSide.WEST
    assert collision.hour_angle == pytest.approx(10.0, abs=1e-6)
    assert collision.time == pytest.approx(tracking_from + (10.0 - ha_then) / SIDEREAL_RATE, abs=1e-3)
    assert "counterweight 10.00° up on the west side of the pier, beyond the limit of 10°" in collision.reason
    assert "pier limit passed while tracking" in caplog.text
    assert len(await telescope.get_pier_collisions()) == 1  # recorded once


async def test_a_flip_is_a_slew_through_the_pole_and_avoids_the_collision(observatory: Observatory) -> None:
    telescope = await _gem(observatory, slew_rate=4.0)
    target = (_ra_at(-2.0, observatory.clock.time()), DEC)
    await telescope.move_radec(*target)
    assert await telescope.get_pier_side() is PierSide.WEST
    await observatory.clock.sleep(5.0 / SIDEREAL_RATE)  # now 3° past the meridian, counterweight up
    assert await telescope.get_destination_pier_side(*target) is PierSide.EAST
    start = observatory.clock.time()
    await telescope.move_radec(*target)  # the flip
    took = observatory.clock.time() - start
    assert 180.0 / 4.0 + 3.0 - 0.1 <= took < 180.0 / 4.0 + 3.0 + 5.0  # the hour axis turns half round
    assert await telescope.get_pier_side() is PierSide.EAST
    assert await telescope.get_motion_status() is MotionStatus.TRACKING
    await observatory.clock.sleep(3 * 3600.0)  # far past where the west side would have hit the pier
    assert await telescope.get_pier_collisions() == []


async def test_a_target_beyond_the_hour_angle_limits_is_refused_before_anything_moves(
    observatory: Observatory,
) -> None:
    telescope = await _gem(observatory)
    before = await telescope.get_altaz()
    with pytest.raises(
        MoveError, match=r"beyond the mount's limits: hour angle -1\d\d\.\d\d° is east of the limit -100°"
    ):
        await telescope.move_radec(_ra_at(-110.0, observatory.clock.time()), 60.0)
    assert await telescope.get_altaz() == pytest.approx(before)
    assert await telescope.get_motion_status() is MotionStatus.IDLE


@pytest.mark.parametrize(
    ("gem", "message"),
    [
        ({"east": 20.0, "west": 10.0}, r"key 'gem.east': east must be east of \(less than\) west"),
        ({"counterweight_up": -1.0}, r"key 'gem.counterweight_up': counterweight_up must be within 0..90"),
        (
            {"east": -90.0, "flip": 3.0},
            r"key 'gem': unknown limit\(s\) flip; known: east, west, counterweight_up",
        ),
    ],
)
def test_gem_limits_that_make_no_sense_are_one_config_error(gem: dict[str, float], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        SimTelescope(name="telescope", site={"latitude": 50, "longitude": 10}, gem=gem)
