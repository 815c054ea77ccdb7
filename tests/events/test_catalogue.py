"""The event catalogue: every event is registered, exported, frozen, keyword-only and typed for the wire."""

from __future__ import annotations

import dataclasses
import typing
from typing import Any

import pytest

import nightcrew.events as events_package
from nightcrew.events import Event, ModuleClosedEvent, ModuleOpenedEvent, event_by_name

from ..interfaces.wire_types import hint_problems
from .catalogue import ALL_EVENTS


def _contains_any(hint: Any) -> bool:
    return hint is Any or any(_contains_any(arg) for arg in typing.get_args(hint))


def test_catalogue_is_not_empty() -> None:
    assert len(ALL_EVENTS) >= 20


@pytest.mark.parametrize("cls", ALL_EVENTS, ids=lambda cls: cls.__name__)
def test_event_is_registered_and_exported(cls: type[Event]) -> None:
    assert event_by_name(cls.__name__) is cls
    assert cls.event_name() == cls.__name__
    assert cls.__name__ in events_package.__all__
    assert getattr(events_package, cls.__name__) is cls
    assert cls.__name__.endswith("Event")


@pytest.mark.parametrize("cls", ALL_EVENTS, ids=lambda cls: cls.__name__)
def test_event_is_frozen_keyword_only_and_documented(cls: type[Event]) -> None:
    assert "__dataclass_fields__" in vars(cls), "subclass must itself be a dataclass"
    params = vars(cls)["__dataclass_params__"]
    assert params.frozen
    assert all(f.kw_only for f in dataclasses.fields(cls))
    assert cls.__doc__ and cls.__doc__.strip()


@pytest.mark.parametrize("cls", ALL_EVENTS, ids=lambda cls: cls.__name__)
def test_event_fields_can_travel_as_json(cls: type[Event]) -> None:
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        assert hint_problems(hints[f.name], f.name) == []
        # JSON has no dates or bytes: only a declared type lets the receiver rebuild them.
        assert not _contains_any(hints[f.name]), f"{f.name}: Any loses types in JSON"


def test_all_names_exist_once() -> None:
    names = events_package.__all__
    assert len(names) == len(set(names))
    for name in names:
        assert hasattr(events_package, name), name


def test_presence_events_need_no_arguments() -> None:
    # The comm builds these itself from presence, without knowing anything but the sender.
    assert ModuleOpenedEvent().to_dict() == {}
    assert ModuleClosedEvent().to_dict() == {}


def test_unknown_event_name_is_none() -> None:
    assert event_by_name("NoSuchEvent") is None
