"""Interfaces and modules used by the comm contract tests."""

from __future__ import annotations

import asyncio
from abc import abstractmethod
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from nightcrew.errors import InvalidArgumentError
from nightcrew.events import TestEvent
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module
from nightcrew.timeout import timeout


class Colour(StrEnum):
    RED = "red"
    GREEN = "green"


@dataclass(frozen=True)
class Measurement:
    value: float
    unit: str
    colour: Colour


class ICalculator(Interface):
    """Arithmetic for the contract tests."""

    @abstractmethod
    async def add(self, a: float, b: float = 1.0) -> float: ...

    @abstractmethod
    async def divide(self, a: float, b: float) -> float: ...

    @abstractmethod
    async def measure(self, colour: Colour) -> Measurement: ...

    @abstractmethod
    async def echo(self, value: Any) -> Any: ...

    @abstractmethod
    async def crash(self) -> None: ...


class ISlow(Interface):
    """Methods that take their time."""

    @abstractmethod
    @timeout(0.3)
    async def too_slow(self) -> None:
        """Announces 0.3 s, takes longer."""

    @abstractmethod
    @timeout(lambda seconds, **_: 100 * seconds)
    async def wait(self, seconds: float) -> float:
        """Announces 100 * ``seconds`` (clock seconds) and takes ``seconds`` of wall time."""


class Calculator(Module, ICalculator, ISlow):
    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.received: list[tuple[TestEvent, str]] = []

    async def add(self, a: float, b: float = 1.0) -> float:
        return a + b

    async def divide(self, a: float, b: float) -> float:
        if b == 0:
            raise InvalidArgumentError("division by zero")
        return a / b

    async def measure(self, colour: Colour) -> Measurement:
        return Measurement(value=42.5, unit="adu", colour=colour)

    async def echo(self, value: Any) -> Any:
        return value

    async def crash(self) -> None:
        raise ValueError("bug in the callee")

    async def too_slow(self) -> None:
        await asyncio.sleep(5)

    async def wait(self, seconds: float) -> float:
        await asyncio.sleep(seconds)
        return seconds


class Listener(Module):
    """Collects TestEvents; answers a TestEvent "ping" with a TestEvent "pong" (chaining)."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.received: list[tuple[TestEvent, str]] = []
        self.arrived = asyncio.Event()

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(TestEvent, self.on_test_event)

    async def on_test_event(self, event: TestEvent, sender: str) -> None:
        self.received.append((event, sender))
        self.arrived.set()
        if event.message == "ping":
            await self.comm.send_event(TestEvent(message="pong"))
