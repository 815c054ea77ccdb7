"""A field rotator on an Alpaca Rotator device.

``MoveAbsolute`` (sky position angle), ``Move`` (relative) and ``MoveMechanical`` start a move;
``IsMoving`` is polled until it ends; ``Halt`` stops it. ``Position`` is the sky position angle
(mechanical angle plus the device's sync offset), ``MechanicalPosition`` the raw angle.
Reversing is refused with NotSupportedError when ``CanReverse`` is false.

Example (``examples/alpaca/rotator.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaRotator
    server: http://127.0.0.1:11111
    device_number: 0
"""

from __future__ import annotations

from typing import Any

from nightcrew.errors import MoveError, NotSupportedError
from nightcrew.modules.alpaca.checked import CheckedGets
from nightcrew.modules.rotator import BaseRotator

__all__ = ["AlpacaRotator"]


class AlpacaRotator(CheckedGets, BaseRotator):
    """A rotator on an Alpaca server.

    Args:
        move_timeout: Wall seconds one move may take (below the interface's 300 s).
        **kwargs: Alpaca options (``server``, ``device_number``, ...) and module options.
    """

    device_type = "rotator"
    wait_limits = {"move_timeout": 300.0}

    def __init__(self, *, move_timeout: float = 240.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._move_timeout = self._checked_wait("move_timeout", move_timeout)
        self._can_reverse = False

    async def _on_connected(self) -> None:
        await super()._on_connected()
        self._can_reverse = await self._get_flag("canreverse")

    async def _move_and_wait(self, method: str, position: float) -> None:
        await self._put(method, Position=position)
        moving = await self._poll_until(
            "ismoving", lambda value: value is not True, self._move_timeout, method, MoveError
        )
        if moving is not False:
            raise self._bad_value("ismoving", moving, "true or false")

    async def _hw_move_position_angle(self, angle: float) -> None:
        await self._move_and_wait("moveabsolute", angle)

    async def _hw_move_position_angle_by(self, delta: float) -> None:
        await self._move_and_wait("move", delta)

    async def _hw_move_mechanical(self, angle: float) -> None:
        await self._move_and_wait("movemechanical", angle)

    async def _hw_get_position_angle(self) -> float:
        return await self._get_number("position")

    async def _hw_get_mechanical_angle(self) -> float:
        return await self._get_number("mechanicalposition")

    async def _hw_set_reversed(self, reverse: bool) -> None:
        if not self._can_reverse:
            raise NotSupportedError(f"{self.device.name} cannot reverse its direction (CanReverse false)")
        await self._put("reverse", Reverse=reverse)

    async def _hw_get_reversed(self) -> bool:
        return await self._get_flag("reverse")

    async def _hw_stop(self) -> None:
        await self._put("halt")
