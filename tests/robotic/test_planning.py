"""The one planned-slot type: checked when built, and passed unchanged from scheduler to mastermind."""

from __future__ import annotations

from datetime import UTC, date, datetime, timedelta
from pathlib import Path

import pytest

from nightcrew.clock import VirtualClock
from nightcrew.errors import InvalidArgumentError
from nightcrew.night.plan import samples_for_night
from nightcrew.robotic.archive_ports import ArchiveBlockSource, as_schedule_writer
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.mastermind import slot_for
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.samples import load_samples
from nightcrew.robotic.scheduler import Scheduler
from nightcrew.robotic.scheduler.ports import night_around
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
DUSK = datetime(2026, 11, 10, 17, 30, tzinfo=UTC)


def test_a_planned_slot_needs_aware_times_and_an_end_after_its_start() -> None:
    with pytest.raises(InvalidArgumentError, match="planned slot of task 7: start and end need a time zone"):
        PlannedSlot("7", datetime(2026, 11, 10, 20), datetime(2026, 11, 10, 21))
    with pytest.raises(InvalidArgumentError, match=r"planned slot of task 7: end .* is not after its start"):
        PlannedSlot("7", DUSK, DUSK)


async def test_the_schedulers_slots_reach_the_mastermind_as_they_are(tmp_path: Path) -> None:
    clock = VirtualClock(DUSK)
    async with SqliteTaskArchive(tmp_path / "tasks.sqlite", clock=clock, poll_interval=0) as archive:
        for group in samples_for_night(load_samples(), date(2026, 11, 10), SITE):
            await archive.add_request_group(group)
        blocks = await ArchiveBlockSource(archive, site=SITE).get_schedulable_blocks()
        now = clock.now()
        schedule = Scheduler(time_limit_s=2.0).schedule(blocks, night_around(SITE, now), now=now)
        assert schedule.slots and all(type(s) is PlannedSlot for s in schedule.slots)

        await as_schedule_writer(archive).set_schedule(schedule.slots, now)
        stored = await archive.read_schedule()
        assert stored == list(schedule.slots)

        first = stored[0]
        task = await archive.get_task(first.task_id)
        slot = slot_for(first, task, max_sun_altitude=-12.0, twilight_max_sun_altitude=-3.0)
        assert slot.planned is first
        assert (slot.task_id, slot.start, slot.end) == (first.task_id, first.start, first.end)
        assert slot.end - slot.start > timedelta(0)
