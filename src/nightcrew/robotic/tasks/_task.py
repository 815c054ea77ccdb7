"""A task: one request of a request group, with its id and status, as archives hand it out."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence

from pydantic import Field

from nightcrew.robotic.tasks._base import Integer, Number, TaskModel
from nightcrew.robotic.tasks._cadence import cadence_visit
from nightcrew.robotic.tasks._request import ObservationType, Request, RequestGroup
from nightcrew.robotic.tasks._state import SCHEDULABLE_STATES, TaskState, TaskStatus

__all__ = ["Task", "cadence_progress", "cadence_summaries", "tasks_of_group"]


class Task(TaskModel):
    """One request with what the scheduler and the runner need from its group.

    Args:
        id: The archive's id of the task (unique in the archive).
        group_id: The archive's id of the request group.
        name: The group's name.
        proposal: The group's proposal.
        observation_type: The group's observation type.
        priority: The group's priority.
        ipp: The group's intra-proposal priority.
        request_index: Position of the request in its group (0-based).
        request: What to do.
        status: State, reason and progress.
    """

    id: str = Field(min_length=1)
    group_id: str
    name: str
    proposal: str
    observation_type: ObservationType = ObservationType.NORMAL
    priority: Number = Field(default=1.0, gt=0.0)
    ipp: Number = 1.0
    request_index: Integer = 0
    request: Request
    status: TaskStatus = Field(default=TaskStatus())

    @property
    def state(self) -> TaskState:
        """The task's state."""
        return self.status.state

    @property
    def effective_priority(self) -> float:
        """Priority scaled by the IPP: what the scheduler weighs."""
        return self.priority * self.ipp

    @property
    def schedulable(self) -> bool:
        """Whether the state lets the scheduler place it (windows are not looked at)."""
        return self.status.state in SCHEDULABLE_STATES

    def with_status(self, status: TaskStatus) -> Task:
        """A copy with another status."""
        return self.model_copy(update={"status": status})


def tasks_of_group(
    group: RequestGroup, group_id: str, task_ids: Sequence[str], statuses: Sequence[TaskStatus] | None = None
) -> list[Task]:
    """One task per request of ``group``, with the given ids (and statuses, default PENDING)."""
    if len(task_ids) != len(group.requests):
        raise ValueError(f"{len(group.requests)} requests need as many task ids, got {len(task_ids)}")
    return [
        Task(
            id=task_id,
            group_id=group_id,
            name=group.name,
            proposal=group.proposal,
            observation_type=group.observation_type,
            priority=group.priority,
            ipp=group.ipp,
            request_index=index,
            request=request,
            status=statuses[index] if statuses is not None else TaskStatus(),
        )
        for index, (task_id, request) in enumerate(zip(task_ids, group.requests, strict=True))
    ]


def cadence_progress(task: Task, group: Sequence[Task]) -> str | None:
    """How far the cadence of ``task`` has come, from its ``group``'s tasks (the visits, with
    others); None when the task is no cadence visit. E.g. ``visit 2 of 4; 1 done, 2 pending, 1 expired``."""
    cadence = task.request.cadence
    if cadence is None:
        return None
    visit, count = cadence_visit(cadence, task.request.first_start)
    return f"visit {visit} of {count}; {_states([t for t in group if t.request.cadence == cadence])}"


def cadence_summaries(tasks: Iterable[Task]) -> list[tuple[str, str]]:
    """``(group name, progress)`` of every cadence among ``tasks``, in the order of their first
    visit, e.g. ``("RZ Cas", "1 of 4 visits completed; 1 completed, 3 pending")``."""
    cadences: dict[tuple[str, int], tuple[str, int, list[Task]]] = {}
    for task in tasks:
        cadence = task.request.cadence
        if cadence is None:
            continue
        visit, count = cadence_visit(cadence, task.request.first_start)
        # A group may hold two cadences: each is known by the request index of its first visit.
        first = (task.group_id, task.request_index - visit + 1)
        cadences.setdefault(first, (task.name, count, []))[2].append(task)
    summaries = []
    for name, count, visits in cadences.values():
        done = sum(t.state is TaskState.COMPLETED for t in visits)
        summaries.append((name, f"{done} of {count} visits completed; {_states(visits)}"))
    return summaries


def _states(tasks: Sequence[Task]) -> str:
    states = Counter(t.state.value.lower() for t in tasks)
    return ", ".join(f"{states[name]} {name}" for name in sorted(states))
