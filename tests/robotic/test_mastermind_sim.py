"""The mastermind on the simulated observatory (LocalNetwork, fast clock): a night with rain and a dawn.

Real modules throughout: SimRoof, SimTelescope, SimCamera, a SimWeatherStation playing a scripted
scenario judged by the Weather module, the SQLite archive and the TaskRunner with the ImagingScript.
Only the scheduler is a stand-in (:class:`QueueScheduler`): it puts the schedulable tasks one after
another from the GoodWeatherEvent's eta on, which is enough to show that an interrupted task comes
back. Times are asserted in clock seconds.
"""

from __future__ import annotations

import re
from datetime import datetime, timedelta

import pytest

from nightcrew.events import (
    BadWeatherEvent,
    RoofClosedEvent,
    RoofClosingEvent,
    RoofOpenedEvent,
    TaskFailedEvent,
    TaskFinishedEvent,
    TaskStartedEvent,
)
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import TaskState

from .mastermind_night import (
    EXPOSURE_TIME,
    EXPOSURES,
    HYADES,
    ORION,
    PLEIADES,
    Parts,
    QueueScheduler,
    Recorder,
    group,
    start_mastermind,
    start_night,
)

RAIN_AT, DRY_AT = 660.0, 900.0  # task b runs from ~600 s to ~740 s


async def test_a_night_with_rain_runs_every_task_and_never_exposes_with_the_roof_closed(parts: Parts) -> None:
    scenario = [
        {"at": 0, "temperature": 8.0},
        {"at": RAIN_AT - 10, "temperature": 8.0},
        {"at": RAIN_AT, "rain": True, "temperature": 3.0},
        {"at": DRY_AT, "rain": False},
    ]
    site = await start_night(parts, [group(PLEIADES), group(ORION), group(HYADES)], scenario)
    observatory = site.obs
    t0 = observatory.clock.time()
    now = observatory.clock.now()
    await observatory.start(QueueScheduler, "scheduler", archive=site.archive, slot=600.0)
    a, b, c = site.tasks
    await site.archive.write_schedule(
        [
            PlannedSlot(a.id, now, now + timedelta(seconds=600)),
            PlannedSlot(b.id, now + timedelta(seconds=600), now + timedelta(seconds=1200)),
            PlannedSlot(c.id, now + timedelta(seconds=1200), now + timedelta(seconds=1800)),
        ],
        replace_from=now,
    )
    mastermind = await start_mastermind(site, autofocus="recorder", refocus_temperature_change=2.0)
    assert await mastermind.is_autonomous()

    async def all_completed() -> bool:
        return all([(await site.archive.get_task(t.id)).state is TaskState.COMPLETED for t in site.tasks])

    done = False
    while not done:
        assert observatory.clock.time() - t0 < 3600, "the tasks did not complete"
        await observatory.clock.sleep(20.0)
        done = await all_completed() and await site.closed_and_parked()
    rec = site.recorder

    # Started and ended in order: a, b (interrupted), b again, c.
    started = [e.id for e in rec.of(TaskStartedEvent)]
    assert started == [a.id, b.id, b.id, c.id]
    ended = [
        (type(e).__name__, e.id) for _, e in rec.events if isinstance(e, TaskFinishedEvent | TaskFailedEvent)
    ]
    assert ended == [
        ("TaskFinishedEvent", a.id),
        ("TaskFailedEvent", b.id),
        ("TaskFinishedEvent", b.id),
        ("TaskFinishedEvent", c.id),
    ]

    # Rain: the task stopped within seconds, the roof was closed within a minute.
    (bad,) = site.since(t0, BadWeatherEvent)
    (failed,) = site.since(t0, TaskFailedEvent)
    closed_after = next(t - bad for t in site.since(t0, RoofClosedEvent) if t > bad)
    print(
        f"\nbad weather at {bad:.0f} s: aborted {failed - bad:.1f} s, roof closed {closed_after:.1f} s later"
    )
    assert RAIN_AT <= bad <= RAIN_AT + 25
    assert failed - bad <= 10.0
    assert closed_after <= 60.0
    (failed_event,) = rec.of(TaskFailedEvent)
    assert failed_event.retryable  # so the scheduler plans it again
    reason = failed_event.reason

    # Every image: the task's cards, exposed entirely while the roof was open. The retry of b took
    # only the frames the rain had kept it from taking; the frame the rain cut short was kept, and
    # the reason says so with the seconds its header gives.
    headers = await site.headers()
    (cut,) = [h for h in headers if h.get("CUTSHORT")]
    assert cut["TASK-ID"] == b.id and cut["EXPTIME"] < cut["EXPREQ"]
    said = re.fullmatch(
        rf"interrupted by bad weather: (\d+) of {EXPOSURES} exposures done, "
        rf"1 cut short after ([\d.]+) of {EXPOSURE_TIME:.0f} s \(kept\)",
        reason,
    )
    assert said is not None, reason
    assert 0 < int(said[1]) < EXPOSURES
    assert float(said[2]) == pytest.approx(cut["EXPTIME"], abs=0.5)  # rounded for reading
    assert len(headers) == 3 * EXPOSURES + 1
    ids = [h["TASK-ID"] for h in headers]
    assert ids == sorted(ids, key=[a.id, b.id, c.id].index) and set(ids) == {a.id, b.id, c.id}
    assert all(h["PROPOSAL"] == "tests" and h["TASK-NAM"].endswith(" in V") for h in headers)
    targets = {t.id: t.request.configurations[0].target for t in (a, b, c)}
    assert all(h["OBJECT"] == getattr(targets[h["TASK-ID"]], "name", None) for h in headers)
    assert all(h["DATE-END"] > h["DATE-OBS"] for h in headers)
    open_intervals = _open_intervals(rec)
    for header in headers:
        begin = datetime.fromisoformat(header["DATE-OBS"]).replace(tzinfo=now.tzinfo).timestamp()
        end = begin + header["EXPTIME"]
        assert any(opened <= begin and end <= closing + 1.0 for opened, closing in open_intervals), header[
            "DATE-OBS"
        ]
    spans = [(round(o - t0), round(c - t0)) for o, c in open_intervals]
    print(f"{len(headers)} images, none exposed while the roof was closed; open from/to (s): {spans}")

    # Focus: before the first task, and again after the rain had cooled the air by 5 °C.
    focus = [t - t0 for t in rec.focus_runs]
    assert len(focus) == 2 and focus[1] > DRY_AT, focus

    # The archive: all completed, b with its exposures and the frame cut short (not counted as
    # done), also as a restarted mastermind would read it: the last thing: closed and parked.
    assert await site.closed_and_parked()
    tasks = [await site.archive.get_task(t.id) for t in site.tasks]
    assert [t.status.progress.total_exposures for t in tasks] == [EXPOSURES] * 3
    reopened = SqliteTaskArchive(site.archive.path, clock=observatory.clock, poll_interval=0)
    await reopened.open()
    try:
        stored = [(await reopened.get_task(t.id)).status.progress for t in site.tasks]
    finally:
        await reopened.close()
    assert stored == [t.status.progress for t in tasks]
    assert [len(p.cut_short) for p in stored] == [0, 1, 0]
    (frame,) = stored[1].cut_short
    assert (frame.configuration, frame.instrument_config) == (0, 0)
    assert frame.exposed == pytest.approx(cut["EXPTIME"], abs=1e-6)


def _open_intervals(rec: Recorder) -> list[tuple[float, float]]:
    """(roof opened, roof started closing) clock times."""
    opened = rec.times(RoofOpenedEvent)
    closing = rec.times(RoofClosingEvent)
    return [(o, next((c for c in closing if c > o), float("inf"))) for o in opened]
