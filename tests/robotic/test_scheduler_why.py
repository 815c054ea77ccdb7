"""Why a block is left out of a plan (one test per reason), and the device faults' back-off."""

from __future__ import annotations

from datetime import timedelta

from nightcrew.astro import moon_radec
from nightcrew.robotic.scheduler import Constraints, Night, SchedulableBlock, Scheduler, Target
from nightcrew.robotic.scheduler.faults import DeviceFaults
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


def test_the_moon_too_bright_all_night() -> None:
    dark = block("dark", constraints=Constraints(max_moon_illumination=0.01))  # the Moon is ~25 % lit
    assert why([dark]) == {"dark": "Moon more than 0.01 illuminated all night (max_lunar_phase)"}


def test_constraints_that_hold_but_never_together() -> None:
    # M31 is high in a January evening and low before dawn; its window is before dawn: each of
    # the two holds at some time, never both.
    m31 = Target(ra=10.68, dec=41.27)
    reasons = why([block("m31", target=m31, windows=((hours(11), hours(12.5)),))])
    assert reasons == {"m31": "its constraints never hold at the same time in the night"}


def test_a_window_outside_the_night() -> None:
    tomorrow = (hours(20), hours(21))
    reasons = why([block("later", windows=(tomorrow,))])
    assert reasons == {"later": "its windows lie outside the night (2024-01-15 17:00 - 06:00 UTC)"}


def test_longer_than_any_usable_gap() -> None:
    window = (hours(1), hours(2))
    reasons = why([block("long", duration_s=2 * 3600.0, windows=(window,))])
    assert reasons == {
        "long": "longer (122 min with set-up and slew) than any usable gap (the longest: 60 min)"
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


def test_device_faults_back_off_doubling_then_give_up_and_are_forgotten_the_next_night() -> None:
    faults = DeviceFaults(backoff_s=300.0, limit=3)
    faults.start_night(NIGHT.end)
    assert faults.record("t", hours(1)) == hours(1) + timedelta(minutes=5)
    assert faults.record("t", hours(2)) == hours(2) + timedelta(minutes=10)
    (held,) = faults.hold_back([block("t")], NIGHT)
    assert held.windows == ((hours(2) + timedelta(minutes=10), NIGHT.end),)
    (untouched,) = faults.hold_back([block("u")], NIGHT)
    assert untouched.windows == ()
    assert faults.record("t", hours(3)) is None  # the third fault: given up
    faults.start_night(NIGHT.end + timedelta(seconds=30))  # the same night, planned later
    assert faults.counts == {"t": 3}
    faults.start_night(NIGHT.end + timedelta(days=1))
    assert faults.counts == {} and faults.record("t", hours(25)) == hours(25) + timedelta(minutes=5)
