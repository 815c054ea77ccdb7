"""Roofs: open and close with events, and close by themselves on bad weather.

A roof's motion status: PARKED when closed, IDLE when open (or stopped halfway), MOVING while
opening, PARKING while closing. ``init()`` opens and ``park()`` closes, so a roof can be driven
like any other IMotion device. Closing always wins: it aborts an opening roof. After a
BadWeatherEvent the roof refuses to open (MoveError) until a GoodWeatherEvent; after a
SafetyAlarmEvent (the safety watchdog's) until a SafetyClearedEvent.

Without the message server nobody could tell the roof to close, so it closes by itself when its
comm has been disconnected for ``park_when_offline`` clock seconds (default 300; the rule of every
motion device, see nightcrew.modules.motion.base). It may open again once it is back and asked to.
With ``watchdog`` set (the dead-man's switch, same place) it closes by itself when the watchdog's
heartbeat stops for ``park_when_watchdog_silent`` clock seconds, and refuses to open until it is back.
"""

from __future__ import annotations

import logging
from abc import abstractmethod
from typing import Any

from nightcrew.errors import MoveError
from nightcrew.events import (
    BadWeatherEvent,
    GoodWeatherEvent,
    RoofClosedEvent,
    RoofClosingEvent,
    RoofOpenedEvent,
    SafetyAlarmEvent,
    SafetyClearedEvent,
)
from nightcrew.interfaces import IRoof, ModuleState, MotionStatus
from nightcrew.modules.motion import BaseMotion

__all__ = ["BaseRoof"]

log = logging.getLogger(__name__)


class BaseRoof(BaseMotion, IRoof):
    """A roof or shutter; a driver implements ``_hw_open``, ``_hw_close`` and ``_hw_stop``.

    Args:
        park_when_offline: Clock seconds without a connection to the other modules (the XMPP
            server) after which the roof closes by itself; None: never.
        **kwargs: Module options (see BaseMotion; ``watchdog`` and ``park_when_watchdog_silent``
            arm the dead-man's switch).
    """

    initial_status = MotionStatus.PARKED

    def __init__(self, *, park_when_offline: float | None = 300.0, **kwargs: Any) -> None:
        super().__init__(park_when_offline=park_when_offline, **kwargs)
        self._bad_weather: str | None = None
        self._alarm: str | None = None

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(BadWeatherEvent, self.on_bad_weather)
        await self.comm.register_event(GoodWeatherEvent, self.on_good_weather)
        await self.comm.register_event(SafetyAlarmEvent, self.on_safety_alarm)
        await self.comm.register_event(SafetyClearedEvent, self.on_safety_cleared)

    # --- hooks ---------------------------------------------------------------------------------

    @abstractmethod
    async def _hw_open(self) -> None:
        """Open completely; return when open."""

    @abstractmethod
    async def _hw_close(self) -> None:
        """Close completely; return when closed."""

    # --- IRoof / IMotion -----------------------------------------------------------------------

    async def open_roof(self) -> None:
        if self._bad_weather is not None:
            raise MoveError(f"weather is bad ({self._bad_weather}); the roof stays closed until it is good")
        if self._alarm is not None:
            raise MoveError(f"safety alarm ({self._alarm}); the roof stays closed until it is cleared")
        if (silence := self._watchdog_silence()) is not None:
            raise MoveError(f"{silence}; the roof stays closed until it is back")
        if self._motion_status is MotionStatus.IDLE and not self._motion.busy:
            return
        self._motion.check_idle()

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.MOVING)
            await self._guarded(self._hw_open(), "roof failed to open")
            await self._set_motion_status(MotionStatus.IDLE)
            await self.comm.send_event(RoofOpenedEvent())

        await self._run_motion("opening", motion())

    async def close_roof(self) -> None:
        if self._motion_status is MotionStatus.PARKED and not self._motion.busy:
            return
        if self._motion.action == "closing":
            await self._motion.join()
            return

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.PARKING)
            await self.comm.send_event(RoofClosingEvent())
            await self._guarded(self._hw_close(), "roof failed to close")
            await self._set_motion_status(MotionStatus.PARKED)
            await self.comm.send_event(RoofClosedEvent())

        await self._run_motion("closing", motion(), preempt=True)

    async def init(self) -> None:
        await self.open_roof()

    async def park(self) -> None:
        await self.close_roof()

    # --- safety --------------------------------------------------------------------------------

    async def on_bad_weather(self, event: BadWeatherEvent, sender: str) -> None:
        """Close by ourselves and refuse to open until the weather is good again."""
        self._bad_weather = event.reason or "no reason given"
        if self._motion_status is not MotionStatus.PARKED or self._motion.busy:
            log.warning("%s: bad weather (%s): closing", self.name, self._bad_weather)
        await self.close_roof()

    async def on_good_weather(self, event: GoodWeatherEvent, sender: str) -> None:
        """Allow opening again (opening itself is the mastermind's decision)."""
        self._bad_weather = None

    async def on_safety_alarm(self, event: SafetyAlarmEvent, sender: str) -> None:
        """Close and refuse to open until the watchdog clears the alarm."""
        self._alarm = event.reason or f"raised by {sender}"
        if self._motion_status is not MotionStatus.PARKED or self._motion.busy:
            log.warning("%s: safety alarm (%s): closing", self.name, self._alarm)
        await self.close_roof()

    async def on_safety_cleared(self, event: SafetyClearedEvent, sender: str) -> None:
        self._alarm = None
