"""The modules online as the console sees them: interfaces, label, version, state, since when.

Presence (ModuleOpened/ClosedEvent) adds and removes modules; their states are polled, because
nothing on the bus announces every state change. A module that goes away while it is being looked
at is simply not listed.
"""

from __future__ import annotations

import asyncio
import logging
import time
from dataclasses import dataclass, field
from typing import Any

from nightcrew.comm.base import Comm
from nightcrew.errors import NightcrewError
from nightcrew.interfaces import IModule, ModuleState
from nightcrew.interfaces.base import Interface, interface_by_name
from nightcrew.modules.console._describe import describe_methods

__all__ = ["ModuleDirectory", "ModuleEntry"]

log = logging.getLogger(__name__)


@dataclass
class ModuleEntry:
    """One online module."""

    name: str
    interfaces: list[type[Interface]]
    online_since: float  # wall time
    label: str = ""
    version: str = ""
    state: str = "?"
    error: str = ""
    methods: dict[str, dict[str, Any]] = field(default_factory=dict)

    @property
    def interface_names(self) -> list[str]:
        return [i.__name__ for i in self.interfaces]

    def offers(self, interface: type[Interface]) -> bool:
        return any(issubclass(i, interface) for i in self.interfaces)

    def describe(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "label": self.label or self.name,
            "state": self.state,
            "error": self.error,
            "version": self.version,
            "online_since": _iso(self.online_since),
            "uptime_s": round(time.time() - self.online_since, 1),
            "interfaces": self.interface_names,
            "methods": self.methods,
        }


def _iso(wall: float) -> str:
    from datetime import UTC, datetime

    return datetime.fromtimestamp(wall, UTC).isoformat()


class ModuleDirectory:
    """The online modules (the console itself excluded)."""

    def __init__(self, comm: Comm) -> None:
        self._comm = comm
        self._online: set[str] = set()  # by presence, maybe not looked at yet
        self._entries: dict[str, ModuleEntry] = {}
        self._started = time.time()

    @property
    def entries(self) -> list[ModuleEntry]:
        return [self._entries[name] for name in sorted(self._entries)]

    def get(self, name: str) -> ModuleEntry | None:
        return self._entries.get(name)

    def first_offering(self, interface: type[Interface]) -> ModuleEntry | None:
        return next((e for e in self.entries if e.offers(interface)), None)

    async def add(self, name: str, *, at_start: bool = False) -> ModuleEntry | None:
        """Look at module ``name`` that came online; None if it went away meanwhile."""
        self._online.add(name)
        try:
            names = await self._comm.get_interface_names(name)
        except NightcrewError as exc:
            if name in self._online:
                log.info("could not look at module %s: %s", name, exc)
            return None
        interfaces = sorted(
            (i for i in (interface_by_name(n) for n in names) if i is not None), key=lambda i: i.__name__
        )
        entry = ModuleEntry(name, interfaces, self._started if at_start else time.time())
        entry.methods = describe_methods(interfaces)
        if entry.offers(IModule):
            # A module joins the network before it is ready and refuses calls until then: it is
            # listed as "starting", and the state poll fills in the rest once it answers.
            details = await self._details(name, with_identity=True)
            if details is not None:
                entry.state, entry.error, entry.label, entry.version = details
            else:
                entry.state = "starting"
        if name not in self._online:
            return None  # left while we looked
        self._entries[name] = entry
        return entry

    def remove(self, name: str) -> bool:
        """Module ``name`` went offline; True if it was listed."""
        self._online.discard(name)
        return self._entries.pop(name, None) is not None

    async def refresh_states(self) -> list[ModuleEntry]:
        """Ask every module offering IModule for its state; the entries whose state or error changed."""
        entries = [e for e in self.entries if e.offers(IModule)]
        results = await asyncio.gather(*(self._details(e.name, with_identity=not e.version) for e in entries))
        changed = []
        for entry, result in zip(entries, results, strict=True):
            if result is None or self._entries.get(entry.name) is not entry:
                continue  # did not answer (its state stays as last seen) or left meanwhile
            state, error, label, version = result
            entry.label, entry.version = label or entry.label, version or entry.version
            if (entry.state, entry.error) != (state, error):
                entry.state, entry.error = state, error
                changed.append(entry)
        return changed

    async def _details(self, name: str, *, with_identity: bool) -> tuple[str, str, str, str] | None:
        """(state, error, label, version) of ``name``; label and version empty unless asked for."""
        try:
            module = await self._comm.proxy(name, IModule)
            state = await module.get_state()
            # Only an error state has an error string: one call per module and poll, not two.
            error = await module.get_error_string() if state is ModuleState.ERROR else ""
            if not with_identity:
                return str(state), error, "", ""
            return str(state), error, await module.get_label(), await module.get_version()
        except NightcrewError:
            return None
