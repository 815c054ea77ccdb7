"""``nightcrew tasks add --comm`` as a real process: the scheduler on Prosody re-plans on its event.

The scheduler runs in this test process on XmppComm with a real clock and polls its database once
an hour, so only the TasksChangedEvent the command sends can bring the new task into a plan soon.
"""

from __future__ import annotations

import asyncio
import contextlib
import io
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import pytest
import yaml

from nightcrew.cli.main import main
from nightcrew.clock import RealClock
from nightcrew.events import RapidResponseEvent
from nightcrew.modules import Module
from nightcrew.modules.robotic import SchedulerModule
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.testing import SITE, wait_for

# The session's Prosody and a room per test, as tests/comm has them (imported to be found here).
from tests.cli.test_operator_xmpp import COMMAND_TIMEOUT, nightcrew, write_operator_comm
from tests.comm.conftest import Network, prosody_network, prosody_server  # noqa: F401

pytestmark = pytest.mark.xmpp


def task_file(path: Path, now: datetime) -> Path:
    """A circumpolar target, any time in the next two days: in the next night's plan."""
    group = {
        "name": "Polaris field",
        "proposal": "test",
        "requests": [
            {
                "location": {"telescope_class": "0m4"},
                "windows": [{"start": now.isoformat(), "end": (now + timedelta(days=2)).isoformat()}],
                "configurations": [
                    {
                        "type": "EXPOSE",
                        "target": {"name": "Polaris field", "ra": 37.95, "dec": 85.0},
                        "constraints": {"min_lunar_distance": 0},
                        "instrument_configs": [{"exposure_time": 60, "exposure_count": 3}],
                    }
                ],
            }
        ],
    }
    path.write_text(yaml.safe_dump(group))
    return path


@pytest.fixture
def network(request: pytest.FixtureRequest) -> Network:
    """Modules in a room of this test's own on the session's Prosody (tests/comm's fixture)."""
    prosody: Network = request.getfixturevalue("prosody_network")
    return prosody


async def test_tasks_add_with_a_comm_is_planned_on_its_event(network: Network, tmp_path: Path) -> None:
    assert network.server is not None
    db = tmp_path / "tasks.sqlite"
    clock = RealClock()
    async with SqliteTaskArchive(db, clock=clock, poll_interval=0) as archive:
        scheduler = await network.start(
            SchedulerModule,
            "scheduler",
            archive=archive,
            store=archive,
            site=SITE,
            clock=clock,
            time_limit_s=5.0,
            poll_interval_s=3600.0,
        )

        async def planned(task_id: str | None) -> bool:
            plan = await scheduler.get_plan()
            return plan is not None and (task_id is None or task_id in {s.task_id for s in plan.slots})

        await wait_for(lambda: planned(None), COMMAND_TIMEOUT, clock=clock, interval=0.05)
        op_file = write_operator_comm(tmp_path / "op.yaml", network.server, network.room)
        tasks = task_file(tmp_path / "polaris.yaml", clock.now())
        done = await nightcrew("tasks", "--db", str(db), "add", str(tasks), "--comm", str(op_file))
        returned = clock.now()
        assert done.code == 0, done.stderr
        assert done.stdout.splitlines()[-1] == "told the scheduler: tasks 1 added"

        await wait_for(lambda: planned("1"), COMMAND_TIMEOUT, clock=clock, interval=0.05)
        plan = await scheduler.get_plan()
        assert plan is not None
        after = (plan.planned_at - returned).total_seconds()
        print(f"\ntasks add --comm: re-planned {after:+.2f} s after the command returned")
        assert after <= 2.0


class RapidResponseListener(Module):
    """Hears RapidResponseEvents, as the mastermind does."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.heard: list[tuple[str, tuple[str, ...]]] = []

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(RapidResponseEvent, self.on_rapid_response)

    async def on_rapid_response(self, event: RapidResponseEvent, sender: str) -> None:
        self.heard.append((sender, event.ids))


async def test_tasks_add_with_a_comm_announces_a_rapid_response_request(
    network: Network, tmp_path: Path
) -> None:
    """docs/rapid-response.md, "Submitting one by hand"."""
    assert network.server is not None
    clock = RealClock()
    listener = await network.start(RapidResponseListener, "mastermind", clock=clock)
    op_file = write_operator_comm(tmp_path / "op.yaml", network.server, network.room)
    tasks = task_file(tmp_path / "too.yaml", clock.now())
    tasks.write_text(tasks.read_text() + "observation_type: RAPID_RESPONSE\n")
    # In this process (a thread with its own loop): the command's start-up is not the point here.
    command = ["tasks", "--db", str(tmp_path / "tasks.sqlite"), "add", str(tasks), "--comm", str(op_file)]
    with contextlib.redirect_stdout(io.StringIO()) as out:
        code = await asyncio.to_thread(main, command)
    assert code == 0
    assert out.getvalue().splitlines()[-1] == "told the mastermind: rapid-response tasks 1"
    await wait_for(lambda: bool(listener.heard), COMMAND_TIMEOUT, clock=clock, interval=0.05)
    assert listener.heard == [("operator", ("1",))]
