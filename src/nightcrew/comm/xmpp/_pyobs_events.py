"""pyobs-core 2.x event bodies ↔ nightcrew event fields (pure; the PubSub plumbing is in _pyobs).

pyobs publishes ``{"type": <class name>, "timestamp": <unix s>, "uuid": …, "data": {fields}}`` as
JSON inside ``<event xmlns='pyobs:event'>``. Events map by class name; docs/pyobs.md has the table.
"""

from __future__ import annotations

import json
import logging
import time
import uuid
from dataclasses import fields
from typing import Any

from nightcrew.comm.xmpp._room import _json_value
from nightcrew.comm.xmpp._stanza_limits import load_json_bounded
from nightcrew.errors import CodecError
from nightcrew.events.base import event_by_name

__all__ = ["FIELD_NAMES", "IGNORED_FIELDS", "NS_PYOBS_EVENT", "PYOBS_EVENTS", "event_body", "translate_event"]

log = logging.getLogger(__name__)

NS_PYOBS_EVENT = "pyobs:event"
#: pyobs-core 2.19's events whose names nightcrew's events share (docs/pyobs.md has the fields).
PYOBS_EVENTS = frozenset(
    {
        "BadWeatherEvent",
        "ExposureStatusChangedEvent",
        "FilterChangedEvent",
        "FocusFoundEvent",
        "GoodWeatherEvent",
        "LogEvent",
        "MotionStatusChangedEvent",
        "MoveAltAzEvent",
        "MoveRaDecEvent",
        "NewImageEvent",
        "NewSpectrumEvent",
        "OffsetsAltAzEvent",
        "OffsetsRaDecEvent",
        "RoofClosingEvent",
        "RoofOpenedEvent",
        "TaskFailedEvent",
        "TaskFinishedEvent",
        "TaskStartedEvent",
        "TestEvent",
    }
)
#: Fields with the same meaning under another name: event → {pyobs name: nightcrew name}.
FIELD_NAMES: dict[str, dict[str, str]] = {
    "FilterChangedEvent": {"current": "filter_name"},
    "OffsetsAltAzEvent": {"alt": "dalt", "az": "daz"},
    "OffsetsRaDecEvent": {"ra": "dra", "dec": "ddec"},
}
#: pyobs fields nightcrew drops knowingly (docs/pyobs.md says why); other unknown fields skip the event.
IGNORED_FIELDS: dict[str, frozenset[str]] = {
    "MotionStatusChangedEvent": frozenset({"interfaces"}),  # per interface; ours are per device
    "TaskStartedEvent": frozenset({"obsnum"}),
    "TaskFinishedEvent": frozenset({"obsnum"}),
    "TaskFailedEvent": frozenset({"obsnum"}),
    "LogEvent": frozenset({"function", "sender"}),  # the sender is the node's; no function field here
}
#: Fields one side requires and the other does not send: event → {field: value when absent}.
#: pyobs sends no logger name; pyobs' LogEvent requires a file, function and line.
RECEIVED_DEFAULTS: dict[str, dict[str, Any]] = {"LogEvent": {"logger": "pyobs"}}
SENT_DEFAULTS: dict[str, dict[str, Any]] = {"LogEvent": {"filename": "", "function": "", "line": 0}}
#: pyobs drops events older than this (a replay after a reconnect); so do we.
_MAX_EVENT_AGE = 30.0


def event_body(name: str, payload: dict[str, Any]) -> str:
    """The JSON pyobs reads for nightcrew event ``name`` with wire fields ``payload``."""
    renamed = {ours: theirs for theirs, ours in FIELD_NAMES.get(name, {}).items()}
    data = {renamed.get(key, key): value for key, value in payload.items()}
    for key, value in SENT_DEFAULTS.get(name, {}).items():
        if data.get(key) is None:
            data[key] = value
    body = {"type": name, "timestamp": time.time(), "uuid": str(uuid.uuid4()), "data": data}
    return json.dumps(body, default=_json_value, separators=(",", ":"))


def translate_event(text: str, name: str, sender: str) -> dict[str, Any] | None:
    """nightcrew's wire fields for one pyobs event body, or None (logged) when it cannot be mapped.

    Fields are renamed where pyobs names the same thing otherwise (:data:`FIELD_NAMES`); one
    nightcrew's event lacks is dropped when empty (pyobs' ``raw=None``) or listed in
    :data:`IGNORED_FIELDS`, and refused otherwise: its meaning would be lost without notice.
    """
    event_type = event_by_name(name)
    if event_type is None:
        log.debug("pyobs event %s from %s has no nightcrew equivalent; skipped", name, sender)
        return None
    try:
        body = load_json_bounded(text)
        data = body.get("data") or {}
        if body.get("type") != name or not isinstance(data, dict):
            raise ValueError(f"type {body.get('type')!r} on the node of {name}, data {type(data).__name__}")
        age = time.time() - float(body.get("timestamp", 0.0))
    except (CodecError, ValueError, TypeError, AttributeError) as exc:
        log.warning("skipped malformed pyobs %s from %s: %s", name, sender, exc)
        return None
    if age > _MAX_EVENT_AGE:
        log.info("skipped pyobs %s from %s: %.0f s old", name, sender, age)
        return None
    renamed = FIELD_NAMES.get(name, {})
    data = {
        renamed.get(key, key): value for key, value in data.items() if key not in IGNORED_FIELDS.get(name, ())
    }
    known = {f.name for f in fields(event_type)}
    unknown = sorted(key for key, value in data.items() if key not in known and value is not None)
    if unknown:
        log.warning(
            "skipped pyobs %s from %s: fields nightcrew's %s lacks: %s",
            name,
            sender,
            name,
            ", ".join(unknown),
        )
        return None
    return {**RECEIVED_DEFAULTS.get(name, {}), **{key: value for key, value in data.items() if key in known}}
