"""The alerts module: subscribes to a VOEvent broker and turns notices into rapid-response requests.

For each VOEvent the broker sends (:class:`BrokerSubscription`, pygcn's client):

* it is read (:func:`parse_notice`); a malformed one, or one with coordinates out of range, is one
  WARNING line and nothing else; the listener keeps listening;
* a notice already seen (same IVORN) is ignored; notices about one event share one request (the
  event's thread: its citations, or GCN's ``TrigID`` within its stream; see ``_threads``);
* a retraction cancels the retracted event's request, stopping it if it runs;
* otherwise the rules (:class:`AlertRules`) make a request group, or say in one INFO line why not
  (role, type, error circle larger than the field allows, not observable soon). A notice that
  supersedes an earlier one, or a follow-up with a smaller error radius, cancels the event's
  earlier request and adds the new one: the request moves.
* A new request is stored in the task archive, and a TasksChangedEvent (the scheduler plans again)
  and a RapidResponseEvent (the mastermind may pre-empt a running task) are sent at once.

Each request names its notice and event in its ``observation_note``: at a start the listener reads
them back from the archive, so after a restart an update still moves its event's request.
"""

from __future__ import annotations

import logging
from typing import Any

from pydantic import ValidationError

from nightcrew.errors import ConfigError
from nightcrew.events import RapidResponseEvent, TasksChangedEvent
from nightcrew.modules.alerts._broker import BrokerSubscription
from nightcrew.modules.alerts._notice import Notice, NoticeError, parse_notice
from nightcrew.modules.alerts._rules import AlertRules, Rejected, request_for
from nightcrew.modules.alerts._threads import EventRequest, Threads, request_note
from nightcrew.modules.module import Module
from nightcrew.modules.robotic._archive_option import built_option
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.tasks import (
    FINAL_STATES,
    InvalidTaskError,
    InvalidTransitionError,
    ObservationType,
    TaskNotFoundError,
    TaskState,
)
from nightcrew.site import Site

__all__ = ["AlertListener"]

log = logging.getLogger(__name__)

#: Most notice IVORNs (and events with a request) remembered, the oldest forgotten first: a bounded
#: memory for a long run (and the most requests read back from the archive at a start).
_REMEMBERED = 10_000


class AlertListener(Module):
    """Turns the notices of a VOEvent broker into rapid-response requests.

    Args:
        broker: The broker's ``host:port`` (its VOEvent Transport Protocol broadcast port).
        archive: The task archive the requests go to (an object or its description): the one the
            scheduler and the mastermind read.
        rules: Which notices become requests and what is observed (:class:`AlertRules`).
        ivorn: How this listener names itself to the broker.
        **kwargs: Module options (``site`` is required: is the target observable soon?).
    """

    def __init__(
        self,
        *,
        broker: str,
        archive: SqliteTaskArchive | dict[str, Any],
        rules: AlertRules | dict[str, Any],
        ivorn: str = "ivo://nightcrew/alerts",
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        site = self.site
        if site is None:
            raise ConfigError("the alerts module needs the observatory's site (is a target up?)", key="site")
        self._site: Site = site
        host, _, port = broker.rpartition(":")
        if not host or not port.isdigit() or not 0 < int(port) < 65536:
            raise ConfigError(f"expected host:port, got {broker!r}", key="broker")
        try:
            self._rules = rules if isinstance(rules, AlertRules) else AlertRules.model_validate(rules)
        except ValidationError as exc:
            first = exc.errors()[0]
            where = ".".join(str(part) for part in ("rules", *first["loc"]))
            raise ConfigError(first["msg"], key=where) from None
        self._archive_option = built_option(archive, SqliteTaskArchive, "archive", self)
        self._archive: SqliteTaskArchive = self._archive_option.value
        self._broker = BrokerSubscription(host, int(port), ivorn, self._on_voevent)
        self._threads = Threads(_REMEMBERED)

    @property
    def connected(self) -> bool:
        """Whether the broker connection is up."""
        return self._broker.connected.is_set()

    async def open(self) -> None:
        await self._archive_option.open()
        await self._restore()
        await super().open()
        await self._broker.open()

    async def close(self) -> None:
        await self._broker.close()
        await super().close()
        await self._archive_option.close()

    async def _on_voevent(self, payload: bytes) -> None:
        try:
            notice = parse_notice(payload)
        except NoticeError as exc:
            log.warning("%s: ignored a notice: %s", self.name, exc)
            return
        threads = self._threads
        if threads.seen(notice.ivorn):
            log.info("%s: %s: seen already", self.name, notice.ivorn)
            return
        key = threads.key(notice)
        threads.remember(notice.ivorn, key)
        if notice.retraction:
            for retracted in threads.cited_keys(notice, "retraction"):
                await self._cancel(retracted, f"retracted by {notice.ivorn}")
            return
        try:
            group = request_for(notice, self._rules, self._site, self.clock.now(), request_note(notice, key))
        except Rejected as exc:
            log.info("%s: %s: not observed: %s", self.name, notice.ivorn, exc)
            return
        except InvalidTaskError as exc:  # e.g. an exposure plan the notice's target cannot take
            log.warning("%s: %s: no request: %s", self.name, notice.ivorn, exc)
            return
        if not await self._replace_earlier(notice, key):
            return
        tasks = await self._archive.add_request_group(group)
        ids = tuple(task.id for task in tasks)
        threads.made(key, EventRequest(ids[0], notice.error_radius or 0.0))
        log.info(
            "%s: %s: rapid-response request %s at ra %.4f dec %.4f",
            self.name,
            notice.ivorn,
            ids[0],
            notice.ra,
            notice.dec,
        )
        await self.comm.send_event(TasksChangedEvent(ids=ids, change="added"))
        await self.comm.send_event(RapidResponseEvent(ids=ids))

    async def _replace_earlier(self, notice: Notice, key: str) -> bool:
        """Cancel the requests ``notice`` replaces; False: it makes no request (the event has a
        request as good, or one that runs or ran already)."""
        if notice.cites_as("supersedes"):  # all earlier information replaced (several: merged)
            keys = self._threads.cited_keys(notice, "supersedes")
            moved = [await self._cancel(k, f"superseded by {notice.ivorn}", update=True) for k in keys]
            return all(moved)
        earlier = self._threads.request(key)
        if earlier is None:
            return True
        # A follow-up (or a later GCN notice of the trigger): a new measurement, the earlier still
        # valid; the request moves only to a better position.
        if notice.error_radius is not None and notice.error_radius >= earlier.error_radius:
            log.info(
                "%s: %s: request %s kept: error radius %g° is not smaller than its %g°",
                self.name,
                notice.ivorn,
                earlier.task_id,
                notice.error_radius,
                earlier.error_radius,
            )
            return False
        return await self._cancel(key, f"superseded by {notice.ivorn}", update=True)

    async def _cancel(self, key: str, reason: str, *, update: bool = False) -> bool:
        """Cancel the request of event ``key``, if it has one still to do; a retraction stops it
        while it runs (the mastermind keeps the frame in flight). False: an update comes too late
        (its request is observed or being observed), so no new one is made."""
        earlier = self._threads.request(key)
        if earlier is None:
            if not update:
                log.info("%s: %s: no request to cancel", self.name, reason)
            return True
        task_id = earlier.task_id
        try:
            task = await self._archive.get_task(task_id)
            if task.state in FINAL_STATES or (update and task.state is TaskState.RUNNING):
                log.info("%s: %s: request %s is %s already", self.name, reason, task_id, task.state.value)
                return not update
            await self._archive.cancel(task_id, reason)
        except (TaskNotFoundError, InvalidTransitionError) as exc:
            log.warning("%s: %s: could not cancel request %s: %s", self.name, reason, task_id, exc)
            return not update
        self._threads.dropped(key)
        running = " while it ran" if task.state is TaskState.RUNNING else ""
        log.warning("%s: request %s cancelled%s: %s", self.name, task_id, running, reason)
        await self.comm.send_event(TasksChangedEvent(ids=(task_id,), change="cancelled"))
        return True

    async def _restore(self) -> None:
        """Read back the events with a request from the archive (a restart keeps the threads)."""
        rapid, proposal = ObservationType.RAPID_RESPONSE, self._rules.proposal
        tasks = [
            task
            for task in await self._archive.list_tasks()
            if task.proposal == proposal and task.observation_type is rapid
        ]
        tasks.sort(key=lambda task: (len(task.id), task.id))  # ids count up: oldest first
        restored = self._threads.restore(
            (task.id, task.request.observation_note) for task in tasks[-_REMEMBERED:]
        )
        if restored:
            log.info("%s: %d earlier alert requests read back from the archive", self.name, restored)
