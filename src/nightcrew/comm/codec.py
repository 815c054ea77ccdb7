"""The value codec: what may travel in RPC arguments, results and events, and how.

*Wire values* are exactly the XML-RPC value types: ``None`` (nil), ``bool``, ``int`` (64-bit),
``float``, ``str``, ``bytes`` (base64), aware UTC ``datetime`` (dateTime.iso8601), ``list`` (array)
and ``dict`` with ``str`` keys (struct). Richer Python values map onto these:

=====================  ============================================
Python                 wire
=====================  ============================================
``Enum``               its value (str or int)
dataclass instance     struct of its fields
``tuple``, ``set``     array
numpy scalar           the matching int / float / bool
naive ``datetime``     taken as UTC
=====================  ============================================

Decoding is guided by the receiver's type hints (:func:`decode`), which turns structs back into
dataclasses, values into enums, arrays into tuples and, for JSON carriers that have no native
date or bytes, ISO strings into datetimes and base64 strings into bytes. Anything else is refused
with :class:`~nightcrew.errors.CodecError` — in-process too, so that nothing works locally that
would fail across the network.
"""

from __future__ import annotations

import base64
import dataclasses
import enum
import functools
import inspect
import json
import math
import types
import typing
from collections.abc import Callable, Mapping
from datetime import UTC, datetime
from typing import Any

from nightcrew.errors import CodecError
from nightcrew.interfaces.quantities import bound_problem

__all__ = [
    "Parameter",
    "bind_arguments",
    "decode",
    "decode_arguments",
    "decode_fields",
    "encode",
    "method_parameters",
]

_INT64 = 2**63
_SCALARS = (str, float, bool, type(None))
_SCALARS_AND_INT = frozenset({str, float, bool, int})


def encode(value: Any, path: str = "value") -> Any:
    """Turn ``value`` into wire values; raises CodecError naming the offending part."""
    kind = type(value)
    if kind in _SCALARS:
        return value
    if kind is int:
        if not -_INT64 <= value < _INT64:
            raise CodecError(f"{path}: integer {value} does not fit in 64 bits")
        return value
    if kind is list or kind is tuple:
        return [encode(v, f"{path}[{i}]") for i, v in enumerate(value)]
    if kind is dict:
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise CodecError(f"{path}: dict keys must be strings, got {type(k).__name__}")
            out[k] = encode(v, f"{path}.{k}")
        return out
    if isinstance(value, datetime):
        return value.replace(tzinfo=UTC) if value.tzinfo is None else value.astimezone(UTC)
    if isinstance(value, enum.Enum):
        return encode(value.value, path)
    if isinstance(value, bytes | bytearray):
        return bytes(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: encode(getattr(value, f.name), f"{path}.{f.name}") for f in dataclasses.fields(value)}
    if isinstance(value, set | frozenset):
        return [encode(v, f"{path}[]") for v in sorted(value)]
    if isinstance(value, int):  # int subclasses other than bool/enum
        return encode(int(value), path)
    if isinstance(value, str | float):
        return encode(kind.__mro__[1](value) if kind not in (str, float) else value, path)
    if hasattr(value, "dtype") and getattr(value, "shape", None) == ():  # numpy scalar
        return encode(value.item(), path)
    raise CodecError(f"{path}: values of type {kind.__name__} cannot be sent over the comm")


def decode(value: Any, hint: Any, path: str = "value") -> Any:
    """Turn wire ``value`` into a value of type ``hint``; raises CodecError if it does not fit."""
    if type(value) is hint and hint in _SCALARS_AND_INT:
        return value  # the common case, decided without looking at the hint's structure
    if hint is Any or hint is object or hint is inspect.Parameter.empty:
        return value
    if hint is type(None) or hint is None:
        if value is not None:
            raise CodecError(f"{path}: expected null, got {_kind(value)}")
        return None
    origin = typing.get_origin(hint)
    if origin is None:
        return _decode_plain(value, hint, path)
    args = typing.get_args(hint)
    if origin is typing.Union or origin is types.UnionType:
        if value is None and type(None) in args:
            return None
        choices = [arg for arg in args if arg is not type(None)]
        if len(choices) == 1:
            try:
                return decode(value, choices[0], path)
            except CodecError as exc:
                # A bound broken or a struct's own key wrong says more than the list of choices.
                if not exc.message.startswith(f"{path}: expected "):
                    raise
        for arg in choices:
            try:
                return decode(value, arg, path)
            except CodecError:
                continue
        raise CodecError(f"{path}: expected {_hint_name(hint)}, got {_kind(value)}")
    if origin is typing.Literal:
        if value not in args:
            raise CodecError(f"{path}: expected {_hint_name(hint)}, got {_kind(value)}")
        return value
    if origin is list or origin is tuple or origin is set or origin is frozenset:
        if not isinstance(value, list | tuple):
            raise CodecError(f"{path}: expected array, got {_kind(value)}")
        if origin is tuple and args and not (len(args) == 2 and args[1] is Ellipsis):
            if len(args) != len(value):
                raise CodecError(f"{path}: expected {len(args)} items, got {len(value)}")
            return tuple(
                decode(v, a, f"{path}[{i}]") for i, (v, a) in enumerate(zip(value, args, strict=True))
            )
        item = args[0] if args else Any
        items = [decode(v, item, f"{path}[{i}]") for i, v in enumerate(value)]
        return origin(items) if origin is not list else items
    if origin is dict or origin is Mapping:
        if not isinstance(value, dict):
            raise CodecError(f"{path}: expected object, got {_kind(value)}")
        vhint = args[1] if len(args) == 2 else Any
        return {k: decode(v, vhint, f"{path}.{k}") for k, v in value.items()}
    if origin is typing.Annotated:
        decoded = decode(value, args[0], path)
        _check_constraints(decoded, hint.__metadata__, path)
        return decoded
    return value


def _check_constraints(value: Any, metadata: tuple[Any, ...], path: str) -> None:
    """Refuse ``value`` when it breaks a bound declared with annotated-types (NaN breaks every one)."""
    problem = bound_problem(value, metadata)
    if problem is not None:
        raise CodecError(f"{path}: {value!r} {problem}")


def _decode_plain(value: Any, hint: Any, path: str) -> Any:
    kind = type(value)
    if hint is float:
        if kind is float or (kind is int):
            return float(value)
    elif hint is int:
        if kind is int:
            return value
    elif hint is str or hint is bool:
        if kind is hint:
            return value
    elif hint is bytes:
        if kind is bytes:
            return value
        if kind is str:
            return base64.b64decode(value)
    elif hint is datetime:
        if isinstance(value, datetime):
            return value if value.tzinfo else value.replace(tzinfo=UTC)
        if kind is str:
            try:
                parsed = datetime.fromisoformat(value)
            except ValueError as exc:
                raise CodecError(f"{path}: expected {_hint_name(hint)}, got {_kind(value)}") from exc
            return parsed if parsed.tzinfo else parsed.replace(tzinfo=UTC)
    elif isinstance(hint, type) and issubclass(hint, enum.Enum):
        try:
            return hint(value)
        except ValueError as exc:
            raise CodecError(f"{path}: expected {_hint_name(hint)}, got {_kind(value)}") from exc
    elif dataclasses.is_dataclass(hint) and isinstance(hint, type):
        if kind is not dict:
            raise CodecError(f"{path}: expected {_hint_name(hint)}, got {_kind(value)}")
        return hint(**decode_fields(hint, value, path))
    elif hint is list or hint is dict or hint is tuple:
        return decode(value, hint[Any] if hint is not dict else dict[str, Any], path)
    else:
        return value  # a type the codec does not know: leave it to the receiver
    raise CodecError(f"{path}: expected {_hint_name(hint)}, got {_kind(value)}")


def decode_fields(cls: type, data: Mapping[str, Any], path: str = "") -> dict[str, Any]:
    """Decode a struct into constructor arguments of dataclass ``cls`` (unknown keys dropped)."""
    hints = _dataclass_hints(cls)
    prefix = f"{path}." if path else ""
    out = {}
    for name, value in data.items():
        if name in hints:
            out[name] = decode(value, hints[name], prefix + name)
    return out


@functools.cache
def _dataclass_hints(cls: type) -> dict[str, Any]:
    hints = typing.get_type_hints(cls)
    return {f.name: hints.get(f.name, Any) for f in dataclasses.fields(cls)}


@dataclasses.dataclass(frozen=True)
class Parameter:
    """One parameter of a remotely callable method (``self`` excluded)."""

    name: str
    hint: Any
    default: Any  # inspect.Parameter.empty when required


@functools.cache
def method_parameters(func: Callable[..., Any]) -> tuple[tuple[Parameter, ...], Any]:
    """Parameters and return hint of a remotely callable method (cached).

    Remote calls carry arguments positionally, so ``*args``/``**kwargs`` are not allowed.
    """
    signature = inspect.signature(func)
    # With extras: bounds and units declared with Annotated are part of the method's contract.
    hints = typing.get_type_hints(func, include_extras=True)
    params = []
    for param in list(signature.parameters.values())[1:]:
        if param.kind in (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD):
            raise TypeError(f"{func.__qualname__}: remotely callable methods cannot take *args/**kwargs")
        params.append(Parameter(param.name, hints.get(param.name, Any), param.default))
    return tuple(params), hints.get("return", Any)


def bind_arguments(func: Callable[..., Any], args: tuple[Any, ...], kwargs: dict[str, Any]) -> list[Any]:
    """The complete positional argument list of a call to ``func`` (defaults filled in).

    Raises TypeError like a normal call would for missing or unexpected arguments.
    """
    params, _ = method_parameters(func)
    if not kwargs and len(args) == len(params):
        return list(args)
    if len(args) > len(params):
        raise TypeError(f"{func.__name__}() takes {len(params)} arguments but {len(args)} were given")
    values = list(args)
    for param in params[len(args) :]:
        if param.name in kwargs:
            values.append(kwargs.pop(param.name))
        elif param.default is not inspect.Parameter.empty:
            values.append(param.default)
        else:
            raise TypeError(f"{func.__name__}() missing required argument '{param.name}'")
    if kwargs:
        raise TypeError(f"{func.__name__}() got unexpected arguments: {', '.join(kwargs)}")
    return values


def decode_arguments(func: Callable[..., Any], args: list[Any]) -> dict[str, Any]:
    """Decode positional wire ``args`` of a call to ``func`` by its type hints, name → value.

    Missing trailing arguments take their defaults. Raises CodecError naming the argument (not the
    method: the caller of this function says which call it was).
    """
    params, _ = method_parameters(func)
    if len(args) > len(params):
        raise CodecError(f"takes {len(params)} arguments, got {len(args)}")
    decoded = {p.name: decode(v, p.hint, f"argument '{p.name}'") for p, v in zip(params, args, strict=False)}
    for param in params[len(args) :]:
        if param.default is inspect.Parameter.empty:
            raise CodecError(f"missing argument '{param.name}'")
        decoded[param.name] = param.default
    return decoded


#: The JSON names of wire values: errors speak JSON, the one language every client shares.
_JSON_KINDS: dict[type, str] = {
    bool: "boolean",
    int: "integer",
    float: "number",
    str: "string",
    bytes: "base64 string",
    list: "array",
    tuple: "array",
    dict: "object",
}
_SHOWN_CHARS = 40


def _kind(value: Any) -> str:
    """A value as an error shows it: its JSON type and, for scalars, itself (cut short)."""
    if value is None:
        return "null"
    if isinstance(value, datetime):
        return f"date-time {value.isoformat()}"
    kind = next((name for cls, name in _JSON_KINDS.items() if type(value) is cls), type(value).__name__)
    if isinstance(value, bool):
        return f"{kind} {str(value).lower()}"
    if isinstance(value, int | float | str):
        shown = json.dumps(value) if not isinstance(value, float) or math.isfinite(value) else repr(value)
        return f"{kind} {shown if len(shown) <= _SHOWN_CHARS else shown[:_SHOWN_CHARS] + '...'}"
    return kind


def _hint_name(hint: Any) -> str:
    """A type hint in the words of docs/catalogue.json: JSON types, enum values, struct names."""
    if hint is None or hint is type(None):
        return "null"
    origin = typing.get_origin(hint)
    if origin is typing.Annotated:
        return _hint_name(typing.get_args(hint)[0])
    if origin is typing.Union or origin is types.UnionType:
        return " or ".join(_hint_name(arg) for arg in typing.get_args(hint))
    if origin is typing.Literal:
        return "one of " + ", ".join(json.dumps(arg) for arg in typing.get_args(hint))
    if origin in (list, tuple, set, frozenset):
        return "array"
    if origin in (dict, Mapping):
        return "object"
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return "one of " + ", ".join(json.dumps(member.value) for member in hint)
    if dataclasses.is_dataclass(hint) and isinstance(hint, type):
        return f"object ({hint.__name__})"
    if hint is datetime:
        return "date-time (ISO 8601 string)"
    if isinstance(hint, type) and hint in _JSON_KINDS:
        return _JSON_KINDS[hint]
    return getattr(hint, "__name__", None) or str(hint).replace("typing.", "")
