"""Test helpers: which type hints the codec can carry, and sample values of a hint.

``hint_problems`` is stricter than the codec (which passes unknown types through untouched): a hint
is accepted only if every value it allows survives encode → decode. ``sample_values`` gives several
values per hint, one per union member among them, so that round trips exercise every branch.
"""

from __future__ import annotations

import dataclasses
import enum
import itertools
import types
import typing
from datetime import UTC, datetime, timedelta, timezone
from typing import Any

_LEAVES: tuple[type, ...] = (bool, int, float, str, bytes, datetime, type(None))


def hint_problems(hint: Any, where: str = "hint", _seen: frozenset[type] = frozenset()) -> list[str]:
    """Everything about ``hint`` that the codec cannot carry faithfully; empty if it is fine."""
    if hint is Any or hint is None or hint in _LEAVES:
        return []
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin is None and isinstance(hint, type):
        if issubclass(hint, enum.Enum):
            bad = [m.name for m in hint if type(m.value) not in (str, int)]
            return [f"{where}: {hint.__name__} members {bad} are not str/int-valued"] if bad else []
        if dataclasses.is_dataclass(hint):
            if hint in _seen:
                return []
            field_hints = typing.get_type_hints(hint)
            return [
                problem
                for f in dataclasses.fields(hint)
                for problem in hint_problems(field_hints[f.name], f"{where}.{f.name}", _seen | {hint})
            ]
        if hint in (list, tuple, dict):
            return [f"{where}: bare {hint.__name__} needs item types"]
        return [f"{where}: {hint.__name__} cannot travel over the comm"]
    if origin is typing.Union or origin is types.UnionType:
        return [p for i, a in enumerate(args) for p in hint_problems(a, f"{where}|{i}", _seen)]
    if origin is typing.Literal:
        bad = [a for a in args if type(a) not in (str, int, bool)]
        return [f"{where}: Literal values {bad!r} are not str/int/bool"] if bad else []
    if origin is typing.Annotated:
        return hint_problems(args[0], where, _seen)
    if origin is list:
        return hint_problems(args[0], f"{where}[]", _seen)
    if origin is tuple:
        items = args[:1] if len(args) == 2 and args[1] is Ellipsis else args
        return [p for i, a in enumerate(items) for p in hint_problems(a, f"{where}[{i}]", _seen)]
    if origin is dict:
        if args[0] is not str:
            return [f"{where}: dict keys must be str, not {args[0]}"]
        return hint_problems(args[1], f"{where}{{}}", _seen)
    return [f"{where}: {hint} cannot travel over the comm"]


_DATETIMES = [
    datetime(2031, 3, 14, 21, 5, 9, 123456, tzinfo=UTC),
    # Another zone: the codec converts to UTC, which must still compare equal.
    datetime(2031, 3, 15, 3, 0, 0, tzinfo=timezone(timedelta(hours=-4))),
]
_SCALAR_SAMPLES: dict[Any, list[Any]] = {
    bool: [True, False],
    int: [0, -7, 2**62],
    float: [1.25, -0.0, 3.0, 1e300],
    str: ["", "Ünïcode ✓ <xml>&"],
    bytes: [b"", b"\x00\xffbinary"],
    datetime: _DATETIMES,
    type(None): [None],
    None: [None],
    # Any is carried as is; only scalars keep their type through it.
    Any: ["anything", 42, None],
}


def _zip_cycled(columns: list[list[Any]]) -> list[tuple[Any, ...]]:
    """Rows taking the i-th sample of every column, cycling the shorter ones."""
    if not columns:
        return [()]
    count = max(len(c) for c in columns)
    return [tuple(c[i % len(c)] for c in columns) for i in range(count)]


def sample_values(hint: Any) -> list[Any]:
    """Several values of type ``hint``, covering every union member somewhere."""
    if hint in _SCALAR_SAMPLES:
        return list(_SCALAR_SAMPLES[hint])
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin is None and isinstance(hint, type) and issubclass(hint, enum.Enum):
        members = list(hint)
        return [members[0], members[-1]]
    if origin is None and dataclasses.is_dataclass(hint) and isinstance(hint, type):
        field_hints = typing.get_type_hints(hint)
        names = [f.name for f in dataclasses.fields(hint)]
        columns = [sample_values(field_hints[n]) for n in names]
        return [hint(**dict(zip(names, row, strict=True))) for row in _zip_cycled(columns)]
    if origin is typing.Union or origin is types.UnionType:
        return list(itertools.chain.from_iterable(sample_values(a) for a in args))
    if origin is typing.Literal:
        return list(args)
    if origin is typing.Annotated:
        return sample_values(args[0])
    if origin is list:
        return [sample_values(args[0]), []]
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return [tuple(sample_values(args[0])), ()]
        return list(_zip_cycled([sample_values(a) for a in args]))
    if origin is dict:
        items = sample_values(args[1])
        return [{f"key{i}": v for i, v in enumerate(items)}, {}]
    raise TypeError(f"no samples for {hint}")
