"""The ``@timeout`` decorator: how long a remotely callable method may take.

Undecorated methods get :data:`DEFAULT_TIMEOUT`, which callers assume. Any other timeout the callee
announces to the caller as soon as a call arrives; the caller then waits at most that long (plus
the transport's grace) and raises :class:`~nightcrew.errors.RemoteTimeoutError` afterwards.
Timeouts are in clock seconds (see :mod:`nightcrew.clock`).

Examples::

    @timeout(1200)
    async def init(self) -> None: ...

    @timeout(lambda exposure_time, **_: exposure_time + 30)
    async def grab_data(self, exposure_time: float) -> str: ...

A callable receives the call's arguments by name (defaults filled in); one with a parameter named
``self`` also receives the module the call runs on, for what the module knows and the arguments do
not say (a camera's exposure time and read-out, a mount's slew rate)::

    @timeout(lambda self, **_: self.exposure_time + self.readout_time + 60)
    async def grab_data(self, broadcast: bool = True) -> str: ...

An implementation's own ``@timeout`` replaces its interface's for calls to it; the catalogue shows
the interface's (docs/protocol.md).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

__all__ = [
    "DEFAULT_TIMEOUT",
    "WALL_ALLOWANCE",
    "has_timeout",
    "method_timeout",
    "needs_owner",
    "timeout",
    "wall_allowance",
]

DEFAULT_TIMEOUT = 10.0
#: Wall seconds a timeout computed from a device's own figures leaves for what takes wall time
#: (calls, events, a busy machine), which a fast clock does not shrink.
WALL_ALLOWANCE = 10.0
_ATTRIBUTE = "__nightcrew_timeout__"

F = TypeVar("F", bound=Callable[..., Any])
TimeoutSpec = float | Callable[..., float]


def timeout(spec: TimeoutSpec) -> Callable[[F], F]:
    """Declare the timeout of a remotely callable method: seconds, or a function of its arguments."""
    if not callable(spec) and not float(spec) > 0:
        raise ValueError(f"timeout must be > 0 seconds, got {spec}")

    def decorate(func: F) -> F:
        setattr(func, _ATTRIBUTE, spec)
        return func

    return decorate


def method_timeout(func: Callable[..., Any], arguments: Mapping[str, Any], owner: object = None) -> float:
    """The timeout in seconds of a call to ``func`` with ``arguments`` (name → value, defaults in)
    on ``owner`` (the module; needed by a timeout computed from the module's own settings).

    Raises:
        TypeError: A computed timeout without the values it needs (e.g. no ``owner``).
    """
    spec: TimeoutSpec | None = getattr(func, _ATTRIBUTE, None)
    if spec is None:
        return DEFAULT_TIMEOUT
    if not callable(spec):
        return float(spec)
    if needs_owner(spec):
        if owner is None:
            raise TypeError("this timeout is computed from the module's settings")
        return float(spec(self=owner, **arguments))
    return float(spec(**arguments))


def needs_owner(spec: Callable[..., float]) -> bool:
    """Whether a computed timeout reads the module (has a parameter named ``self``)."""
    return "self" in inspect.signature(spec).parameters


def has_timeout(func: Callable[..., Any]) -> bool:
    """Whether ``func`` declares its own timeout."""
    return hasattr(func, _ATTRIBUTE)


def wall_allowance(speed: float) -> float:
    """:data:`WALL_ALLOWANCE` in clock seconds, for a clock running ``speed`` clock seconds per wall
    second: add it to a timeout computed from a device's figures (exposure, read-out, slew)."""
    return WALL_ALLOWANCE * speed
