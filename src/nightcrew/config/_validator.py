"""Validating a configuration against constructor signatures, without building anything.

Pure: a configuration and the classes it names go in, :class:`ConfigError` values come out (as a
lazy iterator, so :func:`validate_config` stops at the first). Every problem names the file, the
line and the dotted key path (``comm.jid``, ``things[1].value``).

What a type hint accepts: ``int`` (not ``bool``), ``float`` (also ``int``), ``str``, ``bool``,
``None``, ``list[X]``/``Sequence[X]``/``set[X]`` and ``tuple[...]`` (a YAML list), ``dict[str, X]``/
``Mapping`` (a YAML mapping), ``Literal[...]``, an ``Enum`` (a member's value or name), unions, and
for any other class an instance of it (e.g. a YAML timestamp for ``datetime``) or a description of an
object of (a subclass of) it: a mapping with ``class``. ``str | IInterface`` takes a module name.
A missing hint, ``Any`` and hints this module cannot check (``Callable``, type variables, ...)
accept anything. A class with a static method ``config_value_problems(values)`` (the description's
keys and values, ``class`` left out) yielding ``(key, message)`` pairs has those reported too.
"""

from __future__ import annotations

import difflib
import inspect
import math
import re
import typing
from collections.abc import Iterator, Mapping
from enum import Enum
from typing import Any, Literal

from nightcrew.config._classes import ClassResolutionError, constructor_spec, import_class
from nightcrew.config._hints import (
    NoneType,
    describe_hint,
    describe_value,
    is_class_description,
    is_object_hint,
    mapping_origins,
    sequence_origins,
    union_members,
    unwrap,
)
from nightcrew.config._nodes import ConfigNode, Location, join_key, location_in
from nightcrew.errors import ConfigError
from nightcrew.interfaces.base import is_interface
from nightcrew.interfaces.quantities import bound_problem

__all__ = [
    "accepts",
    "check_object",
    "check_value",
    "enum_member",
    "is_secret_key",
    "iter_problems",
    "preferred_member",
]


def iter_problems(config: object, expected: type | None = None) -> Iterator[ConfigError]:
    """All problems of the object description ``config``, in file order, lazily."""
    location = config.location if isinstance(config, ConfigNode) else None
    if not isinstance(config, Mapping):
        yield _problem(f"expected a mapping with a 'class' key, got {describe_value(config)}", location, "")
        return
    yield from check_object(config, (expected,) if expected else (), "", location)


def check_object(
    node: Mapping[str, Any], expected: tuple[type, ...], prefix: str, owner: Location | None
) -> Iterator[ConfigError]:
    """Problems of the description ``node`` of an object that must be an instance of ``expected``.

    Args:
        node: The mapping with ``class`` and the constructor's keys.
        expected: The object must be an instance of one of these (any class if empty).
        prefix: Dotted key path of ``node`` ("" at the top level).
        owner: Location of the key holding ``node`` (used when ``node`` has no locations).
    """
    class_key = join_key(prefix, "class")
    class_location = location_in(node, "class", owner)
    if "class" not in node:
        wanted = " | ".join(t.__name__ for t in expected) or "object"
        yield _problem(f"missing key 'class' (the dotted path of the {wanted} to build)", owner, class_key)
        return
    path = node["class"]
    if not isinstance(path, str):
        yield _problem(f"expected a dotted class path, got {describe_value(path)}", class_location, class_key)
        return
    try:
        cls = import_class(path)
    except ClassResolutionError as exc:
        yield _problem(str(exc), class_location, class_key)
        return
    if expected and not _is_subclass(cls, expected):
        verb = "implement" if all(is_interface(t) for t in expected) else "derive from"
        names = " or ".join(t.__name__ for t in expected)
        yield _problem(f"{path} does not {verb} {names}", class_location, class_key)
        return
    if inspect.isabstract(cls):
        missing = ", ".join(sorted(getattr(cls, "__abstractmethods__", ())))
        yield _problem(
            f"{path} is abstract and cannot be built (abstract: {missing})", class_location, class_key
        )
        return
    spec = constructor_spec(cls)
    for key, value in node.items():
        if key == "class":
            continue
        location = location_in(node, key, owner)
        parameter = spec.parameters.get(key)
        if parameter is None:
            # A class may say where a key it no longer takes has gone (e.g. into a nested object).
            moved = getattr(cls, "config_moved_keys", {}).get(key)
            if moved is not None:
                yield _problem(f"key '{key}' of {path} {moved}", location, join_key(prefix, key))
            elif not spec.open_ended:
                close = difflib.get_close_matches(key, list(spec.parameters), n=1)
                hint = f" (did you mean '{close[0]}'?)" if close else ""
                yield _problem(f"unknown key '{key}' for {path}{hint}", location, join_key(prefix, key))
            continue
        yield from check_value(value, parameter.hint, join_key(prefix, key), location)
    for name, parameter in spec.parameters.items():
        if parameter.required and name not in node:
            yield _problem(
                f"missing required key '{name}' for {path}", class_location, join_key(prefix, name)
            )
    # A class may check values its type hints cannot express (e.g. that a str is a URL).
    value_check = getattr(cls, "config_value_problems", None)
    if callable(value_check):
        for key, message in value_check({k: v for k, v in node.items() if k != "class"}):
            yield _problem(message, location_in(node, key, owner), join_key(prefix, key))


def check_value(value: object, hint: Any, key: str, location: Location | None) -> Iterator[ConfigError]:
    """Problems of ``value`` given for a parameter with type hint ``hint``."""
    if typing.get_origin(hint) is typing.Annotated:
        problems = list(check_value(value, hint.__origin__, key, location))
        if problems:
            yield from problems
            return
        problem = bound_problem(value, hint.__metadata__)
        if problem is not None:
            yield _problem(f"{_shown(value, key)} {problem}", location, key)
        return
    hint = unwrap(hint)
    if hint is Any or hint is object:
        return
    members = union_members(hint)
    if members is not None:
        yield from _check_union(value, hint, members, key, location)
        return
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin is Literal:
        if not any(type(value) is type(arg) and value == arg for arg in args):
            yield _mismatch(hint, value, key, location)
    elif origin in sequence_origins or origin is tuple:
        yield from _check_sequence(value, hint, origin, args, key, location)
    elif origin in mapping_origins:
        yield from _check_mapping(value, hint, args, key, location)
    elif origin is None and isinstance(hint, type):
        yield from _check_class(value, hint, key, location)
    # Any other hint (Callable[...], type[X], a TypeVar, ...) is beyond checking: accept.


def accepts(value: object, hint: Any) -> bool:
    """Whether ``value`` is valid for ``hint``."""
    return next(check_value(value, hint, "", None), None) is None


def preferred_member(value: object, members: tuple[Any, ...]) -> Any | None:
    """The union member that ``value`` is for: the first that accepts it; None if none does.

    A description (``{class: ...}``) is only for the object types of the union if it has any: in
    ``Thing | dict`` the ``dict`` means "a description of a Thing", never "any mapping".
    """
    if is_class_description(value):
        object_types = tuple(m for m in members if is_object_hint(unwrap(m)))
        members = object_types or members
    return next((member for member in members if accepts(value, member)), None)


def enum_member(enum: type[Enum], value: object) -> Enum | None:
    """The member of ``enum`` with value ``value`` (same type) or name ``value``, else None."""
    for member in enum:
        if type(member.value) is type(value) and member.value == value:
            return member
    if isinstance(value, str) and value in enum.__members__:
        return enum.__members__[value]
    return None


def _check_union(
    value: object, hint: Any, members: tuple[Any, ...], key: str, location: Location | None
) -> Iterator[ConfigError]:
    if preferred_member(value, members) is not None:
        return
    # When only one member has the value's shape (a description, a list, a mapping), its own
    # problem is more telling than "expected A | B".
    if is_class_description(value):
        object_types = tuple(unwrap(m) for m in members if is_object_hint(unwrap(m)))
        if object_types:
            yield from check_object(_as_mapping(value), object_types, key, location)
            return
    shaped = [m for m in members if _same_shape(value, unwrap(m))]
    if len(shaped) == 1:
        yield from check_value(value, shaped[0], key, location)
        return
    # A value of the right type but out of a member's bounds: its range says more than the types.
    bounded = [m for m in members if typing.get_origin(m) is typing.Annotated and accepts(value, unwrap(m))]
    if bounded:
        yield from check_value(value, bounded[0], key, location)
        return
    yield _mismatch(hint, value, key, location)


def _same_shape(value: object, hint: Any) -> bool:
    origin = typing.get_origin(hint) or hint
    if isinstance(value, list):
        return origin in sequence_origins or origin is tuple
    if isinstance(value, Mapping):
        return origin in mapping_origins or is_object_hint(hint)
    return False


def _check_sequence(
    value: object, hint: Any, origin: Any, args: tuple[Any, ...], key: str, location: Location | None
) -> Iterator[ConfigError]:
    if not isinstance(value, list):
        yield _mismatch(hint, value, key, location)
        return
    if origin is tuple and args and not (len(args) == 2 and args[1] is Ellipsis):
        if len(value) != len(args):
            yield _problem(
                f"expected {describe_hint(hint)} ({len(args)} items), got a list of {len(value)}",
                location,
                key,
            )
            return
        item_hints = list(args)
    else:
        item_hints = [args[0] if args else Any] * len(value)
    for index, (item, item_hint) in enumerate(zip(value, item_hints, strict=True)):
        yield from check_value(item, item_hint, join_key(key, index), location_in(value, index, location))


def _check_mapping(
    value: object, hint: Any, args: tuple[Any, ...], key: str, location: Location | None
) -> Iterator[ConfigError]:
    if not isinstance(value, Mapping):
        yield _mismatch(hint, value, key, location)
        return
    value_hint = args[1] if len(args) == 2 else Any
    for name, item in value.items():
        yield from check_value(item, value_hint, join_key(key, name), location_in(value, name, location))


def _check_class(value: object, hint: type, key: str, location: Location | None) -> Iterator[ConfigError]:
    if hint is NoneType:
        ok = value is None
    elif hint is bool:
        ok = isinstance(value, bool)
    elif hint is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
        if ok and not -_INT64 <= value < _INT64:  # type: ignore[operator]
            # What no setting means and no RPC can carry (XML-RPC integers are 64-bit).
            yield _problem(f"expected an integer of at most 64 bits, got {_shown(value, key)}", location, key)
            return
    elif hint is float:
        ok = isinstance(value, int | float) and not isinstance(value, bool)
        if ok and not _is_finite(value):
            # NaN never compares, infinity never arrives: a move or a wait would never end.
            yield _problem(f"expected a finite number, got {_shown(value, key)}", location, key)
            return
    elif hint in (tuple, set, frozenset):
        ok = isinstance(value, list | hint)
    elif issubclass(hint, Enum):
        ok = enum_member(hint, value) is not None
    elif is_object_hint(hint) and isinstance(value, Mapping) and not _is_instance(value, hint):
        yield from check_object(_as_mapping(value), (hint,), key, location)
        return
    else:
        ok = _is_instance(value, hint)
    if ok:
        return
    if is_object_hint(hint):
        wanted = f"a {hint.__name__} description (a mapping with 'class')"
        yield _problem(f"expected {wanted}, got {describe_value(value)}", location, key)
    else:
        yield _mismatch(hint, value, key, location)


#: Integers a setting may hold: those of 64 bits (what XML-RPC carries).
_INT64 = 2**63


def _is_finite(value: Any) -> bool:
    """Whether the int or float ``value`` is a finite float (a 400-digit int is not)."""
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _shown(value: object, key: str) -> str:
    """``value`` for a message: a secret's never, a long number's cut (400 digits help nobody)."""
    if is_secret_key(key):
        return f"{type(value).__name__} (value not shown)"
    text = repr(value)
    return text if len(text) <= 40 else f"{text[:37]}... ({len(text)} characters)"


def _as_mapping(value: object) -> Mapping[str, Any]:
    assert isinstance(value, Mapping)
    return value


def _is_instance(value: object, hint: type) -> bool:
    try:
        return isinstance(value, hint)
    except TypeError:  # e.g. a Protocol that is not runtime-checkable: cannot tell, accept
        return True


def _is_subclass(cls: type, expected: tuple[type, ...]) -> bool:
    try:
        return issubclass(cls, expected)
    except TypeError:
        return True


#: Keys whose values are never shown in a message (a numeric password is still a password).
_SECRET_KEY = re.compile(r"(password|passwd|secret|token|credential|api_?key|private_?key)", re.IGNORECASE)


def _mismatch(hint: Any, value: object, key: str, location: Location | None) -> ConfigError:
    shown = f"{type(value).__name__} (value not shown)" if is_secret_key(key) else describe_value(value)
    return _problem(f"expected {describe_hint(hint)}, got {shown}", location, key)


def is_secret_key(key: str) -> bool:
    """Whether the (dotted) key names a secret whose value must never be printed."""
    return _SECRET_KEY.search(key.rsplit(".", 1)[-1]) is not None


def _problem(message: str, location: Location | None, key: str) -> ConfigError:
    return ConfigError(
        message,
        file=location.file if location else None,
        line=location.line if location else None,
        key=key or None,
    )
