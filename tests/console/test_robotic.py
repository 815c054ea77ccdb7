"""The night for the pages: the mastermind's status and the scheduler's plan over RPC, Sun, weather."""

from __future__ import annotations

from collections.abc import Callable
from datetime import datetime, timedelta

import pytest

from nightcrew.astro.sun import sun_altitude
from nightcrew.events import BadWeatherEvent
from nightcrew.modules import Module
from nightcrew.modules.robotic import SchedulerModule
from nightcrew.modules.robotic.mastermind import Mastermind
from nightcrew.modules.sim import SimRoof, SimTelescope
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.scheduler import Night, SchedulableBlock
from nightcrew.robotic.scheduler.ports import MemoryScheduleStore
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks

from .conftest import SITE, VIEWER, VIEWER_PASSWORD, ApiClient, Observatory, eventually, open_socket


class ListArchive:
    """Blocks in a list, named after their ids (the scheduler's NamedBlockSource)."""

    def __init__(self, blocks: list[SchedulableBlock]) -> None:
        self.blocks = blocks

    async def get_schedulable_blocks(self) -> list[SchedulableBlock]:
        return list(self.blocks)

    async def block_names(self) -> dict[str, str]:
        return {block.id: f"field {block.id}" for block in self.blocks}


async def test_the_pages_see_what_the_mastermind_does_and_what_the_scheduler_plans(
    observatory: Observatory, archive: SqliteTaskArchive, clients: Callable[[str], ApiClient]
) -> None:
    now = observatory.clock.now()
    blocks = synthetic_blocks(Night(now, now + timedelta(hours=8), SITE), 6, seed=11)
    scheduler = await observatory.start(
        SchedulerModule,
        "scheduler",
        archive=ListArchive(blocks),
        store=MemoryScheduleStore(),
        time_limit_s=2.0,
    )
    await observatory.start(SimRoof, "roof")
    await observatory.start(SimTelescope, "telescope")
    await observatory.start(
        Mastermind,
        "mastermind",
        archive=archive,
        runner=TaskRunner(scripts={}),
        weather=None,
        poll_interval=5.0,
    )
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(VIEWER, VIEWER_PASSWORD)
    await eventually(lambda: scheduler.schedule is not None, "the first plan")

    async def looked() -> bool:
        status = (await client.get("/api/robotic"))[1]["mastermind"]["status"]
        return status is not None and status["sun_altitude"] is not None

    await eventually(looked, "the mastermind's first look at the world")
    sender = await observatory.start(Module, "safety")
    await sender.comm.send_event(BadWeatherEvent(reason="rain"))

    status, view = await client.get("/api/robotic")
    assert status == 200
    master = view["mastermind"]
    assert master["module"] == "mastermind"
    state = master["status"]
    assert state["running"] is True and state["task"] is None
    assert state["action"] in ("wait", "close_and_park")
    assert state["weather_good"] is False  # no weather module: unknown is bad
    expected_sun = sun_altitude(
        SITE.latitude, SITE.longitude, datetime.fromisoformat(state["time"]).timestamp()
    )
    assert state["sun_altitude"] == pytest.approx(expected_sun, abs=0.5)

    plan = view["scheduler"]["plan"]
    assert scheduler.schedule is not None
    assert plan["solver"] == "mip" and plan["objective"] == pytest.approx(scheduler.schedule.objective)
    assert [s["task_id"] for s in plan["slots"]] == [s.task_id for s in scheduler.schedule.slots]
    priorities = {b.id: b.priority for b in blocks}
    assert all(s["priority"] == priorities[s["task_id"]] for s in plan["slots"])
    assert all(s["name"] == f"field {s['task_id']}" for s in plan["slots"])

    sun = view["sun"]
    assert sun[0]["time"] <= state["time"] <= sun[-1]["time"]
    assert datetime.fromisoformat(sun[1]["time"]) - datetime.fromisoformat(sun[0]["time"]) == timedelta(
        minutes=5
    )
    await eventually(lambda: console.weather_verdicts.as_list(), "the bad weather heard")
    assert (await client.get("/api/robotic"))[1]["weather"][-1]["good"] is False

    socket = await open_socket(client)
    pushed = await socket.wait_for(lambda m: m["type"] == "robotic", "the robotic status pushed")
    assert pushed["mastermind"]["module"] == "mastermind"
    status, sky = await client.get("/api/sky")
    assert status == 200 and -90 <= sky["moon"]["alt"] <= 90 and 0 <= sky["moon"]["illumination"] <= 1


async def test_without_robotic_modules_the_view_is_empty_but_there(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(VIEWER, VIEWER_PASSWORD)
    status, view = await client.get("/api/robotic")
    assert status == 200 and view["mastermind"] is None and view["scheduler"] is None
    assert len(view["sun"]) == 14 * 12 + 1  # 2 h before to 12 h after now, every 5 min
