"""Early starts: a task may start before its slot when it can be observed from now on."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

from nightcrew.robotic.mastermind import (
    EarlyStarts,
    Wait,
    decide,
    observable_since,
    startable_from,
    startable_now,
)
from nightcrew.site import Site
from tests.robotic.test_mastermind_decide import EXPOSE, KEEP_OPEN, NIGHT, NOW, _at, _slot, _task

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0)
HIGH = {**EXPOSE, "target": {"name": "Capella", "ra": 79.17, "dec": 46.0}}
LOW = {**EXPOSE, "target": {"name": "south", "ra": 79.17, "dec": -30.0}}  # never above airmass 2
RISING = {**EXPOSE, "target": {"name": "rising", "ra": 135.0, "dec": 0.0}}  # airmass 2 at 22:17 (NOW 22:00)


def test_a_task_may_start_early_only_inside_its_window_with_its_target_observable() -> None:
    soon = NOW + timedelta(minutes=10)
    assert startable_now(_task([HIGH]), SITE, NOW, soon)
    assert not startable_now(_task([LOW]), SITE, NOW, soon)
    window_start = datetime(2024, 1, 15, 18, tzinfo=UTC)  # the tasks' window opens then
    before = window_start - timedelta(minutes=5)
    assert not startable_now(_task([HIGH]), SITE, before, window_start + timedelta(minutes=5))


def test_observable_since_finds_when_a_rising_target_comes_up() -> None:
    start = NOW + timedelta(minutes=30)
    lookback = timedelta(minutes=30)
    assert observable_since(_task([RISING]).request, SITE, start, lookback=lookback) == NOW + timedelta(
        minutes=17
    )
    assert observable_since(_task([HIGH]).request, SITE, start, lookback=lookback) == NOW
    assert observable_since(_task([LOW]).request, SITE, start, lookback=lookback) is None


def test_early_starts_mark_the_next_slot_as_startable_now_does_and_follow_new_plans_and_requests() -> None:
    early = EarlyStarts(SITE, timedelta(minutes=30))
    slot = _slot("7", 30, 60)  # _task's id is 7
    rising = {"7": _task([RISING])}
    minutes = (0, 10, 16, 17, 25)
    marked = [early.mark([slot], rising, NOW + timedelta(minutes=m))[0].startable_now for m in minutes]
    assert marked == [False, False, False, True, True]
    expected = [startable_now(rising["7"], SITE, NOW + timedelta(minutes=m), slot.start) for m in minutes]
    assert marked == expected
    later = NOW + timedelta(minutes=25)
    # The same task and slot with another target: asked again, not taken from before.
    assert not early.mark([slot], {"7": _task([LOW])}, later)[0].startable_now
    # A new plan moves the slot: its own answer.
    moved = _slot("7", 40, 70)
    assert early.mark([moved], rising, later)[0].startable_now
    assert not early.mark([moved], rising, NOW)[0].startable_now  # 40 min ahead: beyond early_start
    # Nothing is marked while a task is due, nor without early starts.
    due = _slot("due", 20, 40)  # due at 22:25
    assert early.mark([due, slot], rising, later) == [due, slot]
    assert not EarlyStarts(SITE, timedelta(0)).mark([slot], rising, later)[0].startable_now


def test_early_starts_mark_ahead_when_the_next_task_may_start_so_the_roof_stays_open_for_it() -> None:
    early = EarlyStarts(SITE, timedelta(minutes=30), keep_open=KEEP_OPEN)
    slot = _slot("7", 30, 60)
    rising = {"7": _task([RISING])}
    # Its target comes up at 22:17 (see above): the first minute startable_now says yes.
    since = startable_from(rising["7"].request, SITE, slot.start, lookback=early.early_start)
    assert since == NOW + timedelta(minutes=17)
    assert startable_now(rising["7"], SITE, since, slot.start)
    assert not startable_now(rising["7"], SITE, since - timedelta(minutes=1), slot.start)
    at_five = NOW + timedelta(minutes=5)
    marked = early.mark([slot], rising, at_five)[0]
    assert (marked.early_from, marked.startable_now) == (since, False)
    # The slot is 25 min ahead, the early start 12 min: the open roof waits for it.
    five = _at(NIGHT, now=at_five)
    assert decide(five, [marked], keep_open=KEEP_OPEN, early_start=early.early_start) == Wait(
        "next: 7 at 22:30:00", until=slot.start
    )
    # Never startable before its slot, or beyond early_start + keep_open: not marked.
    assert early.mark([slot], {"7": _task([LOW])}, at_five)[0].early_from is None
    assert early.mark([slot], rising, NOW - timedelta(minutes=16))[0].early_from is None
