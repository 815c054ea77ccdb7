"""Interfaces, methods and events described as JSON for the pages, and values turned into JSON.

The pages build themselves from these descriptions (a camera without IWindow has no
``set_window`` here, so no window controls) and the shell completes from them.
"""

from __future__ import annotations

import base64
import dataclasses
import enum
import inspect
import re
import types
import typing
from collections.abc import Callable, Iterable
from datetime import datetime
from functools import cache
from typing import Any

from nightcrew.comm.codec import encode, method_parameters
from nightcrew.events.base import Event, event_by_name, event_names
from nightcrew.interfaces.base import Interface, interface_methods
from nightcrew.modules.console._auth import is_read_method

__all__ = ["describe_event_types", "describe_methods", "parameter", "to_json", "type_text"]

_DOTTED = re.compile(r"\b(?:[A-Za-z_]\w*\.)+([A-Za-z_]\w*)")


def to_json(value: Any) -> Any:
    """``value`` (anything the codec can send) as plain JSON: datetimes ISO, bytes base64."""
    return _wire_to_json(encode(value))


def _wire_to_json(value: Any) -> Any:
    if isinstance(value, datetime):
        return value.isoformat()
    if isinstance(value, bytes):
        return base64.b64encode(value).decode()
    if isinstance(value, list):
        return [_wire_to_json(v) for v in value]
    if isinstance(value, dict):
        return {k: _wire_to_json(v) for k, v in value.items()}
    if isinstance(value, float) and value != value:  # NaN is no JSON
        return None
    return value


def type_text(hint: Any) -> str:
    """A type hint as a person writes it: ``float``, ``ImageType | None``, ``list[str]``."""
    if hint is inspect.Parameter.empty or hint is Any:
        return "Any"
    if typing.get_origin(hint) is typing.Annotated:  # units and bounds are not part of the type's name
        return type_text(typing.get_args(hint)[0])
    if hint is None or hint is type(None):
        return "None"
    if isinstance(hint, type) and not typing.get_args(hint):
        return hint.__name__
    return _DOTTED.sub(r"\1", str(hint).replace("typing.", "")).replace("NoneType", "None")


def _enum_in(hint: Any) -> type[enum.Enum] | None:
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return hint
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        for arg in typing.get_args(hint):
            found = _enum_in(arg)
            if found is not None:
                return found
    return None


def parameter(name: str, hint: Any, default: Any) -> dict[str, Any]:
    """One parameter (of a method or an event) as the pages see it."""
    choices = _enum_in(hint)
    required = default is inspect.Parameter.empty or default is dataclasses.MISSING
    return {
        "name": name,
        "type": type_text(hint),
        "required": required,
        "default": None if required else _default_json(default),
        "choices": [to_json(member) for member in choices] if choices is not None else None,
    }


def _default_json(default: Any) -> Any:
    try:
        return to_json(default)
    except Exception:  # a default the wire cannot carry (never the case in the catalogue)
        return repr(default)


def describe_methods(interfaces: Iterable[type[Interface]]) -> dict[str, dict[str, Any]]:
    """Method name → interface, doc, parameters, return type, whether a viewer may call it."""
    return {name: _describe_method(name, declaration) for name, declaration in _methods(tuple(interfaces))}


@cache
def _methods(interfaces: tuple[type[Interface], ...]) -> tuple[tuple[str, Callable[..., object]], ...]:
    return tuple(sorted(interface_methods(interfaces).items()))


@cache
def _describe_method(name: str, declaration: Callable[..., object]) -> dict[str, Any]:
    params, returns = method_parameters(declaration)
    return {
        "interface": declaration.__qualname__.split(".")[0],
        "doc": inspect.getdoc(declaration) or "",
        "params": [parameter(p.name, p.hint, p.default) for p in params],
        "returns": type_text(returns),
        "read": is_read_method(name),
    }


def describe_event_types() -> dict[str, dict[str, Any]]:
    """Every event type this process knows, with its fields."""
    described = {}
    for name in event_names():
        event_type = event_by_name(name)
        if event_type is not None:
            described[name] = _describe_event(event_type)
    return described


def _describe_event(event_type: type[Event]) -> dict[str, Any]:
    hints = typing.get_type_hints(event_type)
    fields = []
    for field in dataclasses.fields(event_type):
        default: Any = field.default
        if field.default_factory is not dataclasses.MISSING:
            default = field.default_factory()
        fields.append(parameter(field.name, hints.get(field.name, Any), default))
    return {"doc": inspect.getdoc(event_type) or "", "fields": fields}
