"""What the mastermind tells a display: its action, the running task's progress, why it waits."""

from __future__ import annotations

from datetime import datetime

from nightcrew.interfaces.robotic import RoboticStatus, RoboticTask
from nightcrew.robotic.mastermind._decide import (
    Action,
    CloseAndPark,
    Conditions,
    Focus,
    OpenUp,
    RunTask,
    Wait,
)
from nightcrew.robotic.mastermind._tasks import planned_exposures
from nightcrew.robotic.tasks import Task, TaskProgress

__all__ = ["robotic_status"]

_ACTION_NAMES: dict[type, str] = {
    RunTask: "run_task",
    OpenUp: "open_up",
    Focus: "focus",
    CloseAndPark: "close_and_park",
    Wait: "wait",
}


def robotic_status(
    now: datetime,
    *,
    running: bool,
    safe: bool = True,
    action: Action | None,
    conditions: Conditions | None,
    task: Task | None,
    progress: TaskProgress,
    task_started: datetime | None,
    task_eta: datetime | None,
) -> RoboticStatus:
    """The status of a mastermind that last decided ``action`` under ``conditions``; ``safe``: since
    robotic mode stopped, the roof was closed and the telescope parked."""
    if not running and not safe:
        name, description = "stopping", "robotic mode is stopped; closing the roof and parking"
    elif not running:
        name, description = "stopped", "robotic mode is stopped"
    elif action is None:
        name, description = "wait", "waiting: looking at the world for the first time"
    else:
        name, description = _ACTION_NAMES[type(action)], action.describe()
    waiting = action if running and isinstance(action, Wait) else None
    current = None
    if task is not None:
        current = RoboticTask(
            id=task.id,
            name=task.name,
            started=task_started,
            eta=task_eta,
            exposures_done=progress.total_exposures,
            exposures_total=planned_exposures(task.request),
        )
    return RoboticStatus(
        time=now,
        running=running,
        action=name,
        description=description,
        waiting_for=waiting.reason if waiting is not None else None,
        waiting_until=waiting.until if waiting is not None else None,
        task=current,
        sun_altitude=conditions.sun_altitude if conditions is not None else None,
        weather_good=conditions.weather_good if conditions is not None else None,
        roof=str(conditions.roof) if conditions is not None else None,
        telescope_ready=conditions.telescope_ready if conditions is not None else None,
    )
