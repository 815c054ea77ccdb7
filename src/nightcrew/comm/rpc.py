"""Serving remote calls: one place where calls are dispatched and exceptions become faults.

Every transport hands an incoming call to :meth:`RpcServer.handle` and turns what it raises into a
fault with :func:`fault_from_exception`; every caller turns a fault back into a typed exception with
:func:`exception_from_fault`. Nothing else in nightcrew converts exceptions for the wire.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from typing import Any

from nightcrew.clock import Clock, RealClock
from nightcrew.comm.codec import decode_arguments, encode, method_parameters
from nightcrew.comm.introspection import SYSTEM_PREFIX, SystemMethods
from nightcrew.errors import (
    CodecError,
    ForbiddenError,
    InterfaceError,
    InvalidArgumentError,
    NightcrewError,
    RemoteError,
    error_class,
)
from nightcrew.interfaces.base import Interface, interface_methods, interfaces_of, is_interface
from nightcrew.security import AuditLog, Policy, is_state_changing
from nightcrew.timeout import DEFAULT_TIMEOUT, has_timeout, method_timeout

__all__ = [
    "MAX_ARGUMENT_BYTES",
    "MAX_ARGUMENT_DEPTH",
    "MAX_FAULT_CHARS",
    "Fault",
    "RpcServer",
    "check_wire_arguments",
    "exception_from_fault",
    "fault_from_exception",
    "shorten",
]

log = logging.getLogger(__name__)

#: Largest size of a call's arguments (bytes of text and binary, plus 8 per value). Images never
#: travel in calls (only VFS paths do), so a megabyte is far beyond any honest call.
MAX_ARGUMENT_BYTES = 1_000_000
#: Deepest nesting of lists and structs in arguments.
MAX_ARGUMENT_DEPTH = 32
#: Longest fault message sent back (the rest is cut, with a note of how much).
MAX_FAULT_CHARS = 1_000
#: Longest method name or value shown in a log line.
MAX_SHOWN_CHARS = 200

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
    """The fault to send for an exception raised by a served method (message cut to a bound)."""
    if isinstance(exc, NightcrewError):
        return Fault(type(exc).__name__, shorten(exc.message, MAX_FAULT_CHARS))
    # An unexpected error is a bug in the callee; its class may not exist at the caller.
    return Fault(type(exc).__name__, shorten(f"{type(exc).__name__}: {exc}", MAX_FAULT_CHARS))


def shorten(text: str, limit: int = MAX_SHOWN_CHARS) -> str:
    """``text`` cut to ``limit`` characters, saying how much was left out (arguments are never
    echoed whole into a fault or a log line: an 8-MB argument would be 8 MB of log)."""
    if len(text) <= limit:
        return text
    return f"{text[:limit]}... ({len(text) - limit} more characters)"


def check_wire_arguments(method: str, args: list[Any], names: Sequence[str] = ()) -> None:
    """Refuse arguments beyond :data:`MAX_ARGUMENT_DEPTH` / :data:`MAX_ARGUMENT_BYTES`, or holding
    NaN or infinity (no setting nightcrew has means anything with them), before decoding them.
    ``names`` are the method's parameter names, so that a refusal names the argument."""
    size = 0
    stack: list[tuple[Any, int, str]] = [
        (arg, 1, f"argument '{names[i]}'" if i < len(names) else f"argument {i + 1}")
        for i, arg in enumerate(args)
    ]
    while stack:
        value, depth, where = stack.pop()
        size += 8
        if isinstance(value, str | bytes):
            size += len(value)
        elif isinstance(value, float) and not math.isfinite(value):
            shown = "NaN" if math.isnan(value) else ("Infinity" if value > 0 else "-Infinity")
            raise InvalidArgumentError(f"{shorten(method, 60)}(): {where}: {shown} is not a finite number")
        elif isinstance(value, list | dict):
            if depth >= MAX_ARGUMENT_DEPTH:
                raise InvalidArgumentError(
                    f"{shorten(method, 60)}(): {where} nests deeper than {MAX_ARGUMENT_DEPTH} levels"
                )
            if isinstance(value, dict):
                size += sum(len(key) for key in value)
                stack.extend((item, depth + 1, where) for item in value.values())
            else:
                stack.extend((item, depth + 1, where) for item in value)
        if size > MAX_ARGUMENT_BYTES:
            raise InvalidArgumentError(
                f"{shorten(method, 60)}(): arguments larger than {MAX_ARGUMENT_BYTES} bytes"
            )


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
        policy: Who may call what (None: everyone everything); checked in :meth:`handle`.
        audit: Where state-changing calls are recorded (None: nowhere).
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
        policy: Policy | None = None,
        audit: AuditLog | None = None,
        clock: Callable[[], Clock] = RealClock,
    ) -> None:
        self._obj = obj
        self._guard = guard
        self._on_error = on_error
        self._name = name
        self._policy = policy
        self._audit = audit
        self.interfaces: list[type[Interface]] = interfaces_of(type(obj))
        self._methods = interface_methods(self.interfaces)
        self._interface_of = {
            method: iface.__name__
            for iface in reversed(self.interfaces)
            for method in interface_methods([iface])
        }
        self._system = SystemMethods(name or type(obj).__name__, obj, self._methods, self.interfaces, clock)

    @property
    def interface_names(self) -> list[str]:
        """Names of the served interfaces, as advertised on the wire."""
        return [iface.__name__ for iface in self.interfaces]

    @property
    def method_names(self) -> list[str]:
        return sorted(self._methods)

    def may_call(self, caller: str | None, method: str) -> bool:
        """Whether ``caller`` may call ``method`` here (always, without a policy or a known caller)."""
        if self._policy is None or caller is None:
            return True
        return self._policy.allows(caller, self._name, method, self._interface_of.get(method))

    def methods_for(self, caller: str | None) -> list[str]:
        """The methods ``caller`` may call (what listings show it)."""
        return [method for method in self.method_names if self.may_call(caller, method)]

    def interfaces_for(self, caller: str | None) -> list[str]:
        """Names of the served interfaces announced to ``caller``: those with a method it may call.

        An interface that declares nothing itself (``ICamera`` made of others) counts its bases'
        methods. Without a policy (or a known caller) every interface is announced.
        """
        if self._policy is None or caller is None:
            return self.interface_names
        allowed = set(self.methods_for(caller))
        return [
            iface.__name__
            for iface in self.interfaces
            if allowed & set(interface_methods(base for base in iface.__mro__ if is_interface(base)))
        ]

    async def handle(
        self, method: str, args: list[Any], announce: Callable[[float], None], caller: str | None = None
    ) -> Any:
        """Like :meth:`_dispatch`, after the access check, recorded in the audit trail if it changes state."""
        outcome = "ok"
        try:
            # system.* (introspection, clock) reads only: open to every caller, never audited.
            if not method.startswith(SYSTEM_PREFIX) and not self.may_call(caller, method):
                outcome = "forbidden"
                log.warning("refused %s() to %s: not allowed by the policy", shorten(method), caller)
                raise ForbiddenError(f"{caller} may not call {self._name}.{shorten(method, 60)}()")
            return await self._dispatch(method, args, announce, caller)
        except BaseException as exc:
            if outcome == "ok":
                outcome = type(exc).__name__
            raise
        finally:
            if self._audit is not None and is_state_changing(method) and not method.startswith(SYSTEM_PREFIX):
                self._audit.record(caller or "?", self._name, method, args, outcome)

    async def _dispatch(
        self, method: str, args: list[Any], announce: Callable[[float], None], caller: str | None = None
    ) -> Any:
        """Run ``method`` with wire ``args``; call ``announce(timeout)`` as soon as it is known.

        Only a timeout other than :data:`~nightcrew.timeout.DEFAULT_TIMEOUT` is announced: callers
        wait the default for a call that announces nothing.

        Returns the wire-encoded result; raises the method's exception (see fault_from_exception).
        """
        try:
            return await self._handle(method, args, announce, caller)
        except NightcrewError as exc:
            # Expected failures are reported, not dumped: the caller receives the message anyway.
            log.info("call %s() failed: %s: %s", shorten(method), type(exc).__name__, shorten(exc.message))
            self._report(exc)
            raise
        except Exception as exc:
            log.exception("call %s() failed unexpectedly", shorten(method))
            self._report(exc)
            raise

    async def _handle(
        self, method: str, args: list[Any], announce: Callable[[float], None], caller: str | None
    ) -> Any:
        if method.startswith(SYSTEM_PREFIX):
            return await self._handle_system(method, args, caller)
        declaration = self._methods.get(method)
        if declaration is None:
            raise InterfaceError(
                f"no method '{shorten(method, 60)}' (methods: {', '.join(self.method_names)})"
            )
        if self._guard is not None:
            self._guard(method)
        check_wire_arguments(method, args, [p.name for p in method_parameters(declaration)[0]])
        # Arguments are checked (types, bounds) before the timeout is announced: a refused call
        # gets its fault at once and is never announced as a long one.
        arguments = _decode(method, declaration, args)
        implementation = getattr(self._obj, method)
        # A timeout on the implementation overrides the interface's default.
        impl_func = getattr(implementation, "__func__", implementation)
        seconds = method_timeout(impl_func if has_timeout(impl_func) else declaration, arguments, self._obj)
        if seconds != DEFAULT_TIMEOUT:
            # Without an announcement callers wait the default: saying so would cost a stanza per call.
            announce(seconds)
        result = await implementation(**arguments)
        try:
            return encode(result, f"result of {method}()")
        except CodecError as exc:
            raise RemoteError(exc.message) from exc

    async def _handle_system(self, method: str, args: list[Any], caller: str | None) -> Any:
        # Not guarded: a module in error state can still be asked what it is. Default timeout.
        # Introspection shows the caller only what it may call (listings, signatures, documents).
        declaration = self._system.declarations.get(method)
        if declaration is None:
            known = ", ".join(sorted(self._system.declarations))
            raise InterfaceError(f"no method '{method}' (system methods: {known})")
        arguments = _decode(method, declaration, args)
        system = self._system
        if self._policy is not None and caller is not None:
            system = system.restricted(set(self.methods_for(caller)), self.interfaces_for(caller))
        result = await system.bound(method)(**arguments)
        return encode(result, f"result of {method}()")

    def _report(self, exc: BaseException) -> None:
        if self._on_error is not None:
            self._on_error(exc)


def _decode(method: str, declaration: Callable[..., Any], args: list[Any]) -> dict[str, Any]:
    try:
        return decode_arguments(declaration, args)
    except CodecError as exc:
        raise InvalidArgumentError(f"{method}(): {exc.message}") from exc
