"""Modules on a fresh in-process network, all sharing one fast clock, fixed epoch and site."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any, TypeVar

import pytest

from nightcrew.clock import AcceleratedClock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.modules import Module
from nightcrew.site import Site
from nightcrew.vfs import MemoryFile, VirtualFileSystem

M = TypeVar("M", bound=Module)

#: A winter night at a mid-northern site: Orion and the Pleiades are up, the Sun is down.
EPOCH = "2024-01-15T22:00:00+00:00"
SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")


class Observatory:
    """Builds modules on one network with one clock and one in-memory VFS; closes them after."""

    def __init__(self, speed: float) -> None:
        self.clock = AcceleratedClock(EPOCH, speed=speed)
        self.vfs = VirtualFileSystem({"cache": MemoryFile()})
        self._network = LocalNetwork()
        self._modules: list[Module] = []

    async def start(self, cls: type[M], name: str, **kwargs: Any) -> M:
        kwargs.setdefault("clock", self.clock)
        kwargs.setdefault("site", SITE)
        kwargs.setdefault("vfs", self.vfs)
        module = cls(comm=LocalComm(name, network=self._network), **kwargs)
        self._modules.append(module)
        await module.open()
        return module

    async def close(self) -> None:
        for module in reversed(self._modules):
            await module.close()


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    """Clock at 100x: a 60 s roof closing takes 0.6 s of wall time."""
    obs = Observatory(speed=100.0)
    try:
        yield obs
    finally:
        await obs.close()
