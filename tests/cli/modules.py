"""A module that uses another through a parameter typed ``str | ICalculator`` (for CLI tests)."""

from __future__ import annotations

import asyncio
from typing import Any

from nightcrew.errors import NightcrewError
from nightcrew.events import TestEvent
from nightcrew.modules import Module
from tests.comm.sample import ICalculator


class Asker(Module):
    """Asks ``calculator`` a few questions once it is open and records the answers."""

    def __init__(self, calculator: str | ICalculator, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._calculator = calculator
        self.answers: list[object] = []
        self.done = asyncio.Event()
        self.add_background_task(self._ask, restart=False)

    async def _ask(self) -> None:
        calculator = await self.proxy(self._calculator, ICalculator)
        self.answers.append(await calculator.add(20, 22))
        try:
            await calculator.divide(1, 0)
        except NightcrewError as exc:
            self.answers.append(exc)
        await self.comm.send_event(TestEvent(message="asked"))
        self.done.set()
