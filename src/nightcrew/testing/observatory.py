"""An observatory in one process for tests: modules on one local network, one clock, one VFS."""

from __future__ import annotations

from datetime import datetime
from types import TracebackType
from typing import Any, TypeVar

from nightcrew.clock import AcceleratedClock, Clock, VirtualClock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.modules import Module
from nightcrew.site import Site
from nightcrew.testing.waiting import Condition, wait_for
from nightcrew.vfs import MemoryFile, VirtualFileSystem

__all__ = ["EPOCH", "SITE", "Observatory"]

M = TypeVar("M", bound=Module)

#: A winter night at a mid-northern site: Orion and the Pleiades are up, the Sun is down.
EPOCH = "2024-01-15T22:00:00+00:00"
#: The site every test observatory stands at unless told otherwise.
SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")


class Observatory:
    """Builds modules on one in-process network with one clock, site and VFS; closes them after.

    ``clock``, ``site`` and ``vfs`` are plain attributes: a test may replace them before it starts
    the modules that should use the new ones.

    By default the clock is a :class:`~nightcrew.clock.VirtualClock` started at ``epoch``: the
    test's event loop runs on virtual time, so simulated minutes pass in milliseconds and the
    outcome does not depend on how busy the machine is. Anything that talks to the outside world
    (a server in a subprocess, a real device) needs wall time: give a ``RealClock`` (or a
    ``speed``) instead, since every ``asyncio`` timeout of a virtual loop is virtual too.

    Args:
        speed: Run an AcceleratedClock at this speed from ``epoch`` instead (ignored with ``clock``).
        clock: The clock to use instead, e.g. a RealClock for devices that run in real time.
        epoch: Start of the clock.
        site: Where the observatory stands; None for modules that need no site.
        vfs: The file system; by default one in-memory root ``/cache``. The modules share it and
            do not close it: :meth:`close` closes the default one; one given here is the caller's
            to close (after this observatory).

    Example::

        async with Observatory() as obs:
            roof = await obs.start(SimRoof, "roof", open_time=60.0)
            await roof.open_roof()  # 60 clock seconds, a few ms of wall time
    """

    def __init__(
        self,
        speed: float | None = None,
        *,
        clock: Clock | None = None,
        epoch: datetime | str = EPOCH,
        site: Site | None = SITE,
        vfs: VirtualFileSystem | None = None,
    ) -> None:
        self.clock: Clock = clock if clock is not None else _clock(epoch, speed)
        self.site = site
        self._own_vfs: VirtualFileSystem | None = None  # the default, made (and closed) here
        if vfs is None:
            vfs = self._own_vfs = VirtualFileSystem({"cache": MemoryFile()})
        self.vfs = vfs
        self.network = LocalNetwork()
        self._modules: list[Module] = []

    @property
    def modules(self) -> list[Module]:
        """The modules started so far, in start order."""
        return list(self._modules)

    def module(self, name: str, cls: type[M]) -> M:
        """The started module called ``name``, which must be a ``cls``."""
        found = [m for m in self._modules if m.name == name]
        if not found:
            raise LookupError(
                f"no module {name!r} started; started: {', '.join(m.name for m in self._modules)}"
            )
        if not isinstance(found[0], cls):
            raise TypeError(f"module {name!r} is a {type(found[0]).__name__}, not a {cls.__name__}")
        return found[0]

    def comm(self, name: str) -> LocalComm:
        """A comm called ``name`` on this observatory's network (for a module built by hand)."""
        return LocalComm(name, network=self.network)

    async def start(self, cls: type[M], name: str, **kwargs: Any) -> M:
        """Build ``cls(name, **kwargs)`` with this clock, site and VFS (unless given) and open it."""
        kwargs.setdefault("clock", self.clock)
        if self.site is not None:
            kwargs.setdefault("site", self.site)
        kwargs.setdefault("vfs", self.vfs)
        module = cls(comm=self.comm(name), **kwargs)
        self._modules.append(module)
        await module.open()
        return module

    async def close(self) -> None:
        """Close every started module, the last started first, then the default VFS if this
        observatory made it (safe to call twice)."""
        try:
            while self._modules:
                await self._modules.pop().close()
        finally:
            if self._own_vfs is not None:
                await self._own_vfs.close()

    async def wait_for(
        self, condition: Condition, clock_seconds: float, *, interval: float | None = None, message: str = ""
    ) -> float:
        """:func:`~nightcrew.testing.wait_for` on this observatory's clock."""
        return await wait_for(
            condition,
            clock_seconds,
            clock=self.clock,
            interval=interval,
            message=message or "condition not met",
        )

    async def __aenter__(self) -> Observatory:
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        await self.close()


def _clock(epoch: datetime | str, speed: float | None) -> Clock:
    return VirtualClock(epoch) if speed is None else AcceleratedClock(epoch, speed=speed)
