"""Blocks for calibration tasks: near the pole, weighted; sky flats fit the twilight at the site."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from pathlib import Path

import pytest

from nightcrew.modules.robotic import SchedulerModule
from nightcrew.night.blocks import NightBlockSource
from nightcrew.robotic.archive_ports import as_block_source
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.samples import load_samples
from nightcrew.robotic.scheduler import Scheduler
from nightcrew.robotic.scheduler.ports import night_around
from nightcrew.robotic.scheduler.sky import GridFit
from nightcrew.robotic.tasks import RequestGroup, Task, TaskProgress, TaskState, TaskStatus, Window
from nightcrew.robotic.tasks.calibration import (
    CALIBRATION_WEIGHT,
    SKY_FLAT_SECONDS,
    calibration_block,
    twilights,
)
from nightcrew.site import Site
from nightcrew.testing import Observatory
from tests.robotic.test_archives_sqlite import NIGHT, ManualClock

GOETTINGEN = Site(latitude=51.56, longitude=9.94, elevation=201.0)
EQUATOR = Site(latitude=0.3, longitude=-78.5, elevation=2800.0)  # twilight -3..-9 deg: ~24 min
NORTH = Site(latitude=64.1, longitude=-21.9, elevation=50.0)  # in November: over an hour


def task_of(group: RequestGroup, index: int = 0) -> Task:
    return Task(
        id="1", group_id="1", name=group.name, proposal=group.proposal, priority=group.priority,
        request=group.requests[index],
    )  # fmt: skip


def flats_for_the_day(site: Site) -> Task:
    """The sample sky flats with one window over the whole day after local noon of the sample night."""
    group = load_samples()["twilight-sky-flats"]
    noon = datetime(2026, 11, 10, 12, tzinfo=UTC) - timedelta(hours=site.longitude / 15.0)
    request = group.requests[0].model_copy(
        update={"windows": (Window(start=noon, end=noon + timedelta(days=1)),)}
    )
    return task_of(group.model_copy(update={"requests": (request,)}))


def test_bias_and_darks_go_near_the_pole_with_a_weighted_priority() -> None:
    group = load_samples()["bias-and-darks"]
    block = calibration_block(task_of(group))
    assert block.target.dec == 89.0 and block.priority == group.priority * CALIBRATION_WEIGHT
    assert block.constraints.max_sun_altitude == 90


def test_flats_without_a_site_take_half_an_hour_in_their_windows() -> None:
    task = task_of(load_samples()["twilight-sky-flats"])
    block = calibration_block(task)
    assert block.duration_s == SKY_FLAT_SECONDS
    assert block.windows == tuple((w.start, w.end) for w in task.request.windows)


@pytest.mark.parametrize("site", [EQUATOR, GOETTINGEN, NORTH], ids=["equator", "goettingen", "64N"])
@pytest.mark.parametrize("step_s", [300.0, 120.0])
def test_flats_fit_the_twilight_at_the_sites_latitude(site: Site, step_s: float) -> None:
    task = flats_for_the_day(site)
    fit = GridFit(step_s=step_s, slew_overhead_s=60.0)
    block = calibration_block(task, site, fit=fit)
    spans = twilights(site, *block.windows[0], -9.0, -3.0)
    assert len(block.windows) == 2 and spans == [block.windows[0]]  # dusk and dawn, Sun -9..-3
    longest = max((end - start).total_seconds() for start, end in block.windows)
    assert block.duration_s <= 0.75 * longest
    scheduler = Scheduler(step_s=step_s, slew_overhead_s=60.0)
    night = night_around(site, block.windows[0][0] - timedelta(hours=1), max_sun_altitude=-3.0)
    schedule = scheduler.schedule([block], night)
    assert [slot.task_id for slot in schedule.slots] == ["1"], (site, longest, block.duration_s)
    slot = schedule.slots[0]
    assert any(start <= slot.start and slot.end <= end for start, end in block.windows)
    print(
        f"lat {site.latitude:5.1f}: longest twilight {longest / 60:.0f} min,"
        f" block {block.duration_s / 60:.1f} min"
    )


def test_the_twilight_is_much_shorter_at_the_equator_than_far_north() -> None:
    def longest(site: Site) -> float:
        spans = calibration_block(flats_for_the_day(site), site).windows
        return max((end - start).total_seconds() for start, end in spans)

    assert 20 * 60 <= longest(EQUATOR) <= 28 * 60 and longest(NORTH) >= 60 * 60
    # 1800 s flats would not fit the equatorial twilight; the block is shortened instead.
    assert calibration_block(flats_for_the_day(EQUATOR), EQUATOR).duration_s < 20 * 60


def test_retried_darks_are_planned_for_the_frames_they_lack() -> None:
    darks = task_of(load_samples()["bias-and-darks"], 1)  # 5 x 60 s and 3 x 120 s
    # Default overheads: 15 s to set up, 2 s read-out + 1 s per frame; no filters to change.
    assert calibration_block(darks).duration_s == 15 + 5 * 63 + 3 * 123
    status = TaskStatus(
        state=TaskState.FAILED, reason="interrupted", progress=TaskProgress(exposures_done=((5, 1),))
    )
    assert calibration_block(darks.with_status(status)).duration_s == 15 + 2 * 123


async def test_a_plain_archive_gives_calibration_blocks_with_the_schedulers_site(tmp_path: Path) -> None:
    async with SqliteTaskArchive(tmp_path / "t.sqlite", clock=ManualClock(NIGHT), poll_interval=0) as archive:
        for group in load_samples().values():
            await archive.add_request_group(group)
        tasks = await archive.get_schedulable_tasks()
        plain = await as_block_source(archive, site=GOETTINGEN).get_schedulable_blocks()
        named = await as_block_source(
            NightBlockSource(archive=archive), site=GOETTINGEN
        ).get_schedulable_blocks()
    assert [b.id for b in plain] == [t.id for t in tasks]  # those without a target too
    assert plain == named  # the old name gives the same, with the site from the scheduler's
    (flats_id,) = [t.id for t in tasks if t.name == "Twilight sky flats"]
    (flats,) = [b for b in plain if b.id == flats_id]
    assert flats.priority == 4 * CALIBRATION_WEIGHT
    assert flats.windows == tuple(twilights(GOETTINGEN, *flats.windows[0], -9.0, -3.0)) + flats.windows[1:]


async def test_a_scheduler_on_a_plain_archive_plans_the_flats_in_its_sites_twilight(tmp_path: Path) -> None:
    """As a real observatory's file says it: ``archive: SqliteTaskArchive``, the site the scheduler's."""
    epoch = datetime(2026, 11, 10, 14, 0, tzinfo=UTC)
    path = tmp_path / "tasks.sqlite"
    async with (
        Observatory(epoch=epoch, site=GOETTINGEN) as obs,
        SqliteTaskArchive(path, clock=obs.clock, poll_interval=0) as archive,
    ):
        (flats,) = await archive.add_request_group(load_samples()["twilight-sky-flats"])
        scheduler = await obs.start(
            SchedulerModule,
            "scheduler",
            archive=archive,
            store=archive,
            max_sun_altitude=-3.0,
            time_limit_s=2.0,
        )
        await obs.wait_for(lambda: scheduler.schedule is not None, 60.0)
        assert scheduler.schedule is not None
        (slot,) = [s for s in scheduler.schedule.slots if s.task_id == flats.id]
        spans = [s for w in flats.request.windows for s in twilights(GOETTINGEN, w.start, w.end, -9.0, -3.0)]
        assert len(spans) == 2  # dusk and dawn
        assert any(start <= slot.start and slot.end <= end for start, end in spans), (slot, spans)
