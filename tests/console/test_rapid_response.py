"""A RAPID_RESPONSE request added in the console pre-empts: the console announces it with a
RapidResponseEvent sent in the person's role (``console:operator``), which the starting policy
trusts, where the console's own account (an observer) is refused. Over the HTTP API; the point is
the policy, not the browser."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml

from nightcrew.events import RapidResponseEvent
from nightcrew.modules import Module
from nightcrew.security import read_audit, starting_policy

from .conftest import OPERATOR, OPERATOR_PASSWORD, PATIENCE, ApiClient
from .test_policy_roles import _SecuredObservatory  # the console's observatory with a policy file
from .test_tasks import ARCHIVE_CLASS, group


class Mastermind(Module):
    """Stands for the mastermind: keeps the RapidResponseEvents the policy lets through."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.heard: asyncio.Queue[tuple[RapidResponseEvent, str]] = asyncio.Queue()

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(RapidResponseEvent, self.on_rapid_response)

    async def on_rapid_response(self, event: RapidResponseEvent, sender: str) -> None:
        self.heard.put_nowait((event, sender))


async def test_an_operator_adding_a_rapid_response_request_in_the_console_announces_it(
    tmp_path: Path, clients: Callable[[str], ApiClient]
) -> None:
    # The policy `nightcrew init` writes for these modules and this operator.
    policy = starting_policy(["console", "mastermind"], {OPERATOR: "operator"})
    (tmp_path / "policy.yaml").write_text(yaml.safe_dump(policy))
    observatory = _SecuredObservatory(tmp_path / "policy.yaml", tmp_path / "audit.jsonl")
    try:
        mastermind = await observatory.start(Mastermind, "mastermind")
        tasks = {"class": ARCHIVE_CLASS, "path": str(tmp_path / "tasks.sqlite"), "poll_interval": 0}
        console = await observatory.start_console(tasks=tasks)
        operator = clients(console.url)
        assert (await operator.login(OPERATOR, OPERATOR_PASSWORD))[0] == 200

        # A normal request announces nothing; a rapid-response one does, for the operator.
        assert (await operator.post("/api/tasks", group("Pleiades", 56.75, 24.12)))[0] == 201
        urgent = group("GRB 240115A", 66.75, 15.87, observation_type="RAPID_RESPONSE", priority=50)
        status, added = await operator.post("/api/tasks", urgent)
        assert status == 201, added
        event, sender = await asyncio.wait_for(mastermind.heard.get(), PATIENCE)
        assert event.ids == tuple(task["id"] for task in added["tasks"]) and sender == "console"

        # The console's own account is an observer: as itself it could not pre-empt.
        await console.comm.send_event(RapidResponseEvent(ids=event.ids))
        refused = read_audit(tmp_path / "audit.jsonl", method="RapidResponseEvent")
        assert [(r.caller, r.outcome) for r in refused] == [("console", "forbidden")]
        assert mastermind.heard.empty()
    finally:
        await observatory.close()
