"""A task archive and schedule store backed by an LCO observation portal.

- tasks: ``GET /api/requestgroups/schedulable_requests/`` (one task per request, id = request id);
  a group the task model rejects is logged with its field path and skipped;
- changes: ``GET /api/last_changed/`` polled on the clock; listeners hear of any change;
- schedule: ``POST /api/observations/cancel/`` for this telescope from ``replace_from`` on, then
  ``POST /api/observations/`` with one observation per entry; read back with
  ``GET /api/observations/`` (paginated);
- fate: ``PATCH /api/configurationstatus/<id>/`` per configuration (ATTEMPTED when started;
  COMPLETED / FAILED / NOT_ATTEMPTED with a summary at the end). Progress recorded while running
  stays here until then, and is kept (in memory) for a retry of a FAILED task, which takes only
  what is missing; each observation's summary counts only the exposure time it took itself.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from datetime import datetime, timedelta
from typing import Any

from nightcrew.clock import Clock
from nightcrew.interfaces.quantities import PeriodOrOff
from nightcrew.robotic.archives._base import ScheduleStore, TaskArchive
from nightcrew.robotic.archives._lco_client import LcoPortalClient, PortalError
from nightcrew.robotic.archives._lco_convert import (
    configuration_status_updates,
    observation_document,
    tasks_from_portal,
)
from nightcrew.robotic.archives._local import schedulable_at
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import InvalidTaskError, Task, TaskNotFoundError, TaskProgress, TaskState

__all__ = ["LcoPortalArchive"]

log = logging.getLogger(__name__)


class LcoPortalArchive(TaskArchive, ScheduleStore):
    """Tasks and schedule of one telescope in an LCO observation portal.

    Args:
        url: The portal, e.g. ``https://observe.lco.global``.
        token: API token of an account allowed to schedule (admin).
        site, enclosure, telescope: This telescope's codes in the portal.
        instrument_name: The camera's name in the portal (for the configuration statuses).
        guide_camera_name: The guide camera's name, if guiding.
        telescope_classes: Only requests for these classes (all if empty).
        horizon: How far ahead to ask for schedulable requests.
        clock: Gives "now" and paces the polling.
        poll_interval: Clock seconds between asking the portal for changes; 0: never.
    """

    def __init__(
        self,
        url: str,
        token: str,
        *,
        site: str,
        enclosure: str,
        telescope: str,
        instrument_name: str,
        guide_camera_name: str | None = None,
        telescope_classes: Sequence[str] = (),
        horizon: timedelta = timedelta(days=2),
        clock: Clock | None = None,
        poll_interval: PeriodOrOff = 60.0,
    ) -> None:
        super().__init__(clock=clock)
        self.client = LcoPortalClient(url, token)
        self.site, self.enclosure, self.telescope = site, enclosure, telescope
        self.instrument_name = instrument_name
        self.guide_camera_name = guide_camera_name
        self.telescope_classes = tuple(telescope_classes)
        self.horizon = horizon
        self.poll_interval = poll_interval
        self._tasks: dict[str, Task] = {}
        self._configuration_ids: dict[str, list[int]] = {}
        self._progress_at_start: dict[str, TaskProgress] = {}
        self._last_change = ""

    async def open(self) -> None:
        await self.client.open()
        self._start_polling(self.client.url)

    async def close(self) -> None:
        await self._stop_polling()
        await self.client.close()

    async def check_for_changes(self) -> bool:
        """Whether the portal's request groups changed since the last check (listeners hear)."""
        changed = await self.client.last_changed()
        if changed == self._last_change:
            return False
        self._last_change = changed
        await self._notify()
        return True

    async def get_schedulable_tasks(self) -> list[Task]:
        now = self.clock.now()
        groups = await self.client.schedulable_request_groups(now, now + self.horizon, self.telescope_classes)
        fresh: dict[str, Task] = {}
        for group in groups:
            try:
                converted = tasks_from_portal(group, source=self.client.url)
            except InvalidTaskError as exc:
                log.warning("skipping a request group the task model rejects: %s", exc)
                continue
            self._configuration_ids.update(converted.configuration_ids)
            for task in converted.tasks:
                known = self._tasks.get(task.id)  # keep what we know of a running task
                fresh[task.id] = task if known is None else task.with_status(known.status)
        self._tasks.update(fresh)
        return [task for task in fresh.values() if schedulable_at(task, now)]

    async def get_task(self, task_id: str) -> Task:
        if task_id not in self._tasks:
            await self.get_schedulable_tasks()
        try:
            return self._tasks[task_id]
        except KeyError:
            raise TaskNotFoundError(f"no schedulable request {task_id!r} in {self.client.url}") from None

    async def mark_started(self, task_id: str) -> Task:
        task = await self.get_task(task_id)
        status = task.status.transition(TaskState.RUNNING, at=self.clock.now())
        self._progress_at_start[task_id] = task.status.progress  # a retry goes on from here
        status_ids = await self._configuration_status_ids(task_id)
        if status_ids:
            await self.client.update_configuration_status(status_ids[0], {"state": "ATTEMPTED"})
        return await self._store(task.with_status(status))

    async def record_progress(self, task_id: str, progress: TaskProgress) -> Task:
        task = await self.get_task(task_id)
        progress.check_fits(task.request)
        return await self._store(task.with_status(task.status.with_progress(progress, at=self.clock.now())))

    async def mark_finished(self, task_id: str, progress: TaskProgress) -> Task:
        return await self._finish(task_id, progress, "")

    async def mark_failed(self, task_id: str, reason: str, progress: TaskProgress) -> Task:
        return await self._finish(task_id, progress, reason)

    async def _finish(self, task_id: str, progress: TaskProgress, reason: str) -> Task:
        task = await self.get_task(task_id)
        progress.check_fits(task.request)
        now = self.clock.now()
        state = TaskState.FAILED if reason else TaskState.COMPLETED
        status = task.status.transition(state, at=now, reason=reason, progress=progress)
        start = task.status.started_at or now
        before = self._progress_at_start.pop(task_id, None)
        updates = configuration_status_updates(
            task, progress, reason=reason, start=start, end=now, before=before
        )
        for status_id, update in zip(await self._configuration_status_ids(task_id), updates, strict=False):
            await self.client.update_configuration_status(status_id, update)
        return await self._store(task.with_status(status))

    async def _store(self, task: Task) -> Task:
        self._tasks[task.id] = task
        await self._notify([task.id])
        return task

    async def _configuration_status_ids(self, task_id: str) -> list[int]:
        """The configuration statuses of this telescope's current observation of the request."""
        observations = await self.client.observations(
            {"request_num": task_id, "site": self.site, "telescope": self.telescope}
        )
        current = [o for o in observations if o.get("state") in ("PENDING", "IN_PROGRESS")]
        if not current:
            log.warning("the portal has no pending observation of request %s to update", task_id)
            return []
        # The one under way now, else the next one (a task may be started a little early).
        now = self.clock.now()
        running = [
            o for o in current if datetime.fromisoformat(o["start"]) <= now < datetime.fromisoformat(o["end"])
        ]
        chosen = running[0] if running else min(current, key=lambda o: datetime.fromisoformat(o["start"]))
        return [int(s["id"]) for s in chosen.get("configuration_statuses", [])]

    async def write_schedule(self, entries: Sequence[PlannedSlot], *, replace_from: datetime) -> None:
        documents = []
        for entry in entries:
            if entry.task_id not in self._configuration_ids:
                await self.get_task(entry.task_id)
            documents.append(
                observation_document(
                    entry,
                    self._configuration_ids[entry.task_id],
                    site=self.site,
                    enclosure=self.enclosure,
                    telescope=self.telescope,
                    instrument_name=self.instrument_name,
                    guide_camera_name=self.guide_camera_name,
                )
            )
        until = max([replace_from + self.horizon, *(e.end for e in entries)])
        selection = _telescope(self) | {"start": replace_from.isoformat(), "end": until.isoformat()}
        await self.client.cancel_observations(selection)
        if documents:
            answer = await self.client.submit_observations(documents)
            if answer.get("errors"):
                raise PortalError(f"the portal refused observations: {answer['errors']}")

    async def read_schedule(
        self, *, start: datetime | None = None, end: datetime | None = None
    ) -> list[PlannedSlot]:
        params: dict[str, Any] = _telescope(self) | {"state": "PENDING"}
        if start is not None:
            params["end_after"] = start.isoformat()
        if end is not None:
            params["start_before"] = end.isoformat()
        entries = [
            PlannedSlot(
                str(o["request"]["id"] if isinstance(o["request"], dict) else o["request"]),
                datetime.fromisoformat(o["start"]),
                datetime.fromisoformat(o["end"]),
            )
            for o in await self.client.observations(params)
        ]
        return sorted(entries, key=lambda e: (e.start, e.task_id))


def _telescope(archive: LcoPortalArchive) -> dict[str, Any]:
    return {"site": archive.site, "enclosure": archive.enclosure, "telescope": archive.telescope}
