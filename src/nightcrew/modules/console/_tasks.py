"""The console's task archive: its tasks with tonight's plan beside them, and adding and cancelling.

The console opens the archive named in its ``tasks`` option itself (a description such as
``{class: nightcrew.robotic.archives.SqliteTaskArchive, path: tasks.sqlite}``). A request group is
validated by :func:`~nightcrew.robotic.tasks.parse_request_group`, the validator ``nightcrew tasks
add`` uses; nothing is stored when it fails. After a change the console sends a
:class:`~nightcrew.events.TasksChangedEvent` so that the scheduler plans again at once.
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import datetime
from typing import Any, Protocol, runtime_checkable

from nightcrew.comm.base import Comm
from nightcrew.config import build_object, parse_data
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.interfaces import IRoboticScheduler, Plan
from nightcrew.modules.console._directory import ModuleDirectory
from nightcrew.robotic.archives import TaskArchive
from nightcrew.robotic.tasks import (
    FINAL_STATES,
    InvalidTaskError,
    RequestGroup,
    Task,
    TaskProblem,
    estimate_duration,
    parse_request_group,
)

__all__ = ["EditableTaskArchive", "PlanView", "build_task_archive", "latest_plan", "parse_body", "task_rows"]

#: Content types of a request group sent to ``POST /api/tasks``; the value: whether it is JSON.
BODY_TYPES = {
    "application/json": True,
    "application/yaml": False,
    "application/x-yaml": False,
    "text/yaml": False,
}


@runtime_checkable
class EditableTaskArchive(Protocol):
    """What the console needs of a task archive: list its tasks, add a request group, cancel."""

    async def open(self) -> None: ...

    async def close(self) -> None: ...

    async def list_tasks(self) -> list[Task]: ...

    async def add_request_group(self, group: RequestGroup) -> list[Task]: ...

    async def cancel(self, task_id: str, reason: str) -> Task: ...


def build_task_archive(value: EditableTaskArchive | dict[str, Any], owner_clock: Any) -> EditableTaskArchive:
    """The archive ``value`` describes (its "now" the console's clock unless it names a clock)."""
    archive = build_object(value) if isinstance(value, dict) else value
    if not isinstance(archive, EditableTaskArchive):
        raise ConfigError(
            f"{type(archive).__name__} cannot list, add and cancel tasks (use SqliteTaskArchive)", key="tasks"
        )
    if isinstance(value, dict) and "clock" not in value and isinstance(archive, TaskArchive):
        archive.clock = owner_clock  # "now" of a simulated night is the module's clock
    return archive


def parse_body(text: str, content_type: str) -> RequestGroup:
    """The request group in a request body (JSON or YAML, as in a task file).

    Raises:
        InvalidTaskError: The body does not parse, or the group breaks the model (every problem).
    """
    try:
        data = parse_data(text, "the request body", as_json=BODY_TYPES[content_type])
    except ConfigError as exc:  # the same limits as for a task file
        where = f"line {exc.line}: " if exc.line else ""
        raise InvalidTaskError([TaskProblem("", where + exc.message)]) from None
    return parse_request_group(data)


class PlanView:
    """The scheduler's latest plan as the task list needs it: when each task is next planned, and
    why one is left out."""

    def __init__(self, module: str | None, plan: Plan | None, now: datetime) -> None:
        self.module, self.plan = module, plan
        self._next: dict[str, tuple[datetime, datetime]] = {}
        for slot in sorted(plan.slots if plan else (), key=lambda s: s.start):
            if slot.end > now:
                self._next.setdefault(slot.task_id, (slot.start, slot.end))
        self._why = {u.task_id: u.reason for u in (plan.unplanned if plan else ())}

    def describe(self) -> dict[str, Any] | None:
        if self.module is None:
            return None
        planned_at = self.plan.planned_at.isoformat() if self.plan else None
        return {"module": self.module, "planned_at": planned_at}

    def next_slot(self, task_id: str) -> tuple[datetime, datetime] | None:
        return self._next.get(task_id)

    def why_not(self, task_id: str) -> str | None:
        return self._why.get(task_id)


async def latest_plan(comm: Comm, directory: ModuleDirectory) -> tuple[str | None, Plan | None]:
    """(module, plan) of the first online scheduler; (None, None) without one, plan None when it
    has not planned yet or does not answer."""
    entry = directory.first_offering(IRoboticScheduler)
    if entry is None:
        return None, None
    try:
        scheduler = await comm.proxy(entry.name, IRoboticScheduler)
        return entry.name, await scheduler.get_plan()
    except NightcrewError:
        return entry.name, None


def task_rows(tasks: Sequence[Task], plan: PlanView) -> list[dict[str, Any]]:
    """The tasks as ``GET /api/tasks`` lists them (see docs/console-api.md), newest first."""
    return [_row(task, plan) for task in sorted(tasks, key=_newest_first)]


def _newest_first(task: Task) -> tuple[int, str]:
    return (-int(task.id), "") if task.id.isdigit() else (0, task.id)


def _row(task: Task, plan: PlanView) -> dict[str, Any]:
    status, request = task.status, task.request
    # A plan made before the task ended may still hold it: an ended task is planned no more.
    slot = plan.next_slot(task.id) if status.state not in FINAL_STATES else None
    return {
        "id": task.id,
        "group_id": task.group_id,
        "name": task.name,
        "proposal": task.proposal,
        "observation_type": task.observation_type.value,
        "priority": task.effective_priority,
        "telescope_class": request.location.telescope_class,
        "state": status.state.value,
        "reason": status.reason,
        "ended": status.state in FINAL_STATES,
        "windows": [{"start": w.start.isoformat(), "end": w.end.isoformat()} for w in request.windows],
        "configurations": [
            {"type": c.type.value, "target": c.target.name if c.target else None}
            for c in request.configurations
        ],
        "duration_s": estimate_duration(request, progress=status.progress).total_s,
        "started_at": _iso(status.started_at),
        "finished_at": _iso(status.finished_at),
        "next_start": _iso(slot[0] if slot else None),
        "next_end": _iso(slot[1] if slot else None),
        "why_not": plan.why_not(task.id) if task.schedulable and not slot else None,
    }


def _iso(when: datetime | None) -> str | None:
    return when.isoformat() if when is not None else None
