"""Two small modules that run in separate ``nightcrew run`` processes (test_xmpp_processes.py)."""

from __future__ import annotations

import asyncio
from abc import abstractmethod
from typing import Any

from nightcrew.events import TestEvent
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module


class IPointAndShoot(Interface):
    """Points, then has another module take an image."""

    @abstractmethod
    async def point_and_expose(self, altitude: float) -> str: ...


class IExposeForTests(Interface):
    """Takes a pretend image."""

    @abstractmethod
    async def expose(self, seconds: float) -> str: ...


class MountForTests(Module, IPointAndShoot):
    """Calls the imager in the other process and waits for the imager's event."""

    def __init__(self, imager: str = "camera", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._imager = imager
        self._events: asyncio.Queue[str] = asyncio.Queue()

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(TestEvent, self.on_test_event)

    async def on_test_event(self, event: TestEvent, sender: str) -> None:
        await self._events.put(f"{event.message} from {sender}")

    async def point_and_expose(self, altitude: float) -> str:
        imager = await self.comm.proxy(self._imager, IExposeForTests)
        image = await imager.expose(0.1)
        heard = await asyncio.wait_for(self._events.get(), 5)
        return f"{image} at {altitude:g} deg; heard '{heard}'"


class ImagerForTests(Module, IExposeForTests):
    """Sends a TestEvent for every exposure."""

    async def expose(self, seconds: float) -> str:
        await asyncio.sleep(seconds)
        await self.comm.send_event(TestEvent(message="exposed image-1"))
        return "image-1"
