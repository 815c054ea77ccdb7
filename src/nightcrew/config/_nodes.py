"""Loaded configuration values that remember where each of their entries was written.

YAML mappings become :class:`ConfigNode` (a ``dict``) and sequences :class:`ConfigList` (a
``list``), so code that only reads values needs to know nothing about them; error reporting asks
them for the :class:`Location` of a key or item. Scalars stay plain Python values — their location
is the location of the key or item that holds them.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

__all__ = ["ConfigList", "ConfigNode", "Location", "join_key", "location_in"]


@dataclass(frozen=True)
class Location:
    """A place in a YAML file.

    Attributes:
        file: The file as it was named (relative to the working directory or absolute).
        line: 1-based line number.
    """

    file: str
    line: int


class ConfigNode(dict[str, Any]):
    """A configuration mapping that knows the file and line of every key.

    Args:
        items: Initial entries (without locations; use :meth:`set_located` to add located ones).
        location: Where the mapping itself starts; the fallback for keys without a location.
    """

    def __init__(
        self, items: Mapping[str, Any] | Iterable[tuple[str, Any]] = (), *, location: Location | None = None
    ) -> None:
        super().__init__(items)
        self.location = location
        self._key_locations: dict[str, Location] = {}

    def set_located(self, key: str, value: Any, location: Location | None) -> None:
        """Set ``key`` to ``value`` and remember where the key was written."""
        self[key] = value
        if location is not None:
            self._key_locations[key] = location

    def location_of(self, key: str) -> Location | None:
        """Where ``key`` was written, else where this mapping starts."""
        return self._key_locations.get(key, self.location)


class ConfigList(list[Any]):
    """A configuration sequence that knows the file and line of every item."""

    def __init__(self, *, location: Location | None = None) -> None:
        super().__init__()
        self.location = location
        self._item_locations: list[Location | None] = []

    def append_located(self, value: Any, location: Location | None) -> None:
        """Append ``value`` and remember where it was written."""
        self.append(value)
        self._item_locations.append(location)

    def location_of(self, index: int) -> Location | None:
        """Where item ``index`` was written, else where this sequence starts."""
        if 0 <= index < len(self._item_locations):
            return self._item_locations[index] or self.location
        return self.location


def location_in(container: object, key: str | int, fallback: Location | None) -> Location | None:
    """The location of ``key`` in ``container`` if it is a located node, else ``fallback``.

    Plain dicts and lists (configurations written in Python) have no locations.
    """
    if isinstance(container, ConfigNode) and isinstance(key, str):
        return container.location_of(key) or fallback
    if isinstance(container, ConfigList) and isinstance(key, int):
        return container.location_of(key) or fallback
    return fallback


def join_key(prefix: str, key: str | int) -> str:
    """The dotted key path of ``key`` below ``prefix``: ``comm.jid``, ``things[2]``."""
    if isinstance(key, int):
        return f"{prefix}[{key}]"
    return f"{prefix}.{key}" if prefix else key
