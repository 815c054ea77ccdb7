"""Trigger: when an event arrives, call a method of another module with values from the event.

The paper's example, an archive told about every new image::

    class: nightcrew.modules.utils.Trigger
    triggers:
      - event: NewImageEvent        # event class name
        module: archive             # module to call
        method: add_image           # one of its interface methods
        args: [filename]            # event fields, passed positionally in this order
        # kwargs: {image_type: image_type}   # parameter name → event field
        # sender: camera            # only events from this module (any sender by default)

Only event fields travel: no expressions, so a configuration cannot run code. A failing call is
logged and the other triggers still run.
"""

from __future__ import annotations

import dataclasses
import logging
from collections import defaultdict
from dataclasses import dataclass
from typing import Any

import nightcrew.events  # noqa: F401 - registers the event classes that triggers name
from nightcrew.errors import ConfigError, InterfaceError
from nightcrew.events.base import Event, event_by_name
from nightcrew.interfaces import ModuleState
from nightcrew.interfaces.base import interface_methods, interfaces_of
from nightcrew.modules.module import Module

__all__ = ["Trigger", "TriggerRule"]

log = logging.getLogger(__name__)

_KEYS = {"event", "module", "method", "args", "kwargs", "sender"}


@dataclass(frozen=True)
class TriggerRule:
    """One configured trigger: on ``event`` (from ``sender``) call ``module.method(*args, **kwargs)``."""

    event: type[Event]
    module: str
    method: str
    args: tuple[str, ...] = ()
    kwargs: tuple[tuple[str, str], ...] = ()
    sender: str | None = None

    def arguments(self, event: Event) -> tuple[list[Any], dict[str, Any]]:
        """The call's arguments taken from ``event``'s fields."""
        return [getattr(event, f) for f in self.args], {p: getattr(event, f) for p, f in self.kwargs}


def parse_rule(entry: dict[str, Any], key: str) -> TriggerRule:
    """A rule from one ``triggers`` entry; ConfigError naming ``key`` and the field if it is wrong."""
    if not isinstance(entry, dict):
        raise ConfigError("expected a mapping with event, module and method", key=key)
    unknown = sorted(set(entry) - _KEYS)
    if unknown:
        raise ConfigError(f"unknown keys {unknown}; known: {', '.join(sorted(_KEYS))}", key=key)
    for required in ("event", "module", "method"):
        if not isinstance(entry.get(required), str) or not entry[required]:
            raise ConfigError(f"'{required}' must be a non-empty string", key=f"{key}.{required}")
    event = event_by_name(entry["event"])
    if event is None:
        raise ConfigError(f"unknown event {entry['event']!r}", key=f"{key}.event")
    fields = {f.name for f in dataclasses.fields(event)}
    args = entry.get("args", [])
    kwargs = entry.get("kwargs", {})
    if not isinstance(args, list) or not isinstance(kwargs, dict):
        raise ConfigError("args must be a list and kwargs a mapping of event fields", key=f"{key}.args")
    for name in [*args, *kwargs.values()]:
        if name not in fields:
            raise ConfigError(
                f"{event.__name__} has no field {name!r}; it has: {', '.join(sorted(fields)) or 'none'}",
                key=f"{key}.args" if name in args else f"{key}.kwargs",
            )
    if entry["method"].startswith("_"):
        raise ConfigError("cannot call a private method", key=f"{key}.method")
    sender = entry.get("sender")
    return TriggerRule(event, entry["module"], entry["method"], tuple(args), tuple(kwargs.items()), sender)


class Trigger(Module):
    """Calls methods of other modules when events arrive (see the module docstring).

    Args:
        triggers: List of {event, module, method, args?, kwargs?, sender?}.
        **kwargs: Module options.
    """

    def __init__(self, *, triggers: list[dict[str, Any]], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not triggers:
            raise ConfigError("configure at least one trigger", key="triggers")
        self.rules = [parse_rule(entry, f"triggers[{i}]") for i, entry in enumerate(triggers)]
        self._by_event: dict[str, list[TriggerRule]] = defaultdict(list)
        for rule in self.rules:
            self._by_event[rule.event.event_name()].append(rule)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        for rules in self._by_event.values():
            await self.comm.register_event(rules[0].event, self.on_event)

    async def on_event(self, event: Event, sender: str) -> None:
        """Run every trigger matching the event, one after the other."""
        for rule in self._by_event.get(event.event_name(), []):
            if rule.sender is not None and rule.sender != sender:
                continue
            try:
                await self._call(rule, event)
            except Exception as exc:
                log.error(
                    "%s: %s.%s() for %s failed: %s",
                    self.name,
                    rule.module,
                    rule.method,
                    event.event_name(),
                    exc,
                )

    async def _call(self, rule: TriggerRule, event: Event) -> None:
        proxy = await self.comm.proxy(rule.module)
        if rule.method not in interface_methods(interfaces_of(type(proxy))):
            raise InterfaceError(f"module '{rule.module}' offers no method {rule.method}()")
        args, kwargs = rule.arguments(event)
        log.debug("%s: calling %s.%s(%s)", self.name, rule.module, rule.method, args)
        await getattr(proxy, rule.method)(*args, **kwargs)
