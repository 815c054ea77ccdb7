"""Pure helpers: a task seen as one of its configurations, and that configuration's progress put back."""

from __future__ import annotations

from nightcrew.robotic.tasks import Task, TaskProgress

__all__ = ["configuration_task", "merged_progress"]


def configuration_task(task: Task, index: int) -> Task:
    """``task`` holding only configuration ``index`` (and only that configuration's recorded progress).

    This is what one script runs: it never has to know where its configuration sits in the request.
    """
    request = task.request.model_copy(update={"configurations": (task.request.configurations[index],)})
    status = task.status.model_copy(update={"progress": task.status.progress.of_configuration(index)})
    return task.model_copy(update={"request": request, "status": status})


def merged_progress(progress: TaskProgress, index: int, part: TaskProgress) -> TaskProgress:
    """``progress`` of the whole task with configuration ``index`` replaced by ``part``'s only row
    (and its cut-short frames).

    ``progress`` must have one row per configuration (e.g. from ``TaskProgress.nothing_done``).
    """
    return progress.with_configuration(index, part)
