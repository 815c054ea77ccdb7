"""A VOEvent in a simulated night: published to the broker, on the sky within a minute; retracted
while it is observed, it stops (the frame in flight kept) and is cancelled.

The night runs on virtual time; while the notice travels through the broker (real processes) the
clock is held, as for any work outside the observatory, so the figure is the observatory's own:
from the notice reaching the listener to the shutter opening for it, pre-empting a running task.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable
from datetime import datetime, timedelta
from pathlib import Path

from nightcrew.clock import Clock
from nightcrew.events import NewImageEvent, RapidResponseEvent, TaskFailedEvent, TasksChangedEvent
from nightcrew.modules.alerts import AlertListener
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import TaskState
from nightcrew.testing import Observatory
from nightcrew.testing.comet import CometBroker
from nightcrew.vfs import MemoryFile
from tests.robotic.mastermind_night import PLEIADES, group, start_mastermind, start_night

from .voevents import STREAM, notice

RULES = {
    "field_of_view": 0.5,
    "priority": 100,
    "exposures": [{"exposure_time": 10, "exposure_count": 2, "optical_elements": {"filter": "V"}}],
}


async def outside(clock: Clock, condition: Callable[[], bool], what: str) -> None:
    """Wait for ``condition`` with the clock held (the outside world takes no clock time), at most
    20 wall seconds."""
    loop = asyncio.get_running_loop()
    async with clock.work("simulate"):
        deadline = time.monotonic() + 20.0
        while not condition():
            assert time.monotonic() < deadline, what
            await loop.run_in_executor(None, time.sleep, 0.02)


async def test_a_published_notice_has_the_shutter_open_within_a_minute_and_its_retraction_stops_it(
    comet: CometBroker, tmp_path: Path
) -> None:
    obs = Observatory()
    archive = SqliteTaskArchive(tmp_path / "tasks.sqlite", clock=obs.clock, poll_interval=0)
    await archive.open()
    try:
        site = await start_night(
            (obs, archive), [group(PLEIADES, count=8, exposure_time=60.0)], [{"at": 0, "temperature": 8.0}]
        )
        clock, rec = obs.clock, site.recorder
        listener: AlertListener | None = None

        async def start_listener() -> None:
            nonlocal listener
            listener = await obs.start(
                AlertListener, "alerts", broker=comet.address, archive=archive, rules=RULES
            )

        async with clock.work("simulate"):
            await start_listener()
        assert listener is not None
        await outside(clock, lambda: listener.connected, "the listener did not connect")
        heard: list[RapidResponseEvent] = []

        async def on_rapid(event: RapidResponseEvent, sender: str) -> None:
            heard.append(event)

        await rec.comm.register_event(RapidResponseEvent, on_rapid)
        heard_changes: list[TasksChangedEvent] = []

        async def on_change(event: TasksChangedEvent, sender: str) -> None:
            if event.change == "cancelled":
                heard_changes.append(event)

        await rec.comm.register_event(TasksChangedEvent, on_change)
        (normal,) = site.tasks
        now = clock.now()
        await archive.write_schedule(
            [PlannedSlot(normal.id, now, now + timedelta(hours=1))], replace_from=now
        )
        await start_mastermind(site)
        for _ in range(300):  # bounded: the running task has taken a frame
            if rec.of(NewImageEvent):
                break
            await clock.sleep(5.0)

        published = clock.time()
        async with clock.work("simulate"):
            assert await comet.publish(notice("grb1", ra=66.75, dec=15.87, error=0.05)) == "ack"
        await outside(clock, lambda: bool(heard), "the notice did not become a request")
        (rapid_id,) = heard[0].ids
        for _ in range(120):
            if any(h["TASK-ID"] == rapid_id for h in await site.headers()):
                break
            await clock.sleep(1.0)
        first = next(h for h in await site.headers() if h["TASK-ID"] == rapid_id)
        opened = datetime.fromisoformat(first["DATE-OBS"]).replace(tzinfo=now.tzinfo).timestamp()
        print(f"\nnotice published -> shutter open: {opened - published:.1f} clock s")
        assert 0 < opened - published <= 60.0
        (failed,) = rec.of(TaskFailedEvent)
        assert failed.id == normal.id and failed.retryable

        # Retracted while its second frame is exposed: stopped at once, the frame kept, cancelled.
        retraction = notice("grb1-retr", ra=None, retraction=True, cites=(("retraction", f"{STREAM}#grb1"),))
        async with clock.work("simulate"):
            assert await comet.publish(retraction) == "ack"
        await outside(clock, lambda: len(heard_changes) == 1, "the retraction cancelled nothing")
        for _ in range(30):  # bounded: the frame in flight is stopped and read out
            if len(rec.of(TaskFailedEvent)) == 2:
                break
            await clock.sleep(1.0)
        stopped = rec.of(TaskFailedEvent)[1]
        assert stopped.id == rapid_id and not stopped.retryable
        assert "retracted by" in stopped.reason and "cut short" in stopped.reason
        assert (await archive.get_task(rapid_id)).state is TaskState.CANCELED
        (cut,) = [h for h in await site.headers() if h["TASK-ID"] == rapid_id and h.get("CUTSHORT")]
        assert cut["EXPTIME"] < cut["EXPREQ"] == 10.0
    finally:
        await obs.close()
        await archive.close()
        MemoryFile.clear_shared()
