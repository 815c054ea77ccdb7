"""Proxies: local stand-ins for remote modules.

A proxy for a module offering ``ICamera`` and ``IFilters`` *is* an instance of both
(``isinstance(proxy, ICamera)`` holds), and each interface method on it is a remote call: arguments
are bound to the interface's signature (defaults filled in), encoded, sent positionally, and the
result decoded by the method's return hint.
"""

from __future__ import annotations

import functools
from collections.abc import Awaitable, Callable
from typing import TYPE_CHECKING, Any

from nightcrew.comm.codec import bind_arguments, decode, encode, method_parameters
from nightcrew.interfaces.base import Interface, interface_methods, is_interface

if TYPE_CHECKING:
    from nightcrew.comm.base import Comm

__all__ = ["Proxy", "proxy_class"]


class Proxy:
    """Base of all proxy classes; use :meth:`nightcrew.comm.base.Comm.proxy` to get one."""

    def __init__(self, comm: Comm, name: str) -> None:
        self._comm = comm
        self._name = name

    @property
    def name(self) -> str:
        """Name of the remote module."""
        return self._name

    async def call(self, method: str, *args: Any) -> Any:
        """Call ``method`` with already wire-encodable positional arguments; returns wire values."""
        return await self._comm.execute(self._name, method, [encode(a) for a in args])

    def __repr__(self) -> str:
        interfaces = ", ".join(c.__name__ for c in type(self).__mro__ if c.__name__.startswith("I"))
        return f"<Proxy {self._name} [{interfaces}]>"


def _remote_method(name: str, declaration: Callable[..., Any]) -> Callable[..., Awaitable[Any]]:
    params, return_hint = method_parameters(declaration)
    names = [f"argument '{p.name}'" for p in params]

    async def remote(self: Proxy, *args: Any, **kwargs: Any) -> Any:
        values = bind_arguments(declaration, args, kwargs)
        wire = [encode(value, path) for value, path in zip(values, names, strict=True)]
        result = await self._comm.execute(self._name, name, wire)
        return decode(result, return_hint, f"result of {name}()")

    # Not functools.wraps: it would copy __isabstractmethod__ and keep the class abstract.
    remote.__name__ = remote.__qualname__ = name
    remote.__doc__ = declaration.__doc__
    return remote


def _leaves(interfaces: tuple[type[Interface], ...]) -> tuple[type[Interface], ...]:
    """The interfaces no other listed interface derives from (a consistent MRO needs only these)."""
    return tuple(i for i in interfaces if not any(o is not i and issubclass(o, i) for o in interfaces))


@functools.cache
def proxy_class(interfaces: tuple[type[Interface], ...]) -> type[Proxy]:
    """The proxy class implementing ``interfaces`` (cached per tuple)."""
    bases = _leaves(interfaces)
    # Methods come from every interface in the bases' MROs: ITelescope's own vars hold none of
    # IMotion's or IPointingRaDec's, and a proxy missing them would stay abstract.
    inherited = tuple(dict.fromkeys(c for base in bases for c in base.__mro__ if is_interface(c)))
    namespace: dict[str, Any] = {
        name: _remote_method(name, decl) for name, decl in interface_methods(inherited).items()
    }
    namespace["__module__"] = __name__
    title = ",".join(b.__name__ for b in bases) or "none"
    return type(f"Proxy[{title}]", (Proxy, *bases), namespace)
