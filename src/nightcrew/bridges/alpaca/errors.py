"""The one mapping between Alpaca error numbers and nightcrew's error classes, both ways.

A client turns a reply's ``ErrorNumber``/``ErrorMessage`` into a nightcrew error with
:func:`error_from_reply`; a server turns an exception into ``(ErrorNumber, ErrorMessage)`` with
:func:`reply_from_error`. Numbers from the ASCOM Alpaca API specification:

=========  ======================  ==============================  ======================
number     Alpaca name             client raises                   server sends it for
=========  ======================  ==============================  ======================
0x400      NotImplemented          NotSupportedError               NotSupportedError
0x401      InvalidValue            InvalidArgumentError            InvalidArgumentError
0x402      ValueNotSet             AlpacaValueNotSetError          AlpacaValueNotSetError
0x407      NotConnected            AlpacaNotConnectedError         ModuleError
0x408      InvalidWhileParked      MoveError                       -
0x409      InvalidWhileSlaved      DeviceBusyError                 -
0x40B      InvalidOperation        DeviceBusyError                 DeviceBusyError, MotionError,
                                                                   AlpacaInvalidOperationError
0x40C      ActionNotImplemented    AlpacaActionNotImplementedError AlpacaActionNotImplementedError
0x40E      OperationCancelled      AbortedError                    AbortedError
0x500+     driver error            RemoteError                     any other error
=========  ======================  ==============================  ======================

Transport problems have their own classes, both RemoteErrors: :class:`AlpacaConnectionError` (the
server cannot be reached or dropped the connection: a module goes to error state and reconnects)
and :class:`AlpacaReplyError` (a reply that is not valid Alpaca: malformed JSON, a missing field,
HTTP 4xx/5xx, a broken image).
"""

from __future__ import annotations

from nightcrew.errors import (
    AbortedError,
    DeviceBusyError,
    InvalidArgumentError,
    ModuleError,
    MotionError,
    MoveError,
    NightcrewError,
    NotSupportedError,
    RemoteError,
)

__all__ = [
    "ACTION_NOT_IMPLEMENTED",
    "DRIVER_ERROR",
    "INVALID_OPERATION",
    "INVALID_VALUE",
    "INVALID_WHILE_PARKED",
    "INVALID_WHILE_SLAVED",
    "NOT_CONNECTED",
    "NOT_IMPLEMENTED",
    "OPERATION_CANCELLED",
    "VALUE_NOT_SET",
    "AlpacaActionNotImplementedError",
    "AlpacaConnectionError",
    "AlpacaInvalidOperationError",
    "AlpacaNotConnectedError",
    "AlpacaReplyError",
    "AlpacaValueNotSetError",
    "error_from_reply",
    "error_name",
    "reply_from_error",
]

NOT_IMPLEMENTED = 0x400
INVALID_VALUE = 0x401
VALUE_NOT_SET = 0x402
NOT_CONNECTED = 0x407
INVALID_WHILE_PARKED = 0x408
INVALID_WHILE_SLAVED = 0x409
INVALID_OPERATION = 0x40B
ACTION_NOT_IMPLEMENTED = 0x40C
OPERATION_CANCELLED = 0x40E
#: First number of the range drivers use for their own errors (0x500..0xFFF).
DRIVER_ERROR = 0x500
_DRIVER_ERROR_LAST = 0xFFF


class AlpacaConnectionError(RemoteError):
    """The Alpaca server cannot be reached, or it dropped the connection."""


class AlpacaReplyError(RemoteError):
    """A reply that is not valid Alpaca (malformed JSON, missing field, HTTP error, broken image)."""


class AlpacaNotConnectedError(ModuleError):
    """The Alpaca device says it is not connected (0x407); the module reconnects."""


class AlpacaValueNotSetError(InvalidArgumentError):
    """A value read before it was ever set (ValueNotSet, 0x402), e.g. TargetRightAscension."""


class AlpacaInvalidOperationError(NightcrewError):
    """A call that is not valid in the device's state (InvalidOperation, 0x40B), e.g.
    LastExposureDuration before any exposure."""


class AlpacaActionNotImplementedError(NotSupportedError):
    """An ``Action`` name the device does not support (ActionNotImplemented, 0x40C)."""


#: Client side: the class raised for an error number.
_CLIENT_CLASSES: dict[int, type[NightcrewError]] = {
    NOT_IMPLEMENTED: NotSupportedError,
    INVALID_VALUE: InvalidArgumentError,
    VALUE_NOT_SET: AlpacaValueNotSetError,
    NOT_CONNECTED: AlpacaNotConnectedError,
    INVALID_WHILE_PARKED: MoveError,
    INVALID_WHILE_SLAVED: DeviceBusyError,
    INVALID_OPERATION: DeviceBusyError,
    ACTION_NOT_IMPLEMENTED: AlpacaActionNotImplementedError,
    OPERATION_CANCELLED: AbortedError,
}

#: Server side: the number sent for an error class (the first match along its MRO wins).
_SERVER_NUMBERS: dict[type[BaseException], int] = {
    AlpacaValueNotSetError: VALUE_NOT_SET,
    AlpacaInvalidOperationError: INVALID_OPERATION,
    AlpacaActionNotImplementedError: ACTION_NOT_IMPLEMENTED,
    NotSupportedError: NOT_IMPLEMENTED,
    InvalidArgumentError: INVALID_VALUE,
    ModuleError: NOT_CONNECTED,
    DeviceBusyError: INVALID_OPERATION,
    MotionError: INVALID_OPERATION,
    AbortedError: OPERATION_CANCELLED,
}

_NAMES = {
    NOT_IMPLEMENTED: "NotImplemented",
    INVALID_VALUE: "InvalidValue",
    VALUE_NOT_SET: "ValueNotSet",
    NOT_CONNECTED: "NotConnected",
    INVALID_WHILE_PARKED: "InvalidWhileParked",
    INVALID_WHILE_SLAVED: "InvalidWhileSlaved",
    INVALID_OPERATION: "InvalidOperation",
    ACTION_NOT_IMPLEMENTED: "ActionNotImplemented",
    OPERATION_CANCELLED: "OperationCancelled",
}


def error_name(number: int) -> str:
    """The Alpaca name of an error number, e.g. ``InvalidValue (0x401)``."""
    if number in _NAMES:
        name = _NAMES[number]
    elif DRIVER_ERROR <= number <= _DRIVER_ERROR_LAST:
        name = "driver error"
    else:
        name = "unassigned error"
    return f"{name} (0x{number:X})"


def error_from_reply(number: int, message: str, where: str) -> NightcrewError:
    """The nightcrew error for an Alpaca error reply (``number`` != 0).

    Args:
        number: The reply's ErrorNumber.
        message: The reply's ErrorMessage.
        where: Which device and call, e.g. ``telescope 0 at http://host:11111: PUT slewtocoordinatesasync``.
    """
    cls = _CLIENT_CLASSES.get(number, RemoteError)
    return cls(f"{where}: {error_name(number)}: {message or 'no message'}")


def reply_from_error(exc: BaseException) -> tuple[int, str]:
    """``(ErrorNumber, ErrorMessage)`` for an exception a server's device raised."""
    for cls in type(exc).__mro__:
        if cls in _SERVER_NUMBERS:
            return _SERVER_NUMBERS[cls], _message(exc)
    return DRIVER_ERROR, _message(exc)


def _message(exc: BaseException) -> str:
    text = exc.message if isinstance(exc, NightcrewError) else str(exc)
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__
