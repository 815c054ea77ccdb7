"""A roll-off roof (or any shutter) behind an Alpaca Dome device that only opens and closes.

The Alpaca Dome API drives roofs too: a roll-off roof is a Dome device whose shutter is the roof
and that cannot turn (CanSetAzimuth false). ``OpenShutter``/``CloseShutter`` start the motion;
``ShutterStatus`` is polled until it is done (ASCOM ShutterState: 0 open, 1 closed, 2 opening,
3 closing, 4 error). ``AbortSlew`` stops it halfway. The roof's state is read from the device at
every (re)connect and before every opening or closing, so a roof moved by hand is not mistaken.

Example (``examples/alpaca/roof.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaRoof
    server: http://127.0.0.1:11111
    device_number: 0
"""

from __future__ import annotations

from enum import IntEnum
from typing import Any

from nightcrew.errors import MoveError, NotSupportedError
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.alpaca.checked import CheckedGets
from nightcrew.modules.roof import BaseRoof

__all__ = ["AlpacaRoof", "ShutterState"]


class ShutterState(IntEnum):
    """ASCOM ShutterState, the value of ``ShutterStatus``."""

    OPEN = 0
    CLOSED = 1
    OPENING = 2
    CLOSING = 3
    ERROR = 4


#: Motion status the roof has when its shutter is found in a state (at connect).
_STATUS_OF = {
    ShutterState.OPEN: MotionStatus.IDLE,
    ShutterState.CLOSED: MotionStatus.PARKED,
    ShutterState.OPENING: MotionStatus.MOVING,
    ShutterState.CLOSING: MotionStatus.PARKING,
    ShutterState.ERROR: MotionStatus.ERROR,
}


def _is_shutter_state(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= 4


class AlpacaRoof(CheckedGets, BaseRoof):
    """A roof or shutter on an Alpaca Dome device.

    Args:
        shutter_timeout: Wall seconds opening or closing may take (below the interfaces' 300 s).
        **kwargs: Alpaca options (``server``, ``device_number``, ...) and roof/module options.
    """

    device_type = "dome"
    wait_limits = {"shutter_timeout": 300.0}

    def __init__(self, *, shutter_timeout: float = 240.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._shutter_timeout = self._checked_wait("shutter_timeout", shutter_timeout)
        self._stopped_status = MotionStatus.IDLE

    async def _on_connected(self) -> None:
        await super()._on_connected()
        if not await self._get_flag("cansetshutter"):
            raise NotSupportedError(
                f"{self.device.name} cannot open or close its shutter (CanSetShutter false)"
            )
        if not self._motion.busy:
            await self._set_motion_status(_STATUS_OF[await self._shutter_state()])

    async def _shutter_state(self) -> ShutterState:
        value = await self._get_integer("shutterstatus")
        if not _is_shutter_state(value):
            raise self._bad_value("shutterstatus", value, "an ASCOM ShutterState (0..4)")
        return ShutterState(value)

    async def _move_shutter(self, method: str, target: ShutterState) -> None:
        await self._put(method)
        # Wait for the target itself: a real shutter may still report its old state for a moment.
        state = await self._poll_until(
            "shutterstatus",
            lambda value: value in (target, ShutterState.ERROR) or not _is_shutter_state(value),
            self._shutter_timeout,
            method,
            MoveError,
        )
        if not _is_shutter_state(state):
            raise self._bad_value("shutterstatus", state, "an ASCOM ShutterState (0..4)")
        if state != target:
            raise MoveError(f"{self.device.name}: {method}: the shutter reports an error (ShutterStatus 4)")

    async def _refresh_status(self) -> None:
        """Take the shutter's state from the device while nothing moves: it may have been moved by
        hand or by the device's own controller, and a roof that is open but thought closed would
        ignore close_roof() (fail safe: ask rather than trust)."""
        if not self._motion.busy:
            status = _STATUS_OF[await self._shutter_state()]
            if status in (MotionStatus.IDLE, MotionStatus.PARKED):
                await self._set_motion_status(status)

    async def open_roof(self) -> None:
        await self._refresh_status()
        await super().open_roof()

    async def close_roof(self) -> None:
        await self._refresh_status()
        await super().close_roof()

    async def _hw_open(self) -> None:
        await self._move_shutter("openshutter", ShutterState.OPEN)

    async def _hw_close(self) -> None:
        await self._move_shutter("closeshutter", ShutterState.CLOSED)

    async def _hw_stop(self) -> None:
        await self._put("abortslew")
        # A stopped shutter is wherever it is: closed stays PARKED, halfway counts as open (IDLE).
        state = await self._shutter_state()
        status = _STATUS_OF[state]
        self._stopped_status = (
            MotionStatus.IDLE if status in (MotionStatus.MOVING, MotionStatus.PARKING) else status
        )

    def _status_after_stop(self) -> MotionStatus:
        return self._stopped_status
