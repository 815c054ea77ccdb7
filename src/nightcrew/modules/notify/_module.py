"""The part of every chat module that is not the transport: commands, forwarding, rate limits.

A transport (Telegram, XMPP chat) subclasses :class:`ChatModule`, hands every line a person sends
to :meth:`ChatModule.received` and implements :meth:`ChatModule._send`. Log records (LogEvents of
every module) at or above each person's level and the chosen events go to every logged-in person,
through one :class:`~nightcrew.modules.notify._outbox.Outbox` each, sent by one task each at the
rate limit's pace: a flood never blocks the module, and what is dropped is said.
"""

from __future__ import annotations

import asyncio
import logging
import time
from abc import abstractmethod
from collections.abc import Coroutine, Mapping
from pathlib import Path
from typing import Any

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import (
    BadWeatherEvent,
    Event,
    LogEvent,
    ModuleStateChangedEvent,
    RoofClosedEvent,
    SafetyAlarmEvent,
    TaskFailedEvent,
    event_by_name,
)
from nightcrew.interfaces import ModuleState
from nightcrew.modules.module import Module
from nightcrew.modules.notify._commands import LOG_LEVELS, level_number
from nightcrew.modules.notify._dispatch import CommandDispatcher, Session
from nightcrew.modules.notify._outbox import IncomingLimit, Outbox, RateLimit, TokenBucket
from nightcrew.modules.notify._saved import load_sessions, save_sessions, sessions_text
from nightcrew.modules.notify._text import describe_event
from nightcrew.modules.notify._users import ChatUser

__all__ = ["DEFAULT_EVENTS", "INCOMING_LIMIT", "STALE_AFTER", "ChatModule"]

log = logging.getLogger(__name__)

#: Events sent to people unless configured otherwise: trouble an operator must hear of.
DEFAULT_EVENTS = (
    BadWeatherEvent,
    RoofClosedEvent,
    TaskFailedEvent,
    ModuleStateChangedEvent,
    SafetyAlarmEvent,
)
#: Records of the chat modules themselves are not forwarded: a chat that fails to send would
#: otherwise report its failure to the other chat, and back.
_OWN_LOGGERS = "nightcrew.modules.notify"
_SEND_ATTEMPTS = 3
#: Wall seconds after which a line is too old to act on.
STALE_AFTER = 120.0
#: Lines one sender may send (a person types far fewer; a script trying secrets, more).
INCOMING_LIMIT = RateLimit(messages=30, per=60.0)


class _Recipient:
    """A logged-in person's outbox, rate limit and sender task."""

    def __init__(self, session: Session, limit: RateLimit) -> None:
        self.session = session
        self.outbox = Outbox(limit.queue)
        self.bucket = TokenBucket(limit, time.monotonic())
        self.waiting = asyncio.Event()
        self.task: asyncio.Task[None] | None = None


class ChatModule(Module):
    """Base of the chat modules (see docs/security.md#notifications).

    Args:
        users: The people, ``{key: {account: NAME, secret_hash: HASH}}``: the key is the person on
            the chat, the account theirs in the access policy, the hash from
            ``nightcrew console --hash-password``.
        log_level: Least level of forwarded log records for a new session (``/loglevel`` changes it).
        events: Names of the events sent to people (default: bad weather, roof closed, task
            failed, module error, safety alarm).
        rate_limit: ``{messages: 20, per: 60, queue: 200}``: messages per wall seconds to one person,
            lines waiting for them at most.
        sessions: A file where sessions are kept across restarts (without it, a restart logs
            everybody out and nobody hears of trouble until they log in again).
        **kwargs: Module options.
    """

    channel = "chat"

    def __init__(
        self,
        *,
        users: Mapping[str, ChatUser],
        log_level: str = "WARNING",
        events: list[str] | None = None,
        rate_limit: RateLimit | dict[str, Any] | None = None,
        sessions: str | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not isinstance(log_level, str) or log_level.upper() not in LOG_LEVELS:
            raise ConfigError(f"must be one of {', '.join(LOG_LEVELS)}, got {log_level!r}", key="log_level")
        self._events = _event_types(events)
        if isinstance(rate_limit, dict):
            unknown = set(rate_limit) - {"messages", "per", "queue"}
            if unknown:
                raise ConfigError(f"unknown keys {', '.join(sorted(unknown))}", key="rate_limit")
            rate_limit = RateLimit(**rate_limit)
        self._limit = rate_limit or RateLimit()
        self._sessions_file = Path(sessions) if sessions else None
        self._saved_text: str | None = None
        self._recipients: dict[str, _Recipient] = {}
        self._handling: set[asyncio.Task[None]] = set()
        self._incoming = IncomingLimit(INCOMING_LIMIT)
        self._closing = False
        self.dispatcher = CommandDispatcher(
            self.channel,
            users,
            lambda: self.comm,
            default_level=log_level.upper(),
            on_login=self._start_sending,
            on_logout=self._stop_sending,
        )

    # --- life cycle ----------------------------------------------------------------------------

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        if self.comm.policy is None:
            log.warning("%s: no access policy: every logged-in person may call everything", self.name)
        await self.comm.register_event(LogEvent, self.on_log)
        for event_type in self._events:
            await self.comm.register_event(event_type, self.on_event)
        if self._sessions_file is not None:
            for user, address, level in load_sessions(self._sessions_file, self.dispatcher.users):
                self.dispatcher.restore(user, address, level)
            self._saved_text = sessions_text(self.dispatcher.sessions.values())

    async def close(self) -> None:
        self._closing = True  # lines still coming in while the transport stops are not answered
        tasks = [r.task for r in self._recipients.values() if r.task is not None] + list(self._handling)
        self._recipients.clear()
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        await super().close()

    # --- what transports call and provide ------------------------------------------------------

    def received(self, key: str, address: str, text: str, *, age: float = 0.0) -> None:
        """A line from person ``key`` (reply to ``address``), sent ``age`` wall seconds ago;
        answered in a task of its own, so that a long call never holds up the transport.

        Lines beyond :data:`INCOMING_LIMIT` from one sender are dropped unanswered: a flood of
        lines must not become a flood of replies. Lines older than :data:`STALE_AFTER` are not
        acted on: the servers keep what was sent while nobody listened, and an old
        ``/exec roof.open_roof()`` must not run hours later.
        """
        if self._closing or not self._incoming.allows(key, time.monotonic()):
            return
        if age > STALE_AFTER:
            note = f"Not done: sent {age:.0f} s ago, while nobody listened. Send it again."
            work: Coroutine[Any, Any, None] = self._deliver(address, note)
        else:
            work = self._answer(key, address, text)
        task = asyncio.get_running_loop().create_task(work)
        self._handling.add(task)
        task.add_done_callback(self._handling.discard)

    @abstractmethod
    async def _send(self, address: str, text: str) -> None:
        """Send ``text`` to ``address``; raise NightcrewError when it cannot go (it is retried)."""

    async def _answer(self, key: str, address: str, text: str) -> None:
        try:
            reply = await self.dispatcher.handle(key, address, text)
        except Exception:
            log.exception("%s: answering a message failed", self.name)
            reply = "Internal error; nothing more was done."
        self._save_sessions()
        await self._deliver(address, reply)

    def _save_sessions(self) -> None:
        if self._sessions_file is None:
            return
        text = sessions_text(self.dispatcher.sessions.values())
        if text != self._saved_text:
            try:
                save_sessions(self._sessions_file, text)
            except OSError as exc:
                log.warning("%s: cannot save the sessions to %s: %s", self.name, self._sessions_file, exc)
                return
            self._saved_text = text

    # --- forwarding ----------------------------------------------------------------------------

    async def on_log(self, event: LogEvent, sender: str) -> None:
        if event.logger.startswith(_OWN_LOGGERS):
            return
        number = logging.getLevelName(event.level)
        line = f"{event.level} {sender}: {event.message}"
        for recipient in list(self._recipients.values()):
            if isinstance(number, int) and number >= level_number(recipient.session.level):
                recipient.outbox.put_record(event.level, line)
                recipient.waiting.set()

    async def on_event(self, event: Event, sender: str) -> None:
        line = describe_event(event, sender)
        if line is None:
            return
        for recipient in list(self._recipients.values()):
            recipient.outbox.put_event(line)
            recipient.waiting.set()

    def _start_sending(self, session: Session) -> None:
        if self._closing:
            return
        recipient = _Recipient(session, self._limit)
        self._recipients[session.user.key] = recipient
        recipient.task = asyncio.get_running_loop().create_task(self._send_loop(recipient))

    def _stop_sending(self, session: Session) -> None:
        recipient = self._recipients.pop(session.user.key, None)
        if recipient is not None and recipient.task is not None:
            recipient.task.cancel()

    async def _send_loop(self, recipient: _Recipient) -> None:
        """Sends what waits for one person, at the rate limit's pace (wall time: people's time)."""
        while True:
            await recipient.waiting.wait()
            recipient.waiting.clear()
            while len(recipient.outbox) or recipient.outbox.dropped:
                delay = recipient.bucket.wait_time(time.monotonic())
                if delay > 0:
                    await asyncio.sleep(delay)  # the rate limit is wall time
                message = recipient.outbox.take_message()
                if message is None:
                    break
                recipient.bucket.take(time.monotonic())
                await self._deliver(recipient.session.address, message)

    async def _deliver(self, address: str, text: str) -> None:
        for attempt in range(_SEND_ATTEMPTS):
            try:
                await self._send(address, text)
                return
            except NightcrewError as exc:
                if attempt == _SEND_ATTEMPTS - 1:
                    log.warning("%s: dropped a message to %s: %s", self.name, address, exc.message)
                    return
                await asyncio.sleep(2.0**attempt)


def _event_types(names: list[str] | None) -> tuple[type[Event], ...]:
    if names is None:
        return DEFAULT_EVENTS
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        raise ConfigError("expected a list of event names", key="events")
    found = []
    for name in names:
        event_type = event_by_name(name)
        if event_type is None:
            raise ConfigError(f"unknown event '{name}'", key="events")
        found.append(event_type)
    return tuple(found)
