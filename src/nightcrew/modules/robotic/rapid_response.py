"""The mastermind's rapid-response requests: the announced tasks read from the archive, and the one
to run now (the choice is :class:`~nightcrew.robotic.mastermind.RapidResponse`'s); and the running
task withdrawn (a retracted alert's request cancelled while it runs)."""

from __future__ import annotations

from collections.abc import Iterable
from datetime import datetime

from nightcrew.robotic.archives import TaskArchive
from nightcrew.robotic.mastermind import RapidResponse
from nightcrew.robotic.tasks import Task, TaskNotFoundError, TaskState

__all__ = ["AnnouncedTasks", "Withdrawals"]


class AnnouncedTasks:
    """Rapid-response tasks announced to the mastermind, looked up in ``archive`` when asked."""

    def __init__(self, archive: TaskArchive, rapid: RapidResponse) -> None:
        self._archive, self.rapid = archive, rapid

    async def to_run(self, running: Task | None, now: datetime) -> Task | None:
        """The announced task to run now instead of ``running`` (None: nothing runs), if any;
        tasks no longer to do are forgotten."""
        if not self.rapid.announced:
            return None
        candidates: list[Task] = []
        gone: list[str] = []
        for task_id in self.rapid.announced:
            try:
                task = await self._archive.get_task(task_id)
            except TaskNotFoundError:
                gone.append(task_id)
                continue
            if task.schedulable:
                candidates.append(task)
            else:
                gone.append(task_id)
        self.rapid.forget(gone)
        return self.rapid.choose(candidates, running, now)


class Withdrawals:
    """Tasks cancelled in the archive while they run (a retracted alert, an operator's cancel): the
    running one is stopped at once, its frame in flight kept, as for a pre-emption.

    A ``TasksChangedEvent`` saying "cancelled" is only the cue: the archive says whether the task
    really is CANCELED (anyone may send that event; only the archive's word stops a task).
    """

    def __init__(self, archive: TaskArchive) -> None:
        self._archive = archive
        self._cancelled: dict[str, str] = {}  # task id -> the cancellation's reason

    async def heard(self, ids: Iterable[str], running: Task | None) -> bool:
        """Tasks ``ids`` were said to be cancelled; True if the ``running`` one really is."""
        if running is None or running.id not in ids:
            return False
        try:
            task = await self._archive.get_task(running.id)
        except TaskNotFoundError:
            return False
        if task.state is not TaskState.CANCELED:
            return False
        self._cancelled = {task.id: task.status.reason or "no reason given"}
        return True

    def cause(self, running: Task | None) -> str | None:
        """Why ``running`` must stop (its cancellation), or None."""
        reason = None if running is None else self._cancelled.get(running.id)
        return None if reason is None else f"its cancellation ({reason})"
