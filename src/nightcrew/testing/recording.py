"""A module that records the events it hears, for tests to look at and wait on."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

from nightcrew.events import Event
from nightcrew.interfaces import ModuleState
from nightcrew.modules import Module
from nightcrew.testing.waiting import wait_for

__all__ = ["EventRecorder"]

E = TypeVar("E", bound=Event)


class EventRecorder(Module):
    """Records every event of the given types with its sender and clock time; can send events too.

    Args:
        types: Event classes to listen to.
        **kwargs: Module options (``name``, ``comm``, ``clock`` ...).
    """

    def __init__(self, *, types: list[type[Event]], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._types = list(types)
        #: (event, sender) in the order they arrived.
        self.events: list[tuple[Event, str]] = []
        #: Clock time at which each of ``events`` arrived.
        self.arrivals: list[float] = []

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        for event_type in self._types:
            await self.comm.register_event(event_type, self.on_event)

    async def on_event(self, event: Event, sender: str) -> None:
        self.events.append((event, sender))
        self.arrivals.append(self.clock.time())

    def of(self, event_type: type[E], sender: str | None = None) -> list[E]:
        """The events of ``event_type`` heard so far (from ``sender`` only, if given), oldest first."""
        return [e for e, s in self.events if isinstance(e, event_type) and sender in (None, s)]

    def times(self, event_type: type[Event]) -> list[float]:
        """Clock times at which events of ``event_type`` arrived."""
        return [t for (e, _), t in zip(self.events, self.arrivals, strict=True) if isinstance(e, event_type)]

    def clear(self) -> None:
        """Forget everything heard so far."""
        self.events.clear()
        self.arrivals.clear()

    async def wait_for_event(
        self,
        event_type: type[E],
        clock_seconds: float,
        *,
        sender: str | None = None,
        where: Callable[[E], bool] | None = None,
    ) -> E:
        """The first event of ``event_type`` (from ``sender``, matching ``where``), waiting for it.

        Raises:
            AssertionError: None arrived within ``clock_seconds``.
        """

        def matching() -> list[E]:
            return [e for e in self.of(event_type, sender) if where is None or where(e)]

        await wait_for(
            lambda: bool(matching()),
            clock_seconds,
            clock=self.clock,
            message=f"{self.name} heard no matching {event_type.__name__}",
        )
        return matching()[0]
