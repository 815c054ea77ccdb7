"""Why a block is left out of a plan: one test per reason."""

from __future__ import annotations

from datetime import timedelta

from nightcrew.astro import moon_radec
from nightcrew.robotic.scheduler import Constraints, Night, SchedulableBlock, Scheduler, Target
from tests.robotic.test_scheduler import CIRCUMPOLAR, NIGHT, QUICK, block, hours

SCHEDULER = Scheduler(time_limit_s=QUICK)


def why(blocks: list[SchedulableBlock], night: Night = NIGHT, **kwargs: object) -> dict[str, str]:
    schedule = SCHEDULER.schedule(blocks, night, **kwargs)  # type: ignore[arg-type]
    reasons = SCHEDULER.explain(blocks, night, schedule, names={"high": "M52 (high)"}, **kwargs)  # type: ignore[arg-type]
    print(reasons)
    return reasons


def test_a_planned_block_has_no_reason() -> None:
    assert why([block("fine")]) == {}


def test_a_target_that_never_rises_high_enough() -> None:
    reasons = why([block("south", target=Target(ra=0.0, dec=-60.0))])
    assert reasons["south"].startswith("never above the airmass limit: airmass never <= 2 in the night")


def test_the_moon_closer_than_the_limit_all_night() -> None:
    ra, dec = moon_radec(hours(6.5).timestamp())
    near = block(
        "near",
        target=Target(ra=float(ra), dec=float(dec)),
        constraints=Constraints(max_airmass=40.0, min_moon_distance=30.0),
    )
    assert why([near]) == {"near": "Moon closer than 30° all night (min_lunar_distance)"}


def test_a_window_outside_the_night() -> None:
    tomorrow = (hours(20), hours(21))
    reasons = why([block("later", windows=(tomorrow,))])
    assert reasons == {"later": "its windows lie outside the night (2024-01-15 17:00 - 06:00 UTC)"}


def test_longer_than_any_usable_gap() -> None:
    window = (hours(1), hours(2))
    reasons = why([block("long", duration_s=2 * 3600.0, windows=(window,))])
    assert reasons == {
        "long": "longer (125 min with set-up and slew) than any usable gap (the longest: 60 min)"
    }


def test_displaced_by_higher_priority_tasks_named() -> None:
    window = (hours(1), hours(2))
    high = block("high", priority=10.0, duration_s=3000.0, windows=(window,))
    low = block("low", priority=1.0, duration_s=3000.0, windows=(window,))
    assert why([high, low]) == {"low": "displaced by higher-priority tasks M52 (high)"}


def test_every_reason_that_applies_is_given() -> None:
    reasons = why([block("both", target=Target(ra=0.0, dec=-60.0), windows=((hours(20), hours(21)),))])
    assert reasons["both"].startswith("its windows lie outside the night (")
    assert "; never above the airmass limit" in reasons["both"]


def test_after_the_night_every_block_is_left_out_because_it_is_over() -> None:
    assert why([block("late")], now=NIGHT.end + timedelta(minutes=1)) == {"late": "the night is over"}
    assert CIRCUMPOLAR.dec == 80.0
