"""The adapter from tasks to the scheduler's blocks."""

from __future__ import annotations

from datetime import UTC, datetime
from pathlib import Path

import pytest

from nightcrew.robotic.archive_ports import ArchiveBlockSource
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.samples import load_samples
from nightcrew.robotic.scheduler import Night, Scheduler
from nightcrew.robotic.tasks import (
    OverheadModel,
    Task,
    TaskProgress,
    TaskState,
    TaskStatus,
    estimate_duration,
    tasks_of_group,
)
from nightcrew.robotic.tasks.blocks import NOTHING_LEFT_S, block_of, blocks_of
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
    assert len(blocks) == 11  # 12 tasks, one expired; those without a target as calibration blocks
    night = Night(
        datetime(2026, 11, 10, 17, 50, tzinfo=UTC),
        datetime(2026, 11, 11, 5, tzinfo=UTC),
        Site(latitude=51.56, longitude=9.94, elevation=201.0),
    )
    schedule = Scheduler(solver="priority").schedule(blocks, night)
    assert len(schedule.slots) >= 8


#: Round numbers, so the expected durations below can be added up by hand.
OVERHEADS = OverheadModel(
    request_setup_s=100, configuration_setup_s=10, filter_change_s=5, readout_s=4, per_exposure_s=1
)


def interrupted(task: Task, *exposures_done: tuple[int, ...]) -> Task:
    """``task`` as an interrupted attempt leaves it: FAILED, with ``exposures_done`` recorded."""
    status = TaskStatus(
        state=TaskState.FAILED,
        reason="interrupted by bad weather",
        progress=TaskProgress(exposures_done=exposures_done),
    )
    return task.with_status(status)


def test_a_retried_task_is_planned_for_the_exposures_it_lacks() -> None:
    # M15: 3 x 180 s in B, 3 x 120 s in V, 3 x 120 s in R; one frame costs exposure + 4 + 1 s.
    task = tasks_of_group(load_samples()["m15-globular-cluster"], "g", ["m15"])[0]
    full = block_of(task, OVERHEADS)
    assert full is not None
    assert full.duration_s == 10 + (5 + 3 * 185) + (5 + 3 * 125) + (5 + 3 * 125)
    # B done, 1 V frame taken: the retry sets up, changes to V for 2 frames, then R for 3.
    retry = block_of(interrupted(task, (3, 1, 0)), OVERHEADS)
    assert retry is not None
    assert retry.duration_s == 10 + (5 + 2 * 125) + (5 + 3 * 125)
    assert retry.setup_s == full.setup_s == 100  # the retry slews and sets up again
    # The scheduler weighs it by the time it still observes.
    night = Night(
        datetime(2026, 11, 10, 17, 50, tzinfo=UTC),
        datetime(2026, 11, 10, 21, tzinfo=UTC),
        Site(latitude=51.56, longitude=9.94, elevation=201.0),
    )
    problem = Scheduler(solver="priority", step_s=60).problem([retry], night)
    assert problem.weights[0] == pytest.approx(3.0 * 645 / 3600)  # priority x hours observed
    assert problem.lengths[0] == 15  # 100 s set-up + 100 s slew + 645 s = 845 s: 15 slices of 60 s


def test_a_retried_repeat_is_planned_for_its_time_left() -> None:
    # Algol: 60-s V frames for 2700 s. Ten frames taken: 2100 s left, the first cycle is done.
    task = tasks_of_group(load_samples()["algol-light-curve"], "g", ["algol"])[0]
    full, retry = (block_of(t, OVERHEADS) for t in (task, interrupted(task, (10,))))
    assert full is not None and retry is not None
    assert (full.duration_s, retry.duration_s) == (10 + 2700, 10 + 2700 - 10 * 60)


def test_a_retry_with_every_exposure_taken_still_gets_a_block() -> None:
    task = tasks_of_group(load_samples()["m15-globular-cluster"], "g", ["m15"])[0]
    block = block_of(interrupted(task, (3, 3, 3)), OVERHEADS)
    assert block is not None and block.duration_s == NOTHING_LEFT_S


async def test_the_archive_hands_out_the_shorter_block_after_an_interruption(tmp_path: Path) -> None:
    async with SqliteTaskArchive(tmp_path / "t.sqlite", clock=ManualClock(NIGHT), poll_interval=0) as archive:
        (task,) = await archive.add_request_group(load_samples()["m15-globular-cluster"])
        source = ArchiveBlockSource(archive, OVERHEADS)
        (before,) = await source.get_schedulable_blocks()
        await archive.mark_started(task.id)
        await archive.mark_failed(task.id, "rain", TaskProgress(exposures_done=((3, 1, 0),)))
        (after,) = await source.get_schedulable_blocks()
    assert (before.duration_s, after.duration_s) == (1330, 645)
