"""The alerts module: subscribes to a VOEvent broker and turns notices into rapid-response requests.

For each VOEvent the broker sends (:class:`BrokerSubscription`, pygcn's client):

* it is read (:func:`parse_notice`); a malformed one, or one with coordinates out of range, is one
  WARNING line and nothing else; the listener keeps listening;
* a notice already seen (same IVORN) is ignored; notices about one event (citing it, or with the
  same GCN ``TrigID``) share one request;
* a retraction cancels the event's request;
* otherwise the rules (:class:`AlertRules`) make a request group, or say in one INFO line why not
  (role, type, error circle larger than the field allows, not observable soon). An update (a
  refined position) cancels the event's earlier request and adds the new one: the request moves.
* A new request is stored in the task archive, and a TasksChangedEvent (the scheduler plans again)
  and a RapidResponseEvent (the mastermind may pre-empt a running task) are sent at once.
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
from nightcrew.modules.module import Module
from nightcrew.modules.robotic._archive_option import built_option
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.tasks import (
    FINAL_STATES,
    InvalidTaskError,
    InvalidTransitionError,
    TaskNotFoundError,
    TaskState,
)
from nightcrew.site import Site

__all__ = ["AlertListener"]

log = logging.getLogger(__name__)

#: Most notice IVORNs (and events with a request) remembered, the oldest forgotten first: a bounded
#: memory for a long run.
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
        self._event_of: dict[str, str] = {}  # notice IVORN -> the event it is about (its key)
        self._task_of: dict[str, str] = {}  # event key -> id of its request's task

    @property
    def connected(self) -> bool:
        """Whether the broker connection is up."""
        return self._broker.connected.is_set()

    async def open(self) -> None:
        await self._archive_option.open()
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
        if notice.ivorn in self._event_of:
            log.info("%s: %s: seen already", self.name, notice.ivorn)
            return
        key = self._remember(notice)
        if notice.retraction:
            await self._cancel(key, f"retracted by {notice.ivorn}")
            return
        try:
            group = request_for(notice, self._rules, self._site, self.clock.now())
        except Rejected as exc:
            log.info("%s: %s: not observed: %s", self.name, notice.ivorn, exc)
            return
        except InvalidTaskError as exc:  # e.g. an exposure plan the notice's target cannot take
            log.warning("%s: %s: no request: %s", self.name, notice.ivorn, exc)
            return
        if not await self._cancel(key, f"superseded by {notice.ivorn}", update=True):
            return
        tasks = await self._archive.add_request_group(group)
        ids = tuple(task.id for task in tasks)
        self._task_of[key] = ids[0]
        if len(self._task_of) > _REMEMBERED:
            self._task_of.pop(next(iter(self._task_of)))
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

    def _remember(self, notice: Notice) -> str:
        """The key of the event ``notice`` is about (the first notice of it, or its trigger id)."""
        trigger = f"trigger {notice.trigger}" if notice.trigger else None
        key = next((self._event_of[i] for i in notice.cited if i in self._event_of), None)
        key = key or trigger or next(iter(notice.cited), None) or notice.ivorn
        self._event_of[notice.ivorn] = key
        if len(self._event_of) > _REMEMBERED:
            self._event_of.pop(next(iter(self._event_of)))
        return key

    async def _cancel(self, key: str, reason: str, *, update: bool = False) -> bool:
        """Cancel the request of event ``key``, if it has one still to do. False: an update comes
        too late (its request is observed or being observed), so no new one is made."""
        task_id = self._task_of.get(key)
        if task_id is None:
            if not update:
                log.info("%s: %s: no request to cancel", self.name, reason)
            return True
        try:
            task = await self._archive.get_task(task_id)
            if task.state in FINAL_STATES or task.state is TaskState.RUNNING:
                log.info("%s: %s: request %s is %s already", self.name, reason, task_id, task.state.value)
                return not update
            await self._archive.cancel(task_id, reason)
        except (TaskNotFoundError, InvalidTransitionError) as exc:
            log.warning("%s: %s: could not cancel request %s: %s", self.name, reason, task_id, exc)
            return not update
        del self._task_of[key]
        log.warning("%s: request %s cancelled: %s", self.name, task_id, reason)
        await self.comm.send_event(TasksChangedEvent(ids=(task_id,), change="cancelled"))
        return True
