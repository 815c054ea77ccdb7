"""Why a task is (not) in a night's plan, computed offline from the tasks alone (``tasks why``).

The same blocks, scheduler and explanation as the scheduler module's (:func:`~.blocks.every_block`,
:meth:`Scheduler.schedule` and :meth:`Scheduler.explain`), for a whole night planned at once: what
the scheduler would decide from the evening on, not what it decided after the night's events.
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import datetime

from nightcrew.robotic.scheduler import Night, Scheduler
from nightcrew.robotic.scheduler.sky import GridFit
from nightcrew.robotic.tasks._state import SCHEDULABLE_STATES
from nightcrew.robotic.tasks._task import Task
from nightcrew.robotic.tasks.blocks import every_block

__all__ = ["why_not_planned"]


def why_not_planned(
    task: Task, tasks: Sequence[Task], night: Night, scheduler: Scheduler, *, now: datetime | None = None
) -> str:
    """One line: when ``task`` is planned in ``night`` among ``tasks``, or why it is not.

    Args:
        task: The task asked about.
        tasks: Every task that competes for the night (``task`` among them or not).
        night: The night to plan.
        scheduler: Its settings (time slice, slew overhead, solver).
        now: Plan from this time on (default: the night's start).
    """
    if task.state not in SCHEDULABLE_STATES:
        return f"not planned: it is {task.state.value}" + (
            f" ({task.status.reason})" if task.status.reason else ""
        )
    others = [t for t in tasks if t.id != task.id and t.state in SCHEDULABLE_STATES]
    fit = GridFit(step_s=scheduler.step_s, slew_overhead_s=scheduler.slew_overhead_s)
    blocks = every_block([task, *others], night.site, fit=fit)
    schedule = scheduler.schedule(blocks, night, now=now)
    for slot in schedule.slots:
        if slot.task_id == task.id:
            return f"planned {slot.start:%Y-%m-%d %H:%M} - {slot.end:%H:%M} UTC"
    names = {t.id: f"{t.name} ({t.id})" for t in others}
    reasons = scheduler.explain(blocks, night, schedule, now=now, names=names)
    return "not planned: " + reasons.get(task.id, "left out by the solver")
