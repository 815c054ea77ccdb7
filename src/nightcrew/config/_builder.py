"""Building objects from a configuration that has been validated.

Building follows the same reading of type hints as validation (it asks the validator which union
member a value is for), and converts where a hint asks for it: a description becomes an object,
an ``int`` for ``float`` a float, a list for ``tuple``/``set`` a tuple/set, a name or value for an
``Enum`` its member. Located nodes become plain dicts and lists, so constructors get ordinary data.
Values for parameters without a hint (or typed ``Any``/``dict``) are passed as data: a description
there is not built (the receiving class may build it itself with :func:`build_object`). A
parameter hinted as a path (:mod:`._paths`) gets a relative value read against the folder of the
file it is written in, and an input path that does not exist is refused. So is a
description for a parameter the class lists in ``config_builds_itself`` (validated like any other):
the class builds it, and owns and closes what it built (:class:`~nightcrew.object.Object`'s
``vfs``), while an object handed to it ready-made stays its maker's.
"""

from __future__ import annotations

import collections.abc
import os
import typing
from collections.abc import Mapping
from enum import Enum
from typing import Any, Literal

from nightcrew.config._classes import constructor_spec, import_class
from nightcrew.config._hints import (
    is_class_description,
    is_object_hint,
    mapping_origins,
    sequence_origins,
    union_members,
    unwrap,
)
from nightcrew.config._nodes import ConfigNode, Location, join_key, location_in
from nightcrew.config._paths import PathRole, resolve_path
from nightcrew.config._validator import enum_member, iter_problems, preferred_member
from nightcrew.errors import ConfigError

__all__ = ["build_object", "to_plain"]


def build_object(config: Mapping[str, Any], expected: type | None = None) -> Any:
    """Validate the description ``config``, then build the object it describes.

    Args:
        config: A mapping with ``class`` (a dotted import path) and the constructor's keys, e.g.
            from :func:`~nightcrew.config.load_config` (then errors name file and line).
        expected: If given, the object must be an instance of this class.

    Raises:
        ConfigError: The first problem of the configuration, or the error of a constructor.
    """
    problem = next(iter_problems(config, expected), None)
    if problem is not None:
        raise problem
    location = config.location if isinstance(config, ConfigNode) else None
    return _build_object(config, "", location)


def to_plain(value: Any) -> Any:
    """``value`` with every mapping and list turned into a plain ``dict`` and ``list``."""
    if isinstance(value, Mapping):
        return {key: to_plain(item) for key, item in value.items()}
    if isinstance(value, list):
        return [to_plain(item) for item in value]
    return value


def _build_object(node: Mapping[str, Any], prefix: str, owner: Location | None) -> Any:
    path = node["class"]
    cls = import_class(path)
    parameters = constructor_spec(cls).parameters
    # Descriptions the class builds itself go to it unbuilt, located (its errors name file and line).
    builds_itself: frozenset[str] = getattr(cls, "config_builds_itself", frozenset())
    kwargs: dict[str, Any] = {}
    for key, value in node.items():
        if key in builds_itself and is_class_description(value):
            kwargs[key] = value
        elif key != "class":
            parameter = parameters.get(key)
            location = location_in(node, key, owner)
            if (
                parameter is not None
                and parameter.path_role is not None
                and isinstance(value, str)
                and not _is_literal_word(value, parameter.hint)
            ):
                kwargs[key] = _file_path(value, parameter.path_role, join_key(prefix, key), location)
                continue
            hint = parameter.hint if parameter else Any
            kwargs[key] = _build_value(value, hint, join_key(prefix, key), location)
    try:
        return cls(**kwargs)
    except ConfigError as exc:
        if exc.file or not exc.key or exc.key.split(".")[0] not in node:
            raise
        # The constructor named the offending key: point at that key's line in the file.
        location = location_in(node, exc.key.split(".")[0], owner)
        raise ConfigError(
            exc.message,
            file=location.file if location else None,
            line=location.line if location else None,
            key=join_key(prefix, exc.key),
        ) from exc
    except Exception as exc:
        # The configuration passed every check we know of, but the constructor refused it.
        location = location_in(node, "class", owner)
        raise ConfigError(
            f"building {path} failed: {type(exc).__name__}: {exc}",
            file=location.file if location else None,
            line=location.line if location else None,
            key=prefix or None,
        ) from exc


def _is_literal_word(value: str, hint: Any) -> bool:
    """Whether ``value`` is a word the hint allows besides a path (``policy: open``)."""
    members = union_members(unwrap(hint)) or (hint,)
    return any(typing.get_origin(m) is Literal and value in typing.get_args(m) for m in members)


def _file_path(value: str, role: PathRole, key: str, location: Location | None) -> str:
    """A path written in a file, read against that file's folder; an input must exist."""
    path = resolve_path(value, location.file if location else None)
    if role is PathRole.INPUT and not os.path.exists(path):
        raise ConfigError(
            f"file {path} not found",
            file=location.file if location else None,
            line=location.line if location else None,
            key=key,
        )
    return path


def _build_value(value: Any, hint: Any, key: str, location: Location | None) -> Any:
    hint = unwrap(hint)
    if hint is Any or hint is object:
        return to_plain(value)
    members = union_members(hint)
    if members is not None:
        member = preferred_member(value, members)
        return _build_value(value, member, key, location) if member is not None else to_plain(value)
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin is Literal:
        return value
    if (origin in sequence_origins or origin is tuple) and isinstance(value, list):
        return _build_sequence(value, origin, args, key, location)
    if origin in mapping_origins and isinstance(value, Mapping):
        value_hint = args[1] if len(args) == 2 else Any
        return {
            name: _build_value(item, value_hint, join_key(key, name), location_in(value, name, location))
            for name, item in value.items()
        }
    if isinstance(hint, type) and origin is None:
        if issubclass(hint, Enum):
            return enum_member(hint, value)
        if hint is float and isinstance(value, int):
            return float(value)
        if hint in (tuple, set, frozenset) and isinstance(value, list):
            return hint(to_plain(value))
        if is_object_hint(hint) and is_class_description(value) and not isinstance(value, hint):
            return _build_object(value, key, location)
    return to_plain(value)


def _build_sequence(
    value: list[Any], origin: Any, args: tuple[Any, ...], key: str, location: Location | None
) -> Any:
    if origin is tuple and args and not (len(args) == 2 and args[1] is Ellipsis):
        item_hints = list(args)
    else:
        item_hints = [args[0] if args else Any] * len(value)
    items = [
        _build_value(item, item_hint, join_key(key, index), location_in(value, index, location))
        for index, (item, item_hint) in enumerate(zip(value, item_hints, strict=True))
    ]
    if origin in (tuple, frozenset):
        return origin(items)
    if origin in (set, collections.abc.Set, collections.abc.MutableSet):
        return set(items)
    return items
