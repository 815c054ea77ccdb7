"""The ``system.*`` methods every module answers: XML-RPC introspection, its catalogue entry, its clock.

==========================  ==========================================================================
``system.listMethods()``    names of every callable method, ``system.*`` included, sorted
``system.methodSignature``  ``[[result type, parameter types...]]`` in XML-RPC type names
``system.methodHelp``       the method's docstring
``system.describe``         the module's OpenRPC document; with an interface name, that interface's
``system.clock``            ``{"time": now on the module's clock, "speed": clock s per wall s}``
==========================  ==========================================================================

They are served by :class:`~nightcrew.comm.rpc.RpcServer` for every module and transport, never
refused by a module's state (a module in error state can still be asked what it is), and take the
default timeout, so they are never announced.
"""

from __future__ import annotations

import copy
import dataclasses
import enum
import inspect
import types
import typing
from collections.abc import Callable, Mapping
from datetime import datetime
from typing import Any

from nightcrew.clock import Clock
from nightcrew.comm.codec import method_parameters
from nightcrew.errors import InterfaceError
from nightcrew.interfaces.base import Interface

__all__ = ["SYSTEM_PREFIX", "SystemMethods", "xmlrpc_type"]

SYSTEM_PREFIX = "system."

_SCALAR_TYPES: dict[Any, str] = {
    bool: "boolean",
    int: "int",
    float: "double",
    str: "string",
    bytes: "base64",
    datetime: "dateTime.iso8601",
    type(None): "nil",
    None: "nil",
}


def xmlrpc_type(hint: Any) -> str:
    """The XML-RPC type name a value of ``hint`` travels as (``undef`` when it may be several)."""
    if hint in _SCALAR_TYPES:
        return _SCALAR_TYPES[hint]
    origin = typing.get_origin(hint)
    if origin is typing.Annotated:
        return xmlrpc_type(typing.get_args(hint)[0])
    if origin is typing.Union or origin is types.UnionType:
        kinds = {xmlrpc_type(arg) for arg in typing.get_args(hint) if arg is not type(None)}
        return kinds.pop() if len(kinds) == 1 else "undef"
    if origin in (list, tuple, set, frozenset) or hint in (list, tuple, set, frozenset):
        return "array"
    if (
        origin in (dict, Mapping)
        or hint is dict
        or (dataclasses.is_dataclass(hint) and isinstance(hint, type))
    ):
        return "struct"
    if origin is typing.Literal:
        return _common({xmlrpc_type(type(value)) for value in typing.get_args(hint)})
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return _common({xmlrpc_type(type(member.value)) for member in hint})
    return "undef"  # Any, or a type the codec passes through


def _common(kinds: set[str]) -> str:
    return kinds.pop() if len(kinds) == 1 else "undef"


class SystemMethods:
    """The ``system.*`` methods of one served object.

    Args:
        name: The module's name (the title of its document).
        obj: The served object.
        methods: Its callable methods, name → interface declaration.
        interfaces: The interfaces it serves.
        clock: Called for the module's clock at the time of a ``system.clock`` call.
    """

    def __init__(
        self,
        name: str,
        obj: object,
        methods: Mapping[str, Callable[..., object]],
        interfaces: list[type[Interface]],
        clock: Callable[[], Clock],
    ) -> None:
        self._name = name
        self._obj = obj
        self._methods = methods
        self._interfaces = {iface.__name__: iface for iface in interfaces}
        self._clock = clock
        self.declarations: dict[str, Callable[..., Any]] = {
            "system.listMethods": SystemMethods.list_methods,
            "system.methodSignature": SystemMethods.method_signature,
            "system.methodHelp": SystemMethods.method_help,
            "system.describe": SystemMethods.describe,
            "system.clock": SystemMethods.clock,
        }

    def restricted(self, methods: set[str], interfaces: list[str]) -> SystemMethods:
        """These system methods as one caller sees them: only ``methods`` and ``interfaces``."""
        view = copy.copy(self)
        view._methods = {name: func for name, func in self._methods.items() if name in methods}
        view._interfaces = {name: iface for name, iface in self._interfaces.items() if name in interfaces}
        return view

    def bound(self, method: str) -> Callable[..., Any]:
        """The implementation of ``method`` (a name from :attr:`declarations`)."""
        bound: Callable[..., Any] = self.declarations[method].__get__(self)
        return bound

    def _declaration(self, method: str) -> Callable[..., Any]:
        declaration = self._methods.get(method) or self.declarations.get(method)
        if declaration is None:
            known = ", ".join(sorted([*self._methods, *self.declarations]))
            raise InterfaceError(f"no method '{method}' (methods: {known})")
        return declaration

    async def list_methods(self) -> list[str]:
        """Names of every method this module answers, system.* included."""
        return sorted([*self._methods, *self.declarations])

    async def method_signature(self, method: str) -> list[list[str]]:
        """The one signature of ``method``: its result type, then its parameter types (XML-RPC names)."""
        params, returns = method_parameters(self._declaration(method))
        return [[xmlrpc_type(returns), *(xmlrpc_type(p.hint) for p in params)]]

    async def method_help(self, method: str) -> str:
        """The docstring of ``method``."""
        return inspect.getdoc(self._declaration(method)) or ""

    async def describe(self, interface: str | None = None) -> dict[str, Any]:
        """This module's OpenRPC document (all its methods), or that of one interface it serves."""
        # pydantic, which writes the schemas, is loaded only when someone asks.
        from nightcrew.comm.catalogue import interface_document, module_document

        if interface is None:
            return module_document(self._obj, self._name, self._methods, list(self._interfaces.values()))
        found = self._interfaces.get(interface)
        if found is None:
            offered = ", ".join(sorted(self._interfaces))
            raise InterfaceError(f"module '{self._name}' does not offer {interface} (offers: {offered})")
        return interface_document(found, visible=set(self._methods))

    async def clock(self) -> dict[str, Any]:
        """The module's clock: ``time`` now (UTC) and ``speed`` (clock seconds per wall second)."""
        clock = self._clock()
        return {"time": clock.now(), "speed": clock.speed}
