"""The mastermind's pure decisions: what to do next, when a running task must stop, task helpers."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from typing import Any

import pytest

from nightcrew.interfaces import MotionStatus
from nightcrew.robotic.mastermind import (
    CloseAndPark,
    Conditions,
    Focus,
    OpenUp,
    RoofState,
    RunTask,
    Slot,
    SunLimits,
    Wait,
    abort_cause,
    decide,
    focus_due,
    interruption_reason,
    kept_progress,
    needs_focus,
    needs_sky,
    slot_for,
    sun_limits,
    task_cards,
)
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import (
    CutShortFrame,
    Task,
    TaskProgress,
    TaskState,
    TaskStatus,
    parse_request_group,
    tasks_of_group,
)

NOW = datetime(2024, 1, 15, 22, tzinfo=UTC)
KEEP_OPEN = timedelta(minutes=15)
NIGHT = Conditions(
    now=NOW,
    sun_altitude=-40.0,
    sun_rising=False,
    weather_good=True,
    roof=RoofState.OPEN,
    telescope_ready=True,
)
SAFE = Conditions(
    now=NOW,
    sun_altitude=-40.0,
    sun_rising=False,
    weather_good=True,
    roof=RoofState.CLOSED,
    telescope_ready=False,
)


def _slot(name: str, start_min: float, end_min: float, *, sky: bool = True, **kwargs: Any) -> Slot:
    kwargs.setdefault("sun", SunLimits(high=-12.0))
    return Slot(
        planned=PlannedSlot(name, NOW + timedelta(minutes=start_min), NOW + timedelta(minutes=end_min)),
        name=name,
        needs_sky=sky,
        **kwargs,
    )


def _at(conditions: Conditions, **changes: Any) -> Conditions:
    values = {**vars(conditions), **changes}
    return Conditions(**values)


# --- decide ------------------------------------------------------------------------------------


def test_a_due_sky_task_runs_when_everything_is_ready() -> None:
    slot = _slot("m31", -5, 30)
    assert decide(NIGHT, [slot, _slot("m33", 30, 60)], keep_open=KEEP_OPEN) == RunTask(slot)


def test_a_due_sky_task_first_opens_up_and_waits_for_a_roof_someone_else_moves() -> None:
    slot = _slot("m31", 0, 30)
    assert decide(SAFE, [slot], keep_open=KEEP_OPEN) == OpenUp(slot)
    assert decide(_at(NIGHT, telescope_ready=False), [slot], keep_open=KEEP_OPEN) == OpenUp(slot)
    assert decide(_at(NIGHT, roof=RoofState.UNKNOWN), [slot], keep_open=KEEP_OPEN) == OpenUp(slot)
    for moving in (RoofState.OPENING, RoofState.CLOSING):
        assert decide(_at(NIGHT, roof=moving), [slot], keep_open=KEEP_OPEN) == Wait(f"the roof is {moving}")


@pytest.mark.parametrize("roof", list(RoofState))
def test_bad_weather_closes_and_parks_whatever_is_due(roof: RoofState) -> None:
    bad = _at(NIGHT, weather_good=False, roof=roof)
    assert decide(bad, [_slot("m31", -5, 30)], keep_open=KEEP_OPEN) == CloseAndPark("the weather is bad")
    assert decide(_at(bad, telescope_ready=False), [], keep_open=KEEP_OPEN) == (
        Wait("nothing scheduled") if roof is RoofState.CLOSED else CloseAndPark("the weather is bad")
    )


def test_bad_weather_when_safe_waits_and_never_opens() -> None:
    action = decide(_at(SAFE, weather_good=False), [_slot("m31", -5, 30)], keep_open=KEEP_OPEN)
    assert action == Wait("m31: waiting for good weather")


def test_tasks_without_sky_run_in_bad_weather_with_the_roof_closed() -> None:
    darks = _slot("darks", -1, 30, sky=False)
    assert decide(_at(SAFE, weather_good=False), [darks], keep_open=KEEP_OPEN) == RunTask(darks)
    assert decide(_at(SAFE, sun_altitude=30.0), [darks], keep_open=KEEP_OPEN) == RunTask(darks)


def test_a_sky_task_waits_for_the_sun_and_the_roof_stays_closed() -> None:
    dusk = _at(SAFE, sun_altitude=-8.0)
    assert decide(dusk, [_slot("m31", -5, 30)], keep_open=KEEP_OPEN) == Wait(
        "m31: the Sun is at -8.0°, the task needs ≤ -12°"
    )
    flats = _slot("flats", -5, 30, sun=SunLimits(high=-3.0, low=-12.0))
    assert decide(dusk, [flats], keep_open=KEEP_OPEN) == OpenUp(flats)
    assert decide(_at(SAFE, sun_altitude=-14.0), [flats], keep_open=KEEP_OPEN) == Wait(
        "flats: the Sun is at -14.0°, the task needs -12° .. -3°"
    )


def test_slots_not_due_or_not_runnable_are_skipped() -> None:
    done = _slot("done", -5, 30, may_run=False)
    over = _slot("over", -30, 0)
    later = _slot("later", 60, 90)
    action = decide(SAFE, [done, over, later], keep_open=KEEP_OPEN)
    assert action == Wait("next: later at 23:00:00", until=later.start)
    # overlapping slots: the earliest start goes first
    first, second = _slot("first", -10, 20), _slot("second", -5, 20)
    assert decide(NIGHT, [second, first], keep_open=KEEP_OPEN) == RunTask(first)


def test_the_roof_stays_open_for_a_task_soon_and_closes_for_a_long_gap() -> None:
    soon = _slot("soon", 10, 40)
    assert decide(NIGHT, [soon], keep_open=KEEP_OPEN) == Wait("next: soon at 22:10:00", until=soon.start)
    late = _slot("late", 60, 90)
    assert decide(NIGHT, [late], keep_open=KEEP_OPEN) == CloseAndPark("no sky task within 15 min")
    assert decide(NIGHT, [_slot("darks", 5, 30, sky=False)], keep_open=KEEP_OPEN) == CloseAndPark(
        "the end of the schedule"
    )
    assert decide(NIGHT, [], keep_open=KEEP_OPEN) == CloseAndPark("the end of the schedule")
    # a roof closed with the telescope still unparked is made safe too
    assert decide(_at(NIGHT, roof=RoofState.CLOSED), [], keep_open=KEEP_OPEN) == CloseAndPark(
        "the end of the schedule"
    )


def test_dawn_closes_and_parks_but_dusk_keeps_open_for_the_night() -> None:
    science = _slot("m31", -5, 30)
    dawn = _at(NIGHT, sun_altitude=-11.0, sun_rising=True)
    assert decide(dawn, [science], keep_open=KEEP_OPEN) == CloseAndPark(
        "dawn: the Sun is at -11.0° and rising"
    )
    dusk = _at(NIGHT, sun_altitude=-11.0, sun_rising=False)  # after the flats, before full dark
    assert decide(dusk, [science], keep_open=KEEP_OPEN) == Wait(
        "m31: the Sun is at -11.0°, the task needs ≤ -12°"
    )
    morning_flats = _slot("flats", 0, 30, sun=SunLimits(high=-3.0, low=-12.0))
    assert decide(dawn, [science, morning_flats], keep_open=KEEP_OPEN) == RunTask(morning_flats)


def test_a_due_focus_comes_before_a_task_that_images_stars_but_not_before_flats() -> None:
    science = _slot("m31", -5, 30, needs_focus=True)
    assert decide(NIGHT, [science], keep_open=KEEP_OPEN, focus_below=-10.0) == Focus(science)
    assert decide(NIGHT, [science], keep_open=KEEP_OPEN) == RunTask(science)  # not due
    closed = decide(SAFE, [science], keep_open=KEEP_OPEN, focus_below=-10.0)
    assert closed == OpenUp(science)  # open first, focus then
    flats = _slot("flats", -5, 30, sun=SunLimits(high=-3.0, low=-9.0))
    dusk = _at(NIGHT, sun_altitude=-5.0)
    assert decide(dusk, [flats], keep_open=KEEP_OPEN, focus_below=-10.0) == RunTask(flats)
    # A science task allowed in a bright sky runs unfocused rather than waiting for stars.
    bright = _slot("bright", -5, 30, needs_focus=True, sun=SunLimits(high=0.0))
    assert decide(dusk, [bright], keep_open=KEEP_OPEN, focus_below=-10.0) == RunTask(bright)


def test_the_focus_uses_the_wait_for_the_next_task_once_the_sun_is_low_enough() -> None:
    science = _slot("m31", 10, 40, needs_focus=True)
    after_darks = _at(NIGHT, sun_altitude=-10.5)
    assert decide(after_darks, [science], keep_open=KEEP_OPEN, focus_below=-10.0) == Focus(science)
    waiting = Wait("next: m31 at 22:10:00", until=science.start)
    assert decide(_at(NIGHT, sun_altitude=-9.0), [science], keep_open=KEEP_OPEN, focus_below=-10.0) == waiting
    assert decide(after_darks, [science], keep_open=KEEP_OPEN) == waiting  # focus not due
    # With the roof closed it opens up for the focus; not for a task beyond keep_open.
    assert decide(SAFE, [science], keep_open=KEEP_OPEN, focus_below=-10.0) == OpenUp(science)
    assert decide(_at(SAFE, weather_good=False), [science], keep_open=KEEP_OPEN, focus_below=-10.0) == (
        Wait("next: m31 at 22:10:00", until=science.start)
    )
    later = _slot("m33", 20, 40, needs_focus=True)
    assert decide(SAFE, [later], keep_open=KEEP_OPEN, focus_below=-10.0) == Wait(
        "next: m33 at 22:20:00", until=later.start
    )
    darks = _slot("darks", 10, 40, sky=False)
    assert decide(NIGHT, [darks, science], keep_open=KEEP_OPEN, focus_below=-10.0) == Focus(science)


def test_the_roof_stays_open_when_the_focus_would_open_it_again_within_keep_open() -> None:
    # At dusk the flats are over (Sun -9.5 deg) and the next task, which needs the focus, starts in
    # 26 min: the focus would open up again for it 15 min before, i.e. 11 min after closing.
    after_flats = _at(NIGHT, sun_altitude=-9.5)
    science = _slot("m13", 26, 60, needs_focus=True)
    waiting = Wait("next: m13 at 22:26:00", until=science.start)
    assert decide(after_flats, [science], keep_open=KEEP_OPEN, focus_below=-10.0) == waiting
    darker = _at(after_flats, sun_altitude=-10.5)  # the focus waits for keep_open before the task
    assert decide(darker, [science], keep_open=KEEP_OPEN, focus_below=-10.0) == waiting
    # It closes when the roof would stay unused longer than keep_open ...
    gap = CloseAndPark("no sky task within 15 min")
    assert decide(after_flats, [science], keep_open=KEEP_OPEN) == gap  # focus not due
    far = _slot("m13", 31, 60, needs_focus=True)
    assert decide(after_flats, [far], keep_open=KEEP_OPEN, focus_below=-10.0) == gap
    flats = _slot("flats", 26, 60, sun=SunLimits(high=-3.0, low=-12.0))  # no focus for flats
    assert decide(_at(NIGHT, sun_altitude=-5.0), [flats], keep_open=KEEP_OPEN, focus_below=-10.0) == gap
    # ... and at once, whatever is planned, for bad weather and at dawn.
    bad = _at(after_flats, weather_good=False)
    bad_weather = CloseAndPark("the weather is bad")
    assert decide(bad, [science], keep_open=KEEP_OPEN, focus_below=-10.0) == bad_weather
    dawn = _at(NIGHT, sun_altitude=-9.5, sun_rising=True)
    assert decide(dawn, [science], keep_open=KEEP_OPEN, focus_below=-10.0) == CloseAndPark(
        "dawn: the Sun is at -9.5° and rising"
    )


def test_the_next_task_starts_early_when_it_can_be_observed_now() -> None:
    early = timedelta(minutes=10)
    ready = _slot("m33", 5, 40, startable_now=True)
    assert decide(NIGHT, [ready], keep_open=KEEP_OPEN, early_start=early) == RunTask(ready)
    assert decide(SAFE, [ready], keep_open=KEEP_OPEN, early_start=early) == OpenUp(ready)
    assert decide(NIGHT, [ready], keep_open=KEEP_OPEN) == Wait("next: m33 at 22:05:00", until=ready.start)
    # not too early, not when its target is not up yet, not before a due task, not against the Sun
    later = _slot("later", 15, 40, startable_now=True)
    assert decide(NIGHT, [later], keep_open=KEEP_OPEN, early_start=early) == Wait(
        "next: later at 22:15:00", until=later.start
    )
    not_up = _slot("m33", 5, 40)
    assert decide(NIGHT, [not_up], keep_open=KEEP_OPEN, early_start=early) == Wait(
        "next: m33 at 22:05:00", until=not_up.start
    )
    due = _slot("m31", -5, 30)
    assert decide(NIGHT, [due, ready], keep_open=KEEP_OPEN, early_start=early) == RunTask(due)
    dusk = _at(NIGHT, sun_altitude=-11.0)
    assert decide(dusk, [ready], keep_open=KEEP_OPEN, early_start=early) == Wait(
        "next: m33 at 22:05:00", until=ready.start
    )
    darks = _slot("darks", 5, 40, sky=False, startable_now=True)
    assert decide(_at(SAFE, weather_good=False), [darks], keep_open=KEEP_OPEN, early_start=early) == RunTask(
        darks
    )


def test_the_roof_stays_open_for_a_task_that_may_start_early_within_keep_open() -> None:
    early = timedelta(minutes=30)
    # Its slot is 25 min ahead (beyond keep_open) but it may start early in 10 min: closing now
    # would mean opening again then.
    soon = _slot("m33", 25, 60, early_from=NOW + timedelta(minutes=10))
    assert decide(NIGHT, [soon], keep_open=KEEP_OPEN, early_start=early) == Wait(
        "next: m33 at 22:25:00", until=soon.start
    )
    gap = CloseAndPark("no sky task within 15 min")
    assert decide(NIGHT, [_slot("m33", 25, 60)], keep_open=KEEP_OPEN, early_start=early) == gap
    later = _slot("m33", 25, 60, early_from=NOW + timedelta(minutes=16))
    assert decide(NIGHT, [later], keep_open=KEEP_OPEN, early_start=early) == gap
    # Bad weather and dawn still close at once.
    bad = _at(NIGHT, weather_good=False)
    assert decide(bad, [soon], keep_open=KEEP_OPEN, early_start=early) == CloseAndPark("the weather is bad")
    dawn = _at(NIGHT, sun_altitude=-11.0, sun_rising=True)
    assert decide(dawn, [soon], keep_open=KEEP_OPEN, early_start=early) == CloseAndPark(
        "dawn: the Sun is at -11.0° and rising"
    )


# --- abort_cause -------------------------------------------------------------------------------


def test_a_running_sky_task_stops_for_weather_roof_and_sun() -> None:
    slot = _slot("m31", -5, 30)
    assert abort_cause(NIGHT, slot) is None
    assert abort_cause(_at(NIGHT, weather_good=False), slot) == "bad weather"
    assert abort_cause(_at(NIGHT, roof=RoofState.CLOSING), slot) == "the roof (closing)"
    assert abort_cause(_at(NIGHT, sun_altitude=-11.5), slot) == "the Sun at -11.50° (the task needs ≤ -12°)"


def test_a_running_task_without_sky_goes_on_whatever_happens() -> None:
    darks = _slot("darks", -5, 30, sky=False)
    assert abort_cause(_at(SAFE, weather_good=False, sun_altitude=10.0), darks) is None


# --- tasks -------------------------------------------------------------------------------------


def _task(configurations: list[dict[str, Any]], state: TaskState = TaskState.SCHEDULED) -> Task:
    group = parse_request_group(
        {
            "name": "Test group",
            "proposal": "tests",
            "requests": [
                {
                    "location": {"telescope_class": "0m4"},
                    "windows": [{"start": "2024-01-15T18:00:00Z", "end": "2024-01-16T06:00:00Z"}],
                    "configurations": configurations,
                }
            ],
        }
    )
    (task,) = tasks_of_group(
        group, "g1", ["7"], [TaskStatus(state=state, reason="x" if state is TaskState.FAILED else "")]
    )
    return task


EXPOSE = {
    "type": "EXPOSE",
    "target": {"name": "M31", "ra": 10.68, "dec": 41.27},
    "instrument_configs": [
        {"exposure_time": 10, "exposure_count": 3},
        {"exposure_time": 5, "exposure_count": 2},
    ],
}
DARK = {"type": "DARK", "instrument_configs": [{"exposure_time": 10, "exposure_count": 5}]}
FLAT = {
    "type": "SKY_FLAT",
    "constraints": {"min_sun_altitude": -12, "max_sun_altitude": -1},
    "instrument_configs": [{"exposure_time": 3}],
}


def test_sky_and_sun_limits_come_from_the_configurations_capped_by_the_observatory() -> None:
    caps = {"max_sun_altitude": -12.0, "twilight_max_sun_altitude": -3.0}
    assert not needs_sky(_task([DARK])) and needs_sky(_task([DARK, EXPOSE]))
    assert needs_sky(_task([FLAT])) and not needs_focus(_task([FLAT])) and not needs_focus(_task([DARK]))
    assert needs_focus(_task([FLAT, EXPOSE]))
    assert sun_limits(_task([EXPOSE]), **caps) == SunLimits(high=-12.0)
    assert sun_limits(_task([FLAT]), **caps) == SunLimits(high=-3.0, low=-12.0)
    darker = {**EXPOSE, "constraints": {"max_sun_altitude": -18}}
    assert sun_limits(_task([darker, EXPOSE]), **caps) == SunLimits(high=-18.0)
    brighter = {**EXPOSE, "constraints": {"max_sun_altitude": -6}}
    assert sun_limits(_task([brighter]), **caps) == SunLimits(high=-12.0)


def test_a_slot_may_run_only_for_a_schedulable_task_not_failed_in_it() -> None:
    entry = PlannedSlot("7", NOW, NOW + timedelta(minutes=30))

    def slot_of(task: Task, failed_here: bool = False) -> Slot:
        return slot_for(
            entry, task, max_sun_altitude=-12.0, twilight_max_sun_altitude=-3.0, failed_here=failed_here
        )

    slot = slot_of(_task([EXPOSE]))
    assert (
        slot.task_id,
        slot.name,
        slot.start,
        slot.end,
        slot.needs_sky,
        slot.may_run,
        slot.needs_focus,
    ) == (
        "7",
        "Test group",
        entry.start,
        entry.end,
        True,
        True,
        True,
    )
    assert not slot_of(_task([FLAT])).needs_focus
    assert slot_of(_task([EXPOSE], TaskState.FAILED)).may_run
    assert not slot_of(_task([EXPOSE]), failed_here=True).may_run
    for state in (TaskState.RUNNING, TaskState.COMPLETED, TaskState.CANCELED, TaskState.WINDOW_EXPIRED):
        assert not slot_of(_task([EXPOSE], state)).may_run


def test_the_interruption_reason_says_what_was_done() -> None:
    task = _task([EXPOSE])
    progress = TaskProgress.nothing_done(task.request).with_exposures(task.request, 0, 0, 2)
    assert interruption_reason("bad weather", task, progress) == (
        "interrupted by bad weather: 2 of 5 exposures done"
    )


def test_the_interruption_reason_names_the_frames_cut_short_and_kept() -> None:
    task = _task([DARK, EXPOSE])
    request = task.request
    progress = (
        TaskProgress.nothing_done(request).with_exposures(request, 0, 0, 5).with_exposures(request, 1, 0)
    )
    once = progress.with_cut_short(request, 1, 0, 4.3)
    # Cut short, not done: still 6 of 10, the kept light said with what was asked for.
    assert interruption_reason("bad weather", task, once) == (
        "interrupted by bad weather: 6 of 10 exposures done, 1 cut short after 4.3 of 10 s (kept)"
    )
    twice = once.with_cut_short(request, 1, 1, 2.0)
    assert interruption_reason("the Sun at -1°", task, twice).endswith(
        ": 6 of 10 exposures done, 2 cut short after 4.3 of 10 s and 2 of 5 s (kept)"
    )


def test_task_cards_name_the_task() -> None:
    cards = task_cards(_task([EXPOSE]))
    assert {key: value for key, (value, _) in cards.items()} == {
        "TASK-ID": "7",
        "TASK-NAM": "Test group",
        "TASK-GRP": "g1",
        "TASK-REQ": 0,
        "PROPOSAL": "tests",
        "TASK-PRI": 1.0,
        "OBJECT": "M31",
    }


def test_object_names_the_target_of_the_configuration_being_taken() -> None:
    task = _task([DARK, EXPOSE])
    assert task_cards(task)["OBJECT"][0] == "DARK"
    half = TaskProgress(exposures_done=((5,), (1, 0)))
    assert task_cards(task, half)["OBJECT"][0] == "M31"  # the darks are done


@pytest.mark.parametrize(
    ("focused", "last", "now", "due"),
    [
        (False, None, None, True),
        (False, 5.0, 5.0, True),
        (True, 5.0, None, False),
        (True, None, 5.0, False),
        (True, 5.0, 6.5, False),
        (True, 5.0, 2.9, True),
    ],
)
def test_focus_is_due_first_and_then_after_a_temperature_change(
    focused: bool, last: float | None, now: float | None, due: bool
) -> None:
    assert (
        focus_due(focused=focused, last_temperature=last, temperature=now, threshold=2.0) is not None
    ) is due


def test_the_recorded_progress_never_shrinks_when_a_retry_counts_from_zero() -> None:
    first = TaskProgress(exposures_done=((3, 0),))
    retry = TaskProgress(exposures_done=((1, 0),))
    assert kept_progress(first, retry) == first
    assert kept_progress(first, TaskProgress(exposures_done=((3, 2),))) == TaskProgress(
        exposures_done=((3, 2),)
    )
    # A frame cut short in a run stays recorded, also when a fresh runner then reports from zero.
    cut = CutShortFrame(configuration=0, instrument_config=1, exposed=12.5)
    interrupted = TaskProgress(exposures_done=((3, 1),), cut_short=(cut,))
    assert kept_progress(first, interrupted) == interrupted
    assert kept_progress(interrupted, retry) == TaskProgress(exposures_done=((3, 1),), cut_short=(cut,))
    assert kept_progress(TaskProgress(), retry) == retry
    assert kept_progress(first, TaskProgress()) == first


def test_the_roof_state_follows_the_motion_status() -> None:
    assert RoofState.of_motion(MotionStatus.IDLE) is RoofState.OPEN
    assert RoofState.of_motion(MotionStatus.PARKED) is RoofState.CLOSED
    assert RoofState.of_motion(MotionStatus.PARKING) is RoofState.CLOSING
    assert RoofState.of_motion(MotionStatus.MOVING) is RoofState.OPENING
    assert RoofState.of_motion(MotionStatus.ERROR) is RoofState.UNKNOWN


def test_panel_flats_need_neither_the_sky_nor_a_focus() -> None:
    panel = {"type": "PANEL_FLAT", "instrument_configs": [{"exposure_time": 1, "exposure_count": 3}]}
    task = _task([panel])
    assert not needs_sky(task) and not needs_focus(task)


def test_focus_is_due_again_after_the_refocus_interval_when_one_is_set() -> None:
    steady = {"focused": True, "last_temperature": 5.0, "temperature": 5.0, "threshold": 2.0}
    assert focus_due(**steady, since_focus=7200.0) is None  # type: ignore[arg-type]
    assert focus_due(**steady, since_focus=3500.0, interval=3600.0) is None  # type: ignore[arg-type]
    assert focus_due(**steady, since_focus=3700.0, interval=3600.0) == "3700 s since the last focus"  # type: ignore[arg-type]
