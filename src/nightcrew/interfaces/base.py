"""The base of all interfaces.

An interface is a small abstract class of ``async`` methods. A module offers an interface by
inheriting from it; others call it through a proxy that *is* an instance of the interface. Every
interface registers itself by class name, so a remote module's advertised interface names can be
turned back into classes (:func:`interface_by_name`).

Conventions: method arguments and results are wire-encodable values (see
:mod:`nightcrew.comm.codec`) with complete type hints; units are given in argument names or
docstrings (degrees, seconds, °C); optional arguments are keyword arguments with defaults.
"""

from __future__ import annotations

import inspect
from abc import ABC
from collections.abc import Callable, Iterable

__all__ = ["Interface", "interface_by_name", "interface_methods", "interfaces_of"]

_INTERFACES: dict[str, type[Interface]] = {}


class Interface(ABC):  # noqa: B024 - abstract methods live in the subclasses
    """Base class of all interfaces.

    Attributes:
        version: Interface version, increased on incompatible changes; advertised on the wire.
    """

    version: int = 1

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        # A class made only of interfaces is an interface; a module or proxy mixes in other bases.
        if all(base is Interface or is_interface(base) for base in cls.__bases__):
            if cls.__name__ in _INTERFACES:
                raise TypeError(f"interface name {cls.__name__} is already taken")
            _INTERFACES[cls.__name__] = cls


def interface_by_name(name: str) -> type[Interface] | None:
    """The interface class called ``name``, or None if this process does not know it."""
    return _INTERFACES.get(name)


def is_interface(cls: type) -> bool:
    """Whether ``cls`` is a registered interface class (not a module implementing one)."""
    return isinstance(cls, type) and _INTERFACES.get(cls.__name__) is cls


def interfaces_of(cls: type) -> list[type[Interface]]:
    """All interfaces a class (a module or a proxy class) implements, in MRO order."""
    return [c for c in cls.__mro__ if is_interface(c)]


def interface_methods(interfaces: Iterable[type[Interface]]) -> dict[str, Callable[..., object]]:
    """Name → abstract method definition for every public method declared by ``interfaces``."""
    methods: dict[str, Callable[..., object]] = {}
    for iface in interfaces:
        for name, member in vars(iface).items():
            if not name.startswith("_") and inspect.iscoroutinefunction(member):
                methods.setdefault(name, member)
    return methods
