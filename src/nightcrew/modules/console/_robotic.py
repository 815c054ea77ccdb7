"""The robotic night for the pages: the mastermind's status, the scheduler's plan, Sun and weather.

Asked over RPC (IRobotic, IRoboticScheduler); the weather verdicts are those the console saw.
"""

from __future__ import annotations

from collections import deque
from datetime import datetime, timedelta
from typing import Any

from nightcrew.comm.base import Comm
from nightcrew.errors import NightcrewError
from nightcrew.interfaces import IRobotic, IRoboticScheduler
from nightcrew.modules.console._describe import to_json
from nightcrew.modules.console._directory import ModuleDirectory
from nightcrew.modules.console._sky import sun_curve
from nightcrew.site import Site

__all__ = ["WeatherVerdicts", "robotic_view"]

#: Around now when there is no plan to take the night from.
_BEFORE, _AFTER = timedelta(hours=2), timedelta(hours=12)


class WeatherVerdicts:
    """The good/bad verdicts the console saw, oldest first (a new entry only when it changes)."""

    def __init__(self, size: int = 2000) -> None:
        self._verdicts: deque[dict[str, Any]] = deque(maxlen=size)

    def add(self, time: datetime, good: bool, reason: str = "") -> None:
        """The verdict at clock ``time`` (kept if it differs from the last, and is not older)."""
        if self._verdicts:
            last = self._verdicts[-1]
            if last["good"] == good or datetime.fromisoformat(last["time"]) > time:
                return
        self._verdicts.append({"time": time.isoformat(), "good": good, "reason": reason})

    def as_list(self) -> list[dict[str, Any]]:
        return list(self._verdicts)


async def robotic_view(
    comm: Comm,
    directory: ModuleDirectory,
    *,
    now: datetime,
    site: Site | None,
    task_names: dict[str, str],
    weather: WeatherVerdicts,
) -> dict[str, Any]:
    """The body of ``GET /api/robotic`` (see docs/console-api.md)."""
    mastermind = await _ask(comm, directory, IRobotic, "status", task_names)
    scheduler = await _ask(comm, directory, IRoboticScheduler, "plan", task_names)
    plan = scheduler["plan"] if scheduler is not None else None
    if plan is not None:
        # A re-plan starts its night at the planning time: show the last hours before it too.
        start = min(datetime.fromisoformat(plan["night_start"]), now - _BEFORE)
        end = datetime.fromisoformat(plan["night_end"])
    else:
        start, end = now - _BEFORE, now + _AFTER
    return {
        "time": now.isoformat(),
        "mastermind": mastermind,
        "scheduler": scheduler,
        "sun": sun_curve(site, start, end) if site is not None else [],
        "weather": weather.as_list(),
    }


async def _ask(
    comm: Comm, directory: ModuleDirectory, interface: type[Any], key: str, task_names: dict[str, str]
) -> dict[str, Any] | None:
    entry = directory.first_offering(interface)
    if entry is None:
        return None
    try:
        proxy = await comm.proxy(entry.name, interface)
        value = await (proxy.get_robotic_status() if interface is IRobotic else proxy.get_plan())
    except NightcrewError:
        return {"module": entry.name, key: None}
    answer = to_json(value)
    if interface is IRobotic and answer.get("task"):
        task_names[answer["task"]["id"]] = answer["task"]["name"]
    if interface is IRoboticScheduler and answer is not None:
        for slot in answer["slots"]:
            slot["name"] = slot["name"] or task_names.get(slot["task_id"])
    return {"module": entry.name, key: answer}
