"""A field rotator on an Alpaca Rotator device.

``MoveAbsolute`` (sky position angle), ``Move`` (relative) and ``MoveMechanical`` start a move;
``IsMoving`` is polled until it ends; ``Halt`` stops it. ``Position`` is the sky position angle
(mechanical angle plus the device's sync offset), ``MechanicalPosition`` the raw angle.
A rotator has nothing to park or home: ``init()`` and ``park()`` leave it where it is.

Example (``examples/alpaca/rotator.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaRotator
    server: http://127.0.0.1:11111
    device_number: 0
"""

from __future__ import annotations

import math
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError, MoveError, NightcrewError, NotSupportedError
from nightcrew.interfaces import FitsCard, IFitsHeaderBefore, IRotator, MotionStatus
from nightcrew.modules.alpaca.device import AlpacaModule
from nightcrew.modules.motion import BaseMotion

__all__ = ["AlpacaRotator"]


class AlpacaRotator(AlpacaModule, BaseMotion, IRotator, IFitsHeaderBefore):
    """A rotator; FITS cards ROTPA (sky position angle) and ROTMECH (mechanical angle).

    Args:
        move_timeout: Wall seconds one move may take (below the interface's 300 s).
        **kwargs: Alpaca options (``server``, ``device_number``, ...) and module options.
    """

    device_type = "rotator"

    def __init__(self, *, move_timeout: float = 240.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not 0 < move_timeout < 300:
            raise ConfigError(f"must be within 0..300 seconds, got {move_timeout}", key="move_timeout")
        self._move_timeout = float(move_timeout)
        self._can_reverse = False

    async def _on_connected(self) -> None:
        await super()._on_connected()
        self._can_reverse = bool(await self._get("canreverse"))

    async def _angle(self, member: str) -> float:
        value = await self._get(member)
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise NightcrewError(f"{self.device.name}: GET {member}: {value!r} is not an angle")
        return float(value) % 360.0

    async def _move(self, method: str, angle: float, what: str, *, absolute: bool = True) -> None:
        if not math.isfinite(angle):
            raise InvalidArgumentError(f"{what}: the angle must be a finite number of degrees, got {angle}")
        if absolute:
            angle %= 360.0
        self._motion.check_idle()

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.MOVING)

            async def hardware() -> None:
                await self._put(method, Position=angle)
                await self._poll_until(
                    "ismoving", lambda moving: moving is False, self._move_timeout, what, MoveError
                )

            await self._guarded(hardware(), f"rotator failed: {what}")
            await self._set_motion_status(MotionStatus.IDLE)

        await self._run_motion(what, motion())

    # --- IRotator ------------------------------------------------------------------------------

    async def move_position_angle(self, angle: float) -> None:
        await self._move("moveabsolute", angle, f"turning to PA {angle}°")

    async def move_position_angle_by(self, delta: float) -> None:
        await self._move("move", delta, f"turning by {delta}°", absolute=False)

    async def get_position_angle(self) -> float:
        return await self._angle("position")

    async def move_mechanical(self, angle: float) -> None:
        await self._move("movemechanical", angle, f"turning to mechanical angle {angle}°")

    async def get_mechanical_angle(self) -> float:
        return await self._angle("mechanicalposition")

    async def set_rotator_reversed(self, reverse: bool) -> None:
        if not self._can_reverse:
            raise NotSupportedError(f"{self.device.name} cannot reverse its direction (CanReverse false)")
        await self._put("reverse", Reverse=bool(reverse))

    async def get_rotator_reversed(self) -> bool:
        return bool(await self._get("reverse"))

    # --- IMotion -------------------------------------------------------------------------------

    async def init(self) -> None:
        """Nothing to home; a rotator is ready where it is."""
        await self._set_motion_status(MotionStatus.IDLE)

    async def park(self) -> None:
        """Nothing to park; stays where it is."""

    async def _hw_stop(self) -> None:
        await self._put("halt")

    # --- IFitsHeaderBefore ---------------------------------------------------------------------

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {
            "ROTPA": (round(await self.get_position_angle(), 3), "Rotator sky position angle [deg]"),
            "ROTMECH": (round(await self.get_mechanical_angle(), 3), "Rotator mechanical angle [deg]"),
        }
