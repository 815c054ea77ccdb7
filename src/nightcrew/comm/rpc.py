"""Serving remote calls: one place where calls are dispatched and exceptions become faults.

Every transport hands an incoming call to :meth:`RpcServer.handle` and turns what it raises into a
fault with :func:`fault_from_exception`; every caller turns a fault back into a typed exception with
:func:`exception_from_fault`. Nothing else in nightcrew converts exceptions for the wire.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

from nightcrew.clock import Clock, RealClock
from nightcrew.comm.codec import decode_arguments, encode
from nightcrew.comm.introspection import SYSTEM_PREFIX, SystemMethods
from nightcrew.errors import (
    CodecError,
    InterfaceError,
    InvalidArgumentError,
    NightcrewError,
    RemoteError,
    error_class,
)
from nightcrew.interfaces.base import Interface, interface_methods, interfaces_of
from nightcrew.timeout import DEFAULT_TIMEOUT, has_timeout, method_timeout

__all__ = ["Fault", "RpcServer", "exception_from_fault", "fault_from_exception"]

log = logging.getLogger(__name__)

#: Called with the method name before a call runs; raises to refuse it (e.g. module in error state).
CallGuard = Callable[[str], None]
#: Called with every exception a served method raised (to count it against limits).
ErrorHook = Callable[[BaseException], None]


class Fault:
    """A failed call as it travels: exception class name and message (XML-RPC faultString)."""

    __slots__ = ("error_class", "message")

    def __init__(self, error_class: str, message: str) -> None:
        self.error_class = error_class
        self.message = message

    def __repr__(self) -> str:
        return f"Fault({self.error_class!r}, {self.message!r})"


def fault_from_exception(exc: BaseException) -> Fault:
    """The fault to send for an exception raised by a served method."""
    if isinstance(exc, NightcrewError):
        return Fault(type(exc).__name__, exc.message)
    # An unexpected error is a bug in the callee; its class may not exist at the caller.
    return Fault(type(exc).__name__, f"{type(exc).__name__}: {exc}")


def exception_from_fault(fault: Fault, module: str) -> NightcrewError:
    """The exception a caller raises for a fault received from ``module``."""
    return error_class(fault.error_class)(fault.message, module=module)


class RpcServer:
    """Serves the interface methods of one object (a module) to remote callers.

    Args:
        obj: The served object; its remotely callable methods are those its interfaces declare.
        guard: Called with the method name before each call; may raise to refuse it.
        on_error: Called with every exception a method raised.
        name: The module's name, for its ``system.describe`` document.
        clock: Called for the module's clock (``system.clock``); a real clock by default.

    Besides the interface methods, every object answers the ``system.*`` methods of
    :mod:`nightcrew.comm.introspection`.
    """

    def __init__(
        self,
        obj: object,
        *,
        guard: CallGuard | None = None,
        on_error: ErrorHook | None = None,
        name: str = "",
        clock: Callable[[], Clock] = RealClock,
    ) -> None:
        self._obj = obj
        self._guard = guard
        self._on_error = on_error
        self.interfaces: list[type[Interface]] = interfaces_of(type(obj))
        self._methods = interface_methods(self.interfaces)
        self._system = SystemMethods(name or type(obj).__name__, obj, self._methods, self.interfaces, clock)

    @property
    def interface_names(self) -> list[str]:
        """Names of the served interfaces, as advertised on the wire."""
        return [iface.__name__ for iface in self.interfaces]

    @property
    def method_names(self) -> list[str]:
        return sorted(self._methods)

    async def handle(self, method: str, args: list[Any], announce: Callable[[float], None]) -> Any:
        """Run ``method`` with wire ``args``; call ``announce(timeout)`` as soon as it is known.

        Only a timeout other than :data:`~nightcrew.timeout.DEFAULT_TIMEOUT` is announced: callers
        wait the default for a call that announces nothing.

        Returns the wire-encoded result; raises the method's exception (see fault_from_exception).
        """
        try:
            return await self._handle(method, args, announce)
        except NightcrewError as exc:
            # Expected failures are reported, not dumped: the caller receives the message anyway.
            log.info("call %s() failed: %s: %s", method, type(exc).__name__, exc.message)
            self._report(exc)
            raise
        except Exception as exc:
            log.exception("call %s() failed unexpectedly", method)
            self._report(exc)
            raise

    async def _handle(self, method: str, args: list[Any], announce: Callable[[float], None]) -> Any:
        if method.startswith(SYSTEM_PREFIX):
            return await self._handle_system(method, args)
        declaration = self._methods.get(method)
        if declaration is None:
            raise InterfaceError(f"no method '{method}' (methods: {', '.join(self.method_names)})")
        if self._guard is not None:
            self._guard(method)
        # Arguments are checked (types, bounds) before the timeout is announced: a refused call
        # gets its fault at once and is never announced as a long one.
        arguments = _decode(method, declaration, args)
        implementation = getattr(self._obj, method)
        # A timeout on the implementation overrides the interface's default.
        impl_func = getattr(implementation, "__func__", implementation)
        seconds = method_timeout(impl_func if has_timeout(impl_func) else declaration, arguments)
        if seconds != DEFAULT_TIMEOUT:
            # Without an announcement callers wait the default: saying so would cost a stanza per call.
            announce(seconds)
        result = await implementation(**arguments)
        try:
            return encode(result, f"result of {method}()")
        except CodecError as exc:
            raise RemoteError(exc.message) from exc

    async def _handle_system(self, method: str, args: list[Any]) -> Any:
        # Not guarded: a module in error state can still be asked what it is. Default timeout.
        declaration = self._system.declarations.get(method)
        if declaration is None:
            known = ", ".join(sorted(self._system.declarations))
            raise InterfaceError(f"no method '{method}' (system methods: {known})")
        arguments = _decode(method, declaration, args)
        result = await self._system.bound(method)(**arguments)
        return encode(result, f"result of {method}()")

    def _report(self, exc: BaseException) -> None:
        if self._on_error is not None:
            self._on_error(exc)


def _decode(method: str, declaration: Callable[..., Any], args: list[Any]) -> dict[str, Any]:
    try:
        return decode_arguments(declaration, args)
    except CodecError as exc:
        raise InvalidArgumentError(f"{method}(): {exc.message}") from exc
