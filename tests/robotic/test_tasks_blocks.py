"""The adapter from tasks to the scheduler's blocks."""

from __future__ import annotations

from datetime import UTC, datetime
from pathlib import Path

from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.samples import load_samples
from nightcrew.robotic.scheduler import Night, Scheduler
from nightcrew.robotic.tasks import OverheadModel, estimate_duration, tasks_of_group
from nightcrew.robotic.tasks.blocks import ArchiveBlockSource, block_of, blocks_of
from nightcrew.site import Site
from tests.robotic.test_archives_sqlite import NIGHT, ManualClock


def test_a_task_becomes_a_block_with_the_strictest_constraints() -> None:
    group = load_samples()["m52-focus-and-image"]
    task = tasks_of_group(group, "g", ["t1"])[0]
    overheads = OverheadModel(request_setup_s=120)
    block = block_of(task, overheads)
    assert block is not None
    assert (block.id, block.priority, block.setup_s) == ("t1", 2.0, 120.0)
    assert block.duration_s == sum(estimate_duration(task.request, overheads).configurations_s)
    assert (block.target.ra, block.target.dec) == (351.2, 61.59333)
    assert block.constraints.max_airmass == 1.3  # the EXPOSE limit, stricter than AUTO_FOCUS's 2.0
    assert block.constraints.min_moon_distance == 30.0
    assert block.windows == (
        (datetime(2026, 11, 10, 17, 50, tzinfo=UTC), datetime(2026, 11, 11, tzinfo=UTC)),
    )
    algol = block_of(tasks_of_group(load_samples()["algol-light-curve"], "g", ["a"])[0])
    assert algol is not None and algol.priority == 5.0 and algol.target.pm_ra_cosdec == 2.39


def test_tasks_without_a_target_are_left_out_and_named() -> None:
    samples = load_samples()
    tasks = tasks_of_group(samples["bias-and-darks"], "c", ["bias", "dark"])
    tasks += tasks_of_group(samples["pleiades-open-cluster"], "p", ["pleiades"])
    conversion = blocks_of(tasks)
    assert [b.id for b in conversion.blocks] == ["pleiades"]
    assert conversion.left_out == ("bias", "dark")


async def test_the_scheduler_plans_the_sample_night_from_the_archive(tmp_path: Path) -> None:
    async with SqliteTaskArchive(tmp_path / "t.sqlite", clock=ManualClock(NIGHT), poll_interval=0) as archive:
        for group in load_samples().values():
            await archive.add_request_group(group)
        blocks = await ArchiveBlockSource(archive).get_schedulable_blocks()
    assert len(blocks) == 9  # 12 tasks, three without a target
    night = Night(
        datetime(2026, 11, 10, 17, 50, tzinfo=UTC),
        datetime(2026, 11, 11, 5, tzinfo=UTC),
        Site(latitude=51.56, longitude=9.94, elevation=201.0),
    )
    schedule = Scheduler(solver="priority").schedule(blocks, night)
    assert len(schedule.slots) >= 7
