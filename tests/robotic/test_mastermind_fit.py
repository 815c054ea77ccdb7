"""A task starts only when what it has left ends before its Sun, airmass or window limit."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from typing import Any

from nightcrew.robotic.mastermind import time_left, within_constraints
from nightcrew.robotic.tasks import TaskProgress, Window
from tests.robotic.test_mastermind_decide import EXPOSE, NOW, _task
from tests.robotic.test_mastermind_early_start import HIGH, SITE

# High at dawn: observable until the Sun reaches -12° at 05:58 (its window ends at 06:00).
DAWN = {**EXPOSE, "target": {"name": "east", "ra": 210.0, "dec": 40.0}}
# The same under a Sun up to -6° (at 06:40): only its window end at 06:00 stops it.
LATE = {**DAWN, "constraints": {"max_sun_altitude": -6}}
WINDOW_END = datetime(2024, 1, 16, 6, tzinfo=UTC)


def _fits(configuration: dict[str, Any], now: datetime, minutes: float, **cap: float) -> bool:
    return within_constraints(_task([configuration]).request, SITE, now, timedelta(minutes=minutes), **cap)


def test_a_task_that_would_run_into_dawn_is_not_started_one_that_ends_before_it_is() -> None:
    now = NOW + timedelta(hours=7, minutes=30)  # 05:30
    assert _fits(DAWN, now, 20)
    assert _fits(DAWN, now, 28)  # ends 05:58, still at -12°
    assert not _fits(DAWN, now, 29)
    assert not _fits(DAWN, now, 60)


def test_a_task_must_end_within_its_window_and_above_its_airmass_limit() -> None:
    now = NOW + timedelta(hours=7, minutes=30)
    assert _fits(LATE, now, 30)  # ends at its window's end
    assert not _fits(LATE, now, 31)
    three = NOW + timedelta(hours=5)  # Capella sinks below airmass 2 at 03:33
    assert _fits(HIGH, three, 33)
    assert not _fits(HIGH, three, 34)
    window = _task([LATE]).request.windows[0]
    assert window.end == WINDOW_END


def test_the_observatorys_sun_cap_applies_to_a_task_that_allows_a_brighter_sky() -> None:
    now = NOW + timedelta(hours=7, minutes=40)  # 05:40; the Sun reaches -12° at 05:58
    assert _fits(LATE, now, 19)
    assert not _fits(LATE, now, 19, max_sun_altitude=-12.0)
    assert _fits(LATE, now, 18, max_sun_altitude=-12.0)


def test_a_retried_task_is_judged_by_what_it_has_left() -> None:
    task = _task([{**DAWN, "instrument_configs": [{"exposure_time": 120, "exposure_count": 12}]}])
    now = NOW + timedelta(hours=7, minutes=40)  # 05:40, 18 min before dawn
    whole = time_left(task)
    assert whole.total_seconds() == 90 + 15 + 12 * (120 + 2 + 1)  # set-ups, exposures: 26 min
    assert not within_constraints(task.request, SITE, now, whole)
    status = task.status.model_copy(update={"progress": TaskProgress(exposures_done=((7,),))})
    retried = task.model_copy(update={"status": status})
    assert time_left(retried) == whole - timedelta(seconds=7 * 123)
    assert within_constraints(retried.request, SITE, now, time_left(retried))


def test_a_task_outside_its_window_never_fits() -> None:
    request = _task([LATE]).request
    moved = request.model_copy(update={"windows": (Window(start=NOW + timedelta(hours=1), end=WINDOW_END),)})
    assert not within_constraints(moved, SITE, NOW + timedelta(minutes=30), timedelta(minutes=10))
    assert within_constraints(moved, SITE, NOW + timedelta(hours=2), timedelta(minutes=10))


def test_at_dusk_a_task_fits_from_the_first_moment_the_sun_is_low_enough() -> None:
    request = _task([HIGH]).request.model_copy(
        update={"windows": (Window(start=NOW - timedelta(hours=6), end=WINDOW_END),)}
    )
    dusk = datetime(2024, 1, 15, 17, 0, 5, tzinfo=UTC)  # the Sun passes -12° (17:00:00: -11.99°)
    length = timedelta(minutes=30, seconds=50)  # a grid counted back from its end starts at 16:59:59
    assert not within_constraints(request, SITE, dusk - timedelta(seconds=5), length)
    assert within_constraints(request, SITE, dusk + timedelta(seconds=5), length)


def test_the_slew_to_the_task_counts_with_the_schedulers_model() -> None:
    from nightcrew.robotic.mastermind import slew_before
    from nightcrew.robotic.scheduler.slew import AxisMotion, SlewModel

    model = SlewModel(AxisMotion(1.0), AxisMotion(1.0), settle_s=10.0)  # a slow mount: 1°/s
    task = _task([DAWN])
    now = NOW + timedelta(hours=7, minutes=30)  # 05:30; the task ends at 05:58 with 28 min
    there = slew_before(task, model, SITE, (210.0, 40.0), now)
    assert there == timedelta(0)  # already on target
    far = slew_before(task, model, SITE, (210.0, -20.0), now)  # 60° away in declination
    assert far == timedelta(seconds=70.0)
    assert within_constraints(task.request, SITE, now, timedelta(minutes=27) + there)
    assert not within_constraints(task.request, SITE, now, timedelta(minutes=27) + far)
