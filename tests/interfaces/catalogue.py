"""Test helper: every interface class defined in the nightcrew.interfaces package, found by walking it."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from collections.abc import Callable
from typing import Any

import nightcrew.interfaces
from nightcrew.interfaces.base import Interface


def _defined_interfaces() -> list[type[Interface]]:
    found: list[type[Interface]] = []
    for info in pkgutil.iter_modules(nightcrew.interfaces.__path__, "nightcrew.interfaces."):
        module = importlib.import_module(info.name)
        for obj in vars(module).values():
            if (
                isinstance(obj, type)
                and issubclass(obj, Interface)
                and obj is not Interface
                and obj.__module__ == module.__name__
            ):
                found.append(obj)
    return sorted(found, key=lambda cls: cls.__name__)


ALL_INTERFACES = _defined_interfaces()


def declared_methods() -> list[tuple[type[Interface], str, Callable[..., Any]]]:
    """(interface, name, function) for every public method an interface declares itself."""
    return [
        (iface, name, member)
        for iface in ALL_INTERFACES
        for name, member in vars(iface).items()
        if not name.startswith("_") and inspect.isfunction(member)
    ]


def method_id(item: tuple[type[Interface], str, Callable[..., Any]]) -> str:
    return f"{item[0].__name__}.{item[1]}"
