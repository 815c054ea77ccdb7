"""Arguments and results of every interface method survive the codec, sample by sample."""

from __future__ import annotations

import inspect
import typing
from collections.abc import Callable
from typing import Any

import pytest

from nightcrew.comm.codec import decode, decode_arguments, encode
from nightcrew.errors import CodecError
from nightcrew.interfaces import FitsValue, IFitsHeaderBefore, IMotion, MotionStatus
from nightcrew.interfaces.base import Interface

from .catalogue import declared_methods, method_id
from .wire_types import sample_values

METHODS = declared_methods()
Method = tuple[type[Interface], str, Callable[..., Any]]


def _argument_sets(func: Callable[..., Any]) -> list[dict[str, Any]]:
    """Keyword arguments for calls of ``func``: each sample of each parameter appears once."""
    hints = typing.get_type_hints(func)
    names = list(inspect.signature(func).parameters)[1:]
    columns = [sample_values(hints[name]) for name in names]
    count = max((len(c) for c in columns), default=1)
    return [{n: c[i % len(c)] for n, c in zip(names, columns, strict=True)} for i in range(count)]


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_arguments_round_trip(item: Method) -> None:
    _, _, func = item
    for arguments in _argument_sets(func):
        wire = {name: encode(value) for name, value in arguments.items()}
        bound = decode_arguments(func, [], wire)
        assert dict(list(bound.arguments.items())[1:]) == arguments
        # Positional calls must work as well (the XML-RPC carrier sends arguments by position).
        bound = decode_arguments(func, list(wire.values()), {})
        assert dict(list(bound.arguments.items())[1:]) == arguments


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_result_round_trips(item: Method) -> None:
    _, _, func = item
    hint = typing.get_type_hints(func)["return"]
    for value in sample_values(hint):
        decoded = decode(encode(value), hint)
        assert decoded == value
        assert type(decoded) is type(value)


def test_fits_values_keep_their_type() -> None:
    # int must stay int and bool stay bool through the FitsValue union.
    for value in (True, 3, 3.0, "x", None):
        decoded = decode(encode(value), FitsValue)
        assert decoded == value
        assert type(decoded) is type(value)


def test_fits_header_result_decodes_to_tuples() -> None:
    hint = typing.get_type_hints(IFitsHeaderBefore.get_fits_header_before)["return"]
    wire = {"EXPTIME": [2.5, "exposure time [s]"], "FILTER": ["V", "filter name"]}
    assert decode(wire, hint) == {"EXPTIME": (2.5, "exposure time [s]"), "FILTER": ("V", "filter name")}


def test_wrong_argument_type_is_refused() -> None:
    with pytest.raises(CodecError, match="argument 'device'"):
        decode_arguments(IMotion.get_motion_status, [], {"device": 5})


def test_unknown_motion_status_is_refused() -> None:
    with pytest.raises(CodecError, match="not a valid MotionStatus"):
        decode("sleeping", MotionStatus)
