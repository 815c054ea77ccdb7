"""Opening up costs no more sky time than it must: the slew happens while the roof opens, and a due
task that no longer fits hands over to the next one at once.

Real modules throughout (see test_mastermind_sim); the schedule is written by the test. Times are
clock seconds on the virtual clock.
"""

from __future__ import annotations

from datetime import datetime, timedelta

from nightcrew.events import Event, GoodWeatherEvent, NewImageEvent, RoofOpenedEvent, TaskStartedEvent
from nightcrew.robotic.planning import PlannedSlot

from .mastermind_night import HYADES, ORION, PLEIADES, Night, Parts, group, start_mastermind, start_night

#: The weather module's first verdict comes after a minute of good readings.
DRY = [{"at": 0, "temperature": 8.0}]


async def _run_until(site: Night, event_type: type[Event], count: int = 1, limit: float = 3600.0) -> None:
    t0 = site.obs.clock.time()
    while len(site.recorder.times(event_type)) < count:
        assert site.obs.clock.time() - t0 < limit, f"no {event_type.__name__} within {limit:g} s"
        await site.obs.clock.sleep(5.0)


async def test_the_telescope_slews_to_the_first_target_while_the_roof_opens(parts: Parts) -> None:
    site = await start_night(parts, [group(PLEIADES)], DRY)
    now = site.obs.clock.now()
    (task,) = site.tasks
    await site.archive.write_schedule(
        [PlannedSlot(task.id, now, now + timedelta(seconds=1200))], replace_from=now
    )
    await start_mastermind(site)
    await _run_until(site, NewImageEvent)
    (opened,) = site.recorder.times(RoofOpenedEvent)
    first = datetime.fromisoformat((await site.headers())[0]["DATE-OBS"] + "+00:00").timestamp()
    # From the park position the slew to the Pleiades takes some 15 s; done while the roof opened
    # (30 s), only the task's own short move (settling, 1 s) and a step of the loop are left.
    assert 0.0 < first - opened <= 3.0, first - opened


async def test_a_due_task_that_no_longer_fits_hands_over_to_the_next_at_once(parts: Parts) -> None:
    now = parts[0].clock.now()
    # The first task's window closes before its six exposures could end: it may not start.
    short = group(ORION)
    short["requests"][0]["windows"] = [
        {"start": (now - timedelta(hours=1)).isoformat(), "end": (now + timedelta(seconds=180)).isoformat()}
    ]
    site = await start_night(parts, [short, group(HYADES)], DRY)
    late, next_one = site.tasks
    await site.archive.write_schedule(
        [
            PlannedSlot(late.id, now, now + timedelta(seconds=600)),
            PlannedSlot(next_one.id, now + timedelta(seconds=900), now + timedelta(seconds=1500)),
        ],
        replace_from=now,
    )
    await start_mastermind(site, early_start=1800.0)
    await _run_until(site, TaskStartedEvent)
    (good,) = site.recorder.times(GoodWeatherEvent)
    assert [e.id for e in site.recorder.of(TaskStartedEvent)] == [next_one.id]
    # Opening the roof takes 30 s; the next task starts then, not at its slot 15 minutes on.
    started = site.recorder.times(TaskStartedEvent)[0]
    assert started - good <= 60.0, started - good
