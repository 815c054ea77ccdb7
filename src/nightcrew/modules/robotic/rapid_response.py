"""The mastermind's rapid-response requests: the announced tasks read from the archive, and the one
to run now (the choice is :class:`~nightcrew.robotic.mastermind.RapidResponse`'s)."""

from __future__ import annotations

from datetime import datetime

from nightcrew.robotic.archives import TaskArchive
from nightcrew.robotic.mastermind import RapidResponse
from nightcrew.robotic.tasks import Task, TaskNotFoundError

__all__ = ["AnnouncedTasks"]


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
