"""The one Alpaca error mapping, client and server direction."""

from __future__ import annotations

import pytest

from nightcrew.bridges.alpaca.errors import (
    AlpacaActionNotImplementedError,
    AlpacaInvalidOperationError,
    AlpacaNotConnectedError,
    AlpacaValueNotSetError,
    error_from_reply,
    reply_from_error,
)
from nightcrew.errors import (
    AbortedError,
    DeviceBusyError,
    GrabImageError,
    InvalidArgumentError,
    ModuleError,
    MoveError,
    NightcrewError,
    NotSupportedError,
    ParkError,
    RemoteError,
)


@pytest.mark.parametrize(
    ("number", "cls", "name"),
    [
        (0x400, NotSupportedError, "NotImplemented"),
        (0x401, InvalidArgumentError, "InvalidValue"),
        (0x402, AlpacaValueNotSetError, "ValueNotSet"),  # an InvalidArgumentError
        (0x407, AlpacaNotConnectedError, "NotConnected"),
        (0x408, MoveError, "InvalidWhileParked"),
        (0x409, DeviceBusyError, "InvalidWhileSlaved"),
        (0x40B, DeviceBusyError, "InvalidOperation"),
        (0x40C, AlpacaActionNotImplementedError, "ActionNotImplemented"),  # a NotSupportedError
        (0x40E, AbortedError, "OperationCancelled"),
        (0x500, RemoteError, "driver error"),
        (0xFFF, RemoteError, "driver error"),
        (0x4FF, RemoteError, "unassigned error"),
    ],
)
def test_client_side_class_and_message(number: int, cls: type[NightcrewError], name: str) -> None:
    error = error_from_reply(number, "the device says no", "telescope 0 at http://127.0.0.1:1: PUT park")
    assert type(error) is cls
    assert (
        str(error)
        == f"telescope 0 at http://127.0.0.1:1: PUT park: {name} (0x{number:X}): the device says no"
    )


def test_not_connected_is_a_module_error() -> None:
    assert isinstance(error_from_reply(0x407, "", "x"), ModuleError)


@pytest.mark.parametrize(
    ("exc", "number"),
    [
        (NotSupportedError("no cooler"), 0x400),
        (InvalidArgumentError("bad binning"), 0x401),
        (ModuleError("module is in error state"), 0x407),
        (DeviceBusyError("exposing"), 0x40B),
        (ParkError("park failed"), 0x40B),
        (AbortedError("aborted"), 0x40E),
        (AlpacaValueNotSetError("targetrightascension has not been set"), 0x402),
        (AlpacaInvalidOperationError("no exposure has been started yet"), 0x40B),
        (AlpacaActionNotImplementedError("no actions"), 0x40C),
        (GrabImageError("readout failed"), 0x500),
        (RuntimeError("boom"), 0x500),
    ],
)
def test_server_side_number_and_message(exc: BaseException, number: int) -> None:
    got_number, message = reply_from_error(exc)
    assert got_number == number
    assert message.startswith(type(exc).__name__ + ": ") and str(exc.args[0]) in message


def test_round_trip_keeps_the_kind_of_error() -> None:
    for exc in (NotSupportedError("a"), InvalidArgumentError("b"), DeviceBusyError("c"), AbortedError("d")):
        number, message = reply_from_error(exc)
        assert isinstance(error_from_reply(number, message, "where"), type(exc))
