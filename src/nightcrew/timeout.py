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

A callable receives the call's arguments by name (``self`` excluded; defaults filled in).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, TypeVar

__all__ = ["DEFAULT_TIMEOUT", "has_timeout", "method_timeout", "timeout"]

DEFAULT_TIMEOUT = 10.0
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


def method_timeout(func: Callable[..., Any], arguments: Mapping[str, Any]) -> float:
    """The timeout in seconds of a call to ``func`` with ``arguments`` (name → value, defaults in)."""
    spec: TimeoutSpec | None = getattr(func, _ATTRIBUTE, None)
    if spec is None:
        return DEFAULT_TIMEOUT
    if not callable(spec):
        return float(spec)
    return float(spec(**arguments))


def has_timeout(func: Callable[..., Any]) -> bool:
    """Whether ``func`` declares its own timeout."""
    return hasattr(func, _ATTRIBUTE)
