"""Small helpers to take type hints apart and to describe hints and values in messages."""

from __future__ import annotations

import collections.abc
import types
import typing
from collections.abc import Mapping
from enum import Enum
from typing import Any, Literal

from nightcrew.interfaces.base import is_interface

__all__ = [
    "NoneType",
    "describe_hint",
    "describe_value",
    "is_class_description",
    "is_object_hint",
    "mapping_origins",
    "sequence_origins",
    "union_members",
    "unwrap",
]

NoneType = type(None)

#: Plain data types that a YAML value is directly (no object is built for them).
_DATA_TYPES: frozenset[type] = frozenset(
    {str, int, float, bool, bytes, list, tuple, dict, set, frozenset, NoneType, object}
)
sequence_origins: frozenset[Any] = frozenset(
    {
        list,
        set,
        frozenset,
        collections.abc.Sequence,
        collections.abc.MutableSequence,
        collections.abc.Set,
        collections.abc.MutableSet,
        collections.abc.Collection,
        collections.abc.Iterable,
    }
)
mapping_origins: frozenset[Any] = frozenset({dict, collections.abc.Mapping, collections.abc.MutableMapping})


def unwrap(hint: Any) -> Any:
    """``NewType`` and ``Annotated[X, ...]`` to their base type, ``None`` to ``NoneType``; other
    hints unchanged."""
    while hasattr(hint, "__supertype__") or typing.get_origin(hint) is typing.Annotated:
        hint = hint.__supertype__ if hasattr(hint, "__supertype__") else hint.__origin__
    return NoneType if hint is None else hint


def union_members(hint: Any) -> tuple[Any, ...] | None:
    """The members of ``X | Y`` / ``Optional[X]`` / ``Union[...]``, else None."""
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        return typing.get_args(hint)
    return None


def is_object_hint(hint: Any) -> bool:
    """Whether values for ``hint`` are objects built from a description (a mapping with ``class``)."""
    # typing.Any is a class since Python 3.11, but stands for "anything", not an object type.
    return (
        isinstance(hint, type) and hint is not Any and hint not in _DATA_TYPES and not issubclass(hint, Enum)
    )


def is_class_description(value: object) -> bool:
    """Whether ``value`` describes an object: a mapping with a ``class`` key."""
    return isinstance(value, Mapping) and "class" in value


def describe_hint(hint: Any) -> str:
    """``float``, ``list[Thing]``, ``float | None``, ``one of 'a', 'b'``, ... for messages."""
    hint = unwrap(hint)
    members = union_members(hint)
    if members is not None:
        parts = [describe_hint(m) for m in members]
        if str in members and any(is_interface(m) for m in members):
            parts[members.index(str)] = "str (a module name)"
        return " | ".join(parts)
    origin = typing.get_origin(hint)
    if origin is Literal:
        return "one of " + ", ".join(repr(arg) for arg in typing.get_args(hint))
    if origin is not None:
        args = ", ".join("..." if arg is Ellipsis else describe_hint(arg) for arg in typing.get_args(hint))
        return f"{getattr(origin, '__name__', str(origin))}[{args}]"
    if hint is NoneType:
        return "None"
    if isinstance(hint, type):
        if issubclass(hint, Enum):
            return "one of " + ", ".join(repr(member.value) for member in hint)
        return hint.__name__
    return str(hint)


def describe_value(value: object) -> str:
    """``str 'ten'``, ``int 5``, ``null``, ``a list``, ... for messages."""
    if value is None:
        return "null"
    if isinstance(value, Mapping):
        if "class" in value:
            return f"a description of {value['class']}"
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    text = repr(value)
    if len(text) > 40:
        text = text[:37] + "..."
    return f"{type(value).__name__} {text}"
