"""Every event survives to_dict/from_dict and a JSON carrier, with sample values of all its fields."""

from __future__ import annotations

import base64
import dataclasses
import json
import typing
from datetime import UTC, datetime
from typing import Any

import pytest

from nightcrew.errors import CodecError
from nightcrew.events import (
    Event,
    ExposureStatusChangedEvent,
    LogEvent,
    MotionStatusChangedEvent,
    NewImageEvent,
)
from nightcrew.interfaces import ImageType, MotionStatus

from ..interfaces.wire_types import sample_values
from .catalogue import ALL_EVENTS


def _samples(cls: type[Event]) -> list[Event]:
    """Instances of ``cls`` in which every sample value of every field appears once."""
    hints = typing.get_type_hints(cls)
    names = [f.name for f in dataclasses.fields(cls)]
    columns = [sample_values(hints[name]) for name in names]
    count = max((len(c) for c in columns), default=1)
    return [cls(**{n: c[i % len(c)] for n, c in zip(names, columns, strict=True)}) for i in range(count)]


def _json_default(value: Any) -> Any:
    """What the XMPP layer does with the wire values JSON lacks."""
    if isinstance(value, datetime):
        return value.isoformat()
    if isinstance(value, bytes):
        return base64.b64encode(value).decode("ascii")
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def _through_json(event: Event) -> Event:
    text = json.dumps({"name": event.event_name(), "fields": event.to_dict()}, default=_json_default)
    message = json.loads(text)
    return type(event).from_dict(message["fields"])


@pytest.mark.parametrize("cls", ALL_EVENTS, ids=lambda cls: cls.__name__)
def test_round_trip_through_dict(cls: type[Event]) -> None:
    for event in _samples(cls):
        assert cls.from_dict(event.to_dict()) == event


@pytest.mark.parametrize("cls", ALL_EVENTS, ids=lambda cls: cls.__name__)
def test_round_trip_through_json(cls: type[Event]) -> None:
    for event in _samples(cls):
        rebuilt = _through_json(event)
        assert rebuilt == event
        for f in dataclasses.fields(cls):  # == alone would accept 3.0 for 3 or an str for an enum
            assert type(getattr(rebuilt, f.name)) is type(getattr(event, f.name)), f.name


def test_log_event_by_hand() -> None:
    event = LogEvent(
        time=datetime(2031, 1, 2, 3, 4, 5, 678, tzinfo=UTC),
        level="WARNING",
        logger="nightcrew.modules.roof",
        message="roof motor hot",
        line=42,
    )
    wire = json.loads(json.dumps(event.to_dict(), default=_json_default))
    assert wire["time"] == "2031-01-02T03:04:05.000678+00:00"
    assert wire["filename"] is None
    assert LogEvent.from_dict(wire) == event


def test_enums_travel_as_their_names() -> None:
    event = MotionStatusChangedEvent(status=MotionStatus.TRACKING, devices={"focuser": MotionStatus.IDLE})
    assert event.to_dict() == {"status": "tracking", "devices": {"focuser": "idle"}}
    assert MotionStatusChangedEvent.from_dict(event.to_dict()).devices["focuser"] is MotionStatus.IDLE


def test_unknown_fields_from_newer_senders_are_ignored() -> None:
    wire = {"filename": "/cache/a.fits", "image_type": "bias", "added_later": 1}
    assert NewImageEvent.from_dict(wire) == NewImageEvent(filename="/cache/a.fits", image_type=ImageType.BIAS)


def test_bad_enum_value_is_refused() -> None:
    with pytest.raises(CodecError, match=r'expected one of .*, got string "sleeping"'):
        ExposureStatusChangedEvent.from_dict({"last": None, "current": "sleeping"})


def test_wrong_field_type_is_refused() -> None:
    with pytest.raises(CodecError, match="filename: expected string, got integer 3"):
        NewImageEvent.from_dict({"filename": 3})


def test_events_are_immutable() -> None:
    event = NewImageEvent(filename="/cache/a.fits")
    with pytest.raises(dataclasses.FrozenInstanceError):
        event.filename = "/cache/b.fits"  # type: ignore[misc]
