"""The nightcrew exception tree.

Every error nightcrew raises on purpose derives from :class:`NightcrewError`::

    NightcrewError
    ├── ConfigError             bad configuration (file, line and key named)
    ├── CodecError              a value that cannot travel over the wire
    ├── InterfaceError          a module lacks a required interface / unknown method
    ├── ModuleError             a module is in error state or cannot serve the call
    ├── RemoteError             failure of a remote call (the remote class is unknown)
    │   ├── RemoteTimeoutError  the call's announced timeout passed
    │   └── ForbiddenError      the caller may not call this method
    ├── MotionError
    │   ├── InitError, ParkError, MoveError
    ├── GrabImageError          an exposure failed
    ├── CalibratorError         a flat-field light did not come on (or go off)
    ├── AbortedError            an action was aborted on request
    ├── DeviceBusyError         the device is doing something else
    ├── NotSupportedError       the device cannot do this
    └── InvalidArgumentError    an argument is out of range or of the wrong kind

Errors keep their class across RPC: a remote method raising ``MoveError`` makes the caller's proxy
raise ``MoveError`` too, with :attr:`NightcrewError.module` set to the remote module's name. Classes
are looked up by name (:func:`error_class`), so a new error class only needs to derive from
``NightcrewError`` to be transported faithfully. An unknown class name arrives as ``RemoteError``.
"""

from __future__ import annotations

__all__ = [
    "AbortedError",
    "CalibratorError",
    "CodecError",
    "ConfigError",
    "DeviceBusyError",
    "ForbiddenError",
    "GrabImageError",
    "InitError",
    "InterfaceError",
    "InvalidArgumentError",
    "ModuleError",
    "MotionError",
    "MoveError",
    "NightcrewError",
    "NotSupportedError",
    "ParkError",
    "RemoteError",
    "RemoteTimeoutError",
    "error_class",
]

_ERROR_CLASSES: dict[str, type[NightcrewError]] = {}


class NightcrewError(Exception):
    """Base of all nightcrew errors.

    Args:
        message: What went wrong, for a person.
        module: Name of the module where the error was raised, if it came over the comm.
    """

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        _ERROR_CLASSES[cls.__name__] = cls

    def __init__(self, message: str = "", *, module: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.module = module

    def __str__(self) -> str:
        if self.module:
            return f"{self.module}: {self.message}"
        return self.message


_ERROR_CLASSES["NightcrewError"] = NightcrewError


def error_class(name: str) -> type[NightcrewError]:
    """Return the nightcrew error class called ``name``, or :class:`RemoteError` if unknown."""
    return _ERROR_CLASSES.get(name, RemoteError)


class ConfigError(NightcrewError):
    """A configuration is invalid.

    Args:
        message: What is wrong.
        file: The YAML file, if known.
        line: 1-based line in that file, if known.
        key: Dotted key path inside the file, if known (``comm.jid``).
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        line: int | None = None,
        key: str | None = None,
    ) -> None:
        super().__init__(message)
        self.file = file
        self.line = line
        self.key = key

    def __str__(self) -> str:
        where = ""
        if self.file:
            where = self.file + (f":{self.line}" if self.line else "") + ": "
        key = f"key '{self.key}': " if self.key else ""
        return f"{where}{key}{self.message}"


class CodecError(NightcrewError):
    """A value cannot be encoded for or decoded from the wire."""


class InterfaceError(NightcrewError):
    """A module does not offer a required interface, or a method is unknown."""


class ModuleError(NightcrewError):
    """A module cannot serve a call, e.g. because it is in error state."""


class RemoteError(NightcrewError):
    """A remote call failed; raised as is when the remote error class is not known here."""


class RemoteTimeoutError(RemoteError):
    """A remote call did not finish within the timeout its callee announced."""


class ForbiddenError(RemoteError):
    """The caller is not allowed to call this method."""


class MotionError(NightcrewError):
    """A motion (telescope, roof, focuser, ...) failed."""


class InitError(MotionError):
    """Initialising a device failed."""


class ParkError(MotionError):
    """Parking a device failed."""


class MoveError(MotionError):
    """A move failed or was refused."""


class GrabImageError(NightcrewError):
    """Taking an image failed."""


class CalibratorError(NightcrewError):
    """A flat-field light did not reach the state asked for (on and stable, or off)."""


class AbortedError(NightcrewError):
    """An action was aborted on request."""


class DeviceBusyError(NightcrewError):
    """The device is busy with another action."""


class NotSupportedError(NightcrewError):
    """The device or module does not support this."""


class InvalidArgumentError(NightcrewError):
    """An argument is out of range or of the wrong kind."""
