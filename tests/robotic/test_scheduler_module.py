"""The scheduler module re-plans on changed tasks, failed tasks and good weather (in-process, fast clock)."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import AsyncIterator
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta

import pytest

from nightcrew.events import GoodWeatherEvent, ScheduleChangedEvent, TaskFailedEvent, TasksChangedEvent
from nightcrew.modules import Module
from nightcrew.modules.robotic import SchedulerModule
from nightcrew.robotic.scheduler import Night, SchedulableBlock, Target
from nightcrew.robotic.scheduler.ports import MemoryScheduleStore, night_around
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks
from nightcrew.testing import SITE, Observatory, wait_for

EPOCH = datetime(2024, 1, 15, 20, 0, tzinfo=UTC)
BLOCKS = synthetic_blocks(Night(EPOCH, EPOCH + timedelta(hours=10), SITE), 25, seed=11)


class ListArchive:
    """The blocks in a list that the test may change."""

    def __init__(self, blocks: list[SchedulableBlock]) -> None:
        self.blocks = blocks

    async def get_schedulable_blocks(self) -> list[SchedulableBlock]:
        return list(self.blocks)


class CountingStore(MemoryScheduleStore):
    def __init__(self) -> None:
        super().__init__()
        self.writes = 0
        self.written = asyncio.Event()

    async def set_schedule(self, slots: object, planned_at: datetime) -> None:
        await super().set_schedule(slots, planned_at)  # type: ignore[arg-type]
        self.writes += 1
        self.written.set()

    async def next_write(self) -> None:
        self.written.clear()
        # Clock seconds (the observatory's loop runs on virtual time): a poll interval, the solve's
        # declared cost (WORK_COSTS["schedule"]) and some.
        await asyncio.wait_for(self.written.wait(), timeout=60)


@dataclass
class Setup:
    scheduler: SchedulerModule
    sender: Module
    archive: ListArchive
    store: CountingStore


@pytest.fixture
async def setup() -> AsyncIterator[Setup]:
    async with Observatory(epoch=EPOCH) as obs:
        archive, store = ListArchive(list(BLOCKS)), CountingStore()
        sender = await obs.start(Module, "mastermind")
        scheduler = await obs.start(
            SchedulerModule, "scheduler", archive=archive, store=store, time_limit_s=2.0, poll_interval_s=20.0
        )
        await asyncio.wait_for(store.written.wait(), timeout=20)  # the first plan
        yield Setup(scheduler, sender, archive, store)


async def test_the_first_plan_is_written_at_start(setup: Setup) -> None:
    assert setup.store.writes == 1
    assert setup.store.slots
    assert setup.store.planned_at is not None and setup.store.planned_at >= EPOCH
    assert setup.store.slots[0].start >= EPOCH


async def test_a_failed_task_is_left_out_of_the_new_plan(setup: Setup) -> None:
    failed = setup.store.slots[0].task_id
    await setup.sender.comm.send_event(TaskFailedEvent(name=failed, id=failed, reason="dome stuck"))
    await setup.store.next_write()
    assert setup.store.writes == 2
    assert failed not in {slot.task_id for slot in setup.store.slots}
    assert setup.store.planned_at is not None
    assert all(slot.start >= setup.store.planned_at - timedelta(seconds=1) for slot in setup.store.slots)


async def test_an_interrupted_task_stays_in_the_new_plan(setup: Setup) -> None:
    interrupted = setup.store.slots[0].task_id
    await setup.sender.comm.send_event(
        TaskFailedEvent(
            name=interrupted,
            id=interrupted,
            reason="interrupted by bad weather: 2 of 6 exposures done",
            retryable=True,
        )
    )
    await setup.store.next_write()
    assert setup.store.writes == 2
    assert interrupted in {slot.task_id for slot in setup.store.slots}


async def test_good_weather_plans_from_its_eta(setup: Setup) -> None:
    eta = EPOCH + timedelta(hours=2)
    await setup.sender.comm.send_event(GoodWeatherEvent(eta=eta))
    await setup.store.next_write()
    assert setup.store.writes == 2
    assert all(slot.start >= eta for slot in setup.store.slots)


async def test_changed_tasks_are_noticed_by_polling(setup: Setup) -> None:
    first = setup.store.slots[0].task_id
    setup.archive.blocks = [b for b in setup.archive.blocks if b.id != first]
    await setup.store.next_write()  # within one poll interval (20 clock s) and a solve
    assert first not in {slot.task_id for slot in setup.store.slots}


def test_the_night_is_found_around_now() -> None:
    night = night_around(SITE, EPOCH)
    assert night.start == EPOCH
    dawn = datetime(2024, 1, 16, 6, 0, tzinfo=UTC)
    assert dawn - timedelta(minutes=30) < night.end < dawn + timedelta(minutes=30)
    afternoon = night_around(SITE, datetime(2024, 1, 15, 12, 0, tzinfo=UTC))
    dusk = datetime(2024, 1, 15, 17, 0, tzinfo=UTC)  # nautical twilight ends about then
    assert dusk - timedelta(minutes=30) < afternoon.start < dusk + timedelta(minutes=30)


# --- why tasks are left out, tasks changed by event, device faults ---------------------------------

FEW = [
    SchedulableBlock(id=name, priority=1.0, duration_s=1200.0, target=Target(ra=60.0, dec=80.0))
    for name in ("a", "b", "c")
]
NEVER_UP = SchedulableBlock(id="south", priority=1.0, duration_s=600.0, target=Target(ra=0.0, dec=-80.0))


@pytest.fixture
async def few() -> AsyncIterator[Setup]:
    """Three short circumpolar blocks and one that never rises; polling too rare to matter."""
    async with Observatory(epoch=EPOCH) as obs:
        archive, store = ListArchive([*FEW, NEVER_UP]), CountingStore()
        sender = await obs.start(Module, "mastermind")
        scheduler = await obs.start(
            SchedulerModule,
            "scheduler",
            archive=archive,
            store=store,
            time_limit_s=2.0,
            poll_interval_s=3600.0,
        )
        await asyncio.wait_for(store.written.wait(), timeout=20)
        yield Setup(scheduler, sender, archive, store)


async def test_the_plan_names_every_task_it_leaves_out_with_the_reason(
    few: Setup, caplog: pytest.LogCaptureFixture
) -> None:
    plan = await few.scheduler.get_plan()
    assert plan is not None and {slot.task_id for slot in plan.slots} == {"a", "b", "c"}
    assert [u.task_id for u in plan.unplanned] == ["south"]
    assert plan.unplanned[0].reason.startswith("never above the airmass limit")
    # Logged once per change of the reason, not with every plan.
    caplog.set_level(logging.INFO, logger="nightcrew.modules.robotic.scheduler")
    await few.sender.comm.send_event(TasksChangedEvent(ids=("a",), change="changed"))
    await few.store.next_write()
    assert not [r for r in caplog.records if "not planned" in r.getMessage()]
    few.archive.blocks = [NEVER_UP]
    await few.sender.comm.send_event(TasksChangedEvent(ids=("a", "b", "c"), change="cancelled"))
    await few.store.next_write()
    assert not [r for r in caplog.records if "not planned" in r.getMessage()]  # the same reason
    few.archive.blocks = [
        NEVER_UP,
        SchedulableBlock(id="long", priority=1.0, duration_s=20 * 3600.0, target=FEW[0].target),
    ]
    await few.sender.comm.send_event(TasksChangedEvent(ids=("long",), change="added"))
    await few.store.next_write()
    (logged,) = [r.getMessage() for r in caplog.records if "not planned" in r.getMessage()]
    assert logged.startswith("task long (?) not planned: longer (")


async def test_every_plan_is_announced_with_its_tasks_in_slot_order(few: Setup) -> None:
    heard: list[ScheduleChangedEvent] = []

    async def on_schedule_changed(event: ScheduleChangedEvent, sender: str) -> None:
        heard.append(event)

    await few.sender.comm.register_event(ScheduleChangedEvent, on_schedule_changed)
    await few.sender.comm.send_event(TasksChangedEvent(ids=("a",), change="changed"))
    await few.store.next_write()
    await wait_for(lambda: bool(heard), 10.0, clock=few.scheduler.clock, message="the plan announced")
    assert heard[-1].ids == tuple(slot.task_id for slot in few.store.slots)


async def test_a_task_added_is_planned_at_once_on_the_event(few: Setup) -> None:
    clock = few.scheduler.clock
    new = SchedulableBlock(id="new", priority=5.0, duration_s=600.0, target=Target(ra=60.0, dec=80.0))
    few.archive.blocks.append(new)
    added = clock.now()
    await few.sender.comm.send_event(TasksChangedEvent(ids=("new",), change="added"))
    await few.store.next_write()
    plan = await few.scheduler.get_plan()
    assert plan is not None and "new" in {slot.task_id for slot in plan.slots}
    reaction = (plan.planned_at - added).total_seconds()
    available = (clock.now() - added).total_seconds()
    # The re-plan starts on the event (the poll is an hour away); the plan is ready after the
    # solve, which a virtual clock charges at its modelled cost (WORK_COSTS["schedule"]).
    print(
        f"\ntask added -> re-planned with it: {reaction:.2f} clock s"
        f" (plan ready after {available:.1f} clock s)"
    )
    assert reaction <= 2.0


async def test_a_device_fault_plans_the_task_again_after_a_doubling_back_off(few: Setup) -> None:
    clock = few.scheduler.clock
    task = few.store.slots[0].task_id
    for fault, backoff in enumerate((300.0, 600.0), start=1):
        at = clock.now()
        event = TaskFailedEvent(
            name=task, id=task, reason="camera is not idle", retryable=True, device_fault=True
        )
        await few.sender.comm.send_event(event)
        await few.store.next_write()
        (slot,) = [slot for slot in few.store.slots if slot.task_id == task]
        assert slot.start >= at + timedelta(seconds=backoff), f"fault {fault}"
    await few.sender.comm.send_event(
        TaskFailedEvent(name=task, id=task, reason="camera is not idle", device_fault=True)
    )
    await few.store.next_write()
    plan = await few.scheduler.get_plan()
    assert plan is not None and task not in {slot.task_id for slot in plan.slots}
    assert {u.task_id: u.reason for u in plan.unplanned}[task] == (
        "left out after 3 device faults (camera is not idle)"
    )


async def test_a_device_fault_is_not_a_failure_of_the_task(few: Setup) -> None:
    """Without device_fault and retryable, the task is dropped for the night, as before."""
    task = few.store.slots[0].task_id
    await few.sender.comm.send_event(TaskFailedEvent(name=task, id=task, reason="bad script"))
    await few.store.next_write()
    plan = await few.scheduler.get_plan()
    assert (
        plan is not None
        and {u.task_id: u.reason for u in plan.unplanned}[task] == "failed tonight (bad script)"
    )
