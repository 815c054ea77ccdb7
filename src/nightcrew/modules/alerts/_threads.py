"""Which event a notice is about, what it asks for, and where that is kept across restarts.

Notices about one event form a thread (VOEvent 2.0, section 3.7): a notice without citations
announces a new event; one citing an earlier notice belongs to that notice's event. The citation
says what it does there:

* ``supersedes``: all the earlier information is replaced: the event's request moves;
* ``followup``: a new, independent measurement, the earlier one still valid: the request moves
  only to a better position (a smaller error radius);
* ``retraction``: the event is withdrawn: its request is cancelled.

GCN's notices cite nothing; a notice of the same stream with the same ``TrigID`` is about the same
burst (a later, refined one, taken as a follow-up), and one whose ``Retraction`` parameter is true
withdraws it. A trigger id is only unique within its stream (Swift's 1001 is not Fermi's).

Each request carries its event in its ``observation_note`` (:func:`request_note`), so a listener
that restarts reads the threads back from the task archive (:func:`read_note`). Pure.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from nightcrew.modules.alerts._notice import Notice

__all__ = ["EventRequest", "Threads", "read_note", "request_note"]

_NOTE = re.compile(r"from VOEvent (?P<ivorn>\S+) \(event (?P<key>.+); error (?P<error>[0-9.eE+-]+) deg\)")


def request_note(notice: Notice, key: str) -> str:
    """The ``observation_note`` of the request made for ``notice`` (about event ``key``)."""
    return f"from VOEvent {notice.ivorn} (event {key}; error {notice.error_radius or 0.0:.6g} deg)"


def read_note(note: str) -> tuple[str, str, float] | None:
    """``(notice ivorn, event key, error radius)`` from a note of :func:`request_note`, else None."""
    match = _NOTE.fullmatch(note.strip())
    if match is None:
        return None
    try:
        return match["ivorn"], match["key"], float(match["error"])
    except ValueError:
        return None


@dataclass(frozen=True)
class EventRequest:
    """The request an event has: its task, and the error radius of the notice it was made from."""

    task_id: str
    error_radius: float


class Threads:
    """Notices seen and the request of each event, the oldest forgotten past ``limit`` of each."""

    def __init__(self, limit: int) -> None:
        self._limit = limit
        self._event_of: dict[str, str] = {}  # notice IVORN -> the event it is about (its key)
        self._requests: dict[str, EventRequest] = {}  # event key -> its latest request

    def seen(self, ivorn: str) -> bool:
        return ivorn in self._event_of

    def key(self, notice: Notice) -> str:
        """The event ``notice`` is about: that of the first cited notice known, else its trigger's
        (``stream#trigger id``), else the first cited IVORN, else its own."""
        known = next((self._event_of[i] for i in notice.cited if i in self._event_of), None)
        trigger = f"{notice.stream}#trigger {notice.trigger}" if notice.trigger else None
        return known or trigger or next(iter(notice.cited), None) or notice.ivorn

    def cited_keys(self, notice: Notice, kind: str) -> list[str]:
        """The events ``notice`` cites as ``kind`` (a retraction without citations: its own event)."""
        keys = [self._event_of.get(ivorn, ivorn) for cite, ivorn in notice.cites if cite == kind]
        return list(dict.fromkeys(keys)) or [self.key(notice)]

    def remember(self, ivorn: str, key: str) -> None:
        _put(self._event_of, ivorn, key, self._limit)

    def request(self, key: str) -> EventRequest | None:
        return self._requests.get(key)

    def made(self, key: str, request: EventRequest) -> None:
        _put(self._requests, key, request, self._limit)

    def dropped(self, key: str) -> None:
        self._requests.pop(key, None)

    def restore(self, notes: Iterable[tuple[str, str]]) -> int:
        """Take back ``(task id, observation note)`` of stored requests, oldest first; how many."""
        count = 0
        for task_id, note in notes:
            read = read_note(note)
            if read is None:
                continue
            ivorn, key, error = read
            self.remember(ivorn, key)
            self.made(key, EventRequest(task_id, error))
            count += 1
        return count


def _put(table: dict[str, Any], key: str, value: Any, limit: int) -> None:
    table.pop(key, None)  # to the end: the newest
    table[key] = value
    if len(table) > limit:
        table.pop(next(iter(table)))
