"""Arguments and results of every interface method survive the codec, sample by sample."""

from __future__ import annotations

import typing
from collections.abc import Callable
from typing import Any

import pytest

from nightcrew.comm.codec import decode, encode
from nightcrew.errors import CodecError
from nightcrew.interfaces import (
    CalibratorState,
    CoverState,
    FitsValue,
    IFitsHeaderBefore,
    IMotion,
    ISwitch,
    MotionStatus,
    SwitchInfo,
)
from nightcrew.interfaces.base import Interface

from .catalogue import declared_methods, method_id
from .wire_types import sample_values

METHODS = declared_methods()
Method = tuple[type[Interface], str, Callable[..., Any]]


@pytest.mark.parametrize("item", METHODS, ids=method_id)
def test_arguments_round_trip(item: Method) -> None:
    # Decoded one by one with the parameter's hint, as the RPC layer does on the receiving end.
    _, _, func = item
    for name, hint in typing.get_type_hints(func).items():
        if name == "return":
            continue
        for value in sample_values(hint):
            decoded = decode(encode(value), hint, f"argument '{name}'")
            assert decoded == value
            assert type(decoded) is type(value)


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
    hint = typing.get_type_hints(IMotion.get_motion_status)["device"]
    with pytest.raises(CodecError, match="expected string or null, got integer 5"):
        decode(5, hint)


def test_unknown_motion_status_is_refused() -> None:
    with pytest.raises(CodecError, match=r'expected one of "parked", .*, got string "sleeping"'):
        decode("sleeping", MotionStatus)


def test_switch_list_decodes_to_switch_infos() -> None:
    hint = typing.get_type_hints(ISwitch.get_switches)["return"]
    heater = SwitchInfo(
        index=1,
        name="Dew heater",
        description="0-100 %",
        can_write=True,
        min_value=0.0,
        max_value=100.0,
        step=0.5,
    )
    decoded = decode(encode([heater]), hint)
    assert decoded == [heater]
    assert type(decoded[0]) is SwitchInfo


@pytest.mark.parametrize(
    ("enum_class", "wire"), [(CoverState, "not_present"), (CalibratorState, "not_ready")]
)
def test_cover_calibrator_states_travel_as_strings(
    enum_class: type[CoverState | CalibratorState], wire: str
) -> None:
    assert encode(enum_class(wire)) == wire
    first = next(iter(enum_class)).value
    with pytest.raises(CodecError, match=rf'expected one of "{first}", .*, got string "half_open"'):
        decode("half_open", enum_class)
