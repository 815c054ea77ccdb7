"""Test helper: every event class defined in the nightcrew.events package, found by walking it."""

from __future__ import annotations

import importlib
import pkgutil

import nightcrew.events as events_package
from nightcrew.events import Event


def _defined_events() -> list[type[Event]]:
    found: list[type[Event]] = []
    for info in pkgutil.iter_modules(events_package.__path__, "nightcrew.events."):
        module = importlib.import_module(info.name)
        found += [
            obj
            for obj in vars(module).values()
            if isinstance(obj, type)
            and issubclass(obj, Event)
            and obj is not Event
            and obj.__module__ == module.__name__
        ]
    return sorted(found, key=lambda cls: cls.__name__)


ALL_EVENTS = _defined_events()
