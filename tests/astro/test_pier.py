"""German-equatorial geometry: pier side per hour angle, limits, collisions, the flip through the pole."""

from __future__ import annotations

import pytest

from nightcrew.astro import local_sidereal_time
from nightcrew.astro.pier import (
    SIDEREAL_RATE,
    GemLimits,
    counterweight_up,
    destination_side,
    hour_angle,
    limit_violation,
    mechanical_axes,
    seconds_until_limit,
)
from nightcrew.interfaces import PierSide
from nightcrew.sim.mount import axes_slew_time

LIMITS = GemLimits(east=-120.0, west=100.0, counterweight_up=15.0)
T = 1_705_356_000.0  # 2024-01-15T22:00Z


def test_a_slew_ends_with_the_counterweight_down_as_ascom_defines_the_sides() -> None:
    # ASCOM pierEast: the normal state, looking west of the meridian; pierWest looks east.
    assert destination_side(30.0) is PierSide.EAST
    assert destination_side(-30.0) is PierSide.WEST
    assert counterweight_up(30.0, PierSide.EAST) < 0 and counterweight_up(-30.0, PierSide.WEST) < 0
    with pytest.raises(ValueError, match="side unknown has no counterweight"):
        counterweight_up(0.0, PierSide.UNKNOWN)


def test_tracking_across_the_meridian_raises_the_counterweight_until_the_limit() -> None:
    assert counterweight_up(10.0, PierSide.WEST) == 10.0
    assert limit_violation(10.0, PierSide.WEST, LIMITS) is None
    assert limit_violation(16.0, PierSide.WEST, LIMITS) == (
        "counterweight 16.00° up on the west side of the pier, beyond the limit of 15°"
    )
    # After the flip the same hour angle is fine.
    assert limit_violation(16.0, PierSide.EAST, LIMITS) is None
    assert limit_violation(-16.0, PierSide.EAST, LIMITS) is not None


def test_hour_angle_limits_hold_on_both_sides() -> None:
    for side in (PierSide.EAST, PierSide.WEST):
        assert limit_violation(-121.0, side, LIMITS) == "hour angle -121.00° is east of the limit -120°"
    assert limit_violation(101.0, PierSide.EAST, LIMITS) == "hour angle 101.00° is west of the limit 100°"


def test_seconds_until_the_limit_follow_the_sidereal_rate() -> None:
    assert seconds_until_limit(-5.0, PierSide.WEST, LIMITS) == pytest.approx(20.0 / SIDEREAL_RATE)
    assert seconds_until_limit(5.0, PierSide.EAST, LIMITS) == pytest.approx(95.0 / SIDEREAL_RATE)
    assert seconds_until_limit(20.0, PierSide.WEST, LIMITS) == 0.0  # passed already


def test_a_flip_goes_through_the_pole_and_takes_the_time_of_its_longer_axis() -> None:
    before = mechanical_axes(5.0, 40.0, PierSide.WEST)
    after = mechanical_axes(5.0, 40.0, PierSide.EAST)
    assert after[0] - before[0] == -180.0  # the hour axis turns half round
    assert before[1] == 140.0 and after[1] == 40.0  # the dec axis crossed 90 (the pole)
    assert axes_slew_time(before, after, rate=4.0, settle_time=3.0) == pytest.approx(180.0 / 4.0 + 3.0)
    # In the south the dec axis goes through the south pole: 120° for a flip at -30°, not 240°.
    south = [mechanical_axes(5.0, -30.0, side, south=True) for side in (PierSide.WEST, PierSide.EAST)]
    assert abs(south[1][1] - south[0][1]) == 120.0
    # A short slew on one side takes only its own distance.
    near = mechanical_axes(8.0, 41.0, PierSide.EAST)
    assert axes_slew_time(after, near, rate=4.0) == pytest.approx(3.0 / 4.0)


def test_hour_angle_is_sidereal_time_minus_right_ascension() -> None:
    lst = local_sidereal_time(T, 10.0)
    # A star on the equator of date at RA = LST is on the meridian (precession moves J2000 a little).
    assert abs(hour_angle(lst, 0.0, 10.0, T)) < 0.5
    assert hour_angle((lst - 30.0) % 360.0, 0.0, 10.0, T) == pytest.approx(30.0, abs=0.5)
    later = hour_angle(lst, 0.0, 10.0, T + 3600.0) - hour_angle(lst, 0.0, 10.0, T)
    assert later == pytest.approx(3600.0 * SIDEREAL_RATE, rel=1e-6)


@pytest.mark.parametrize(
    ("limits", "message"),
    [
        ({"east": 10.0, "west": 5.0}, r"east must be east of \(less than\) west, got east 10° and west 5°"),
        (
            {"east": 10.0, "west": 50.0},
            r"east must be an hour angle east of the meridian \(-180..0\), got 10°",
        ),
        (
            {"east": -90.0, "west": -10.0},
            r"west must be an hour angle west of the meridian \(0..180\), got -10°",
        ),
        ({"counterweight_up": 95.0}, r"counterweight_up must be within 0..90 degrees, got 95°"),
        ({"west": float("nan")}, r"west must be a finite number of degrees, got nan"),
    ],
)
def test_limits_that_make_no_sense_are_refused(limits: dict[str, float], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        GemLimits(**limits)
