"""A field rotator behind an INDI driver: ``ABS_ROTATOR_ANGLE``, ``SYNC_ROTATOR_ANGLE``,
``ROTATOR_REVERSE`` and ``ROTATOR_ABORT_MOTION``.

INDI reports one angle, already corrected by the driver's sync offset: it is both the sky
position angle and (as INDI offers no other) the mechanical angle here.

Example (``examples/indi/rotator.yaml``)::

    class: nightcrew.modules.indi.IndiRotator
    host: 192.168.1.20
    device: Rotator Simulator
"""

from __future__ import annotations

import math
from typing import Any

from nightcrew.astro import angular_separation
from nightcrew.bridges.indi import IndiUpdate, PropertyState
from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import FitsCard, IFitsHeaderBefore, IRotator, MotionStatus
from nightcrew.modules.indi.link import IndiModule
from nightcrew.modules.motion import BaseMotion

__all__ = ["IndiRotator"]

_ANGLE = "ABS_ROTATOR_ANGLE"


class IndiRotator(IndiModule, BaseMotion, IRotator, IFitsHeaderBefore):
    """An INDI rotator; FITS card ROTPA (position angle).

    Args:
        **kwargs: INDI options (``host``, ``port``, ``device`` ...) and module options.
    """

    indi_needs = (_ANGLE,)

    async def _on_indi_ready(self) -> None:
        if not self._motion.busy:
            await self._set_motion_status(MotionStatus.IDLE)

    async def _on_indi_update(self, update: IndiUpdate) -> None:
        if update.name != _ANGLE or self._motion.busy or update.vector is None:
            return
        statuses = {PropertyState.BUSY: MotionStatus.MOVING, PropertyState.ALERT: MotionStatus.ERROR}
        await self._set_motion_status(statuses.get(update.vector.state, MotionStatus.IDLE))

    async def _turn(self, angle: float, what: str) -> None:
        if not math.isfinite(angle):
            raise InvalidArgumentError(f"{what}: the angle must be a finite number of degrees, got {angle}")
        target = angle % 360.0
        self._motion.check_idle()

        def arrived(vector: Any) -> bool:
            return bool(angular_separation(vector.number("ANGLE"), 0.0, target, 0.0) < 0.01)

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.MOVING)
            await self._guarded(
                self._indi.send(_ANGLE, {"ANGLE": target}, wait=self._move_timeout, done=arrived),
                f"rotator failed: {what}",
            )
            await self._set_motion_status(MotionStatus.IDLE)

        await self._run_motion(what, motion())

    # --- IRotator ------------------------------------------------------------------------------

    async def move_position_angle(self, angle: float) -> None:
        await self._turn(angle, f"turning to PA {angle}°")

    async def move_position_angle_by(self, delta: float) -> None:
        if not math.isfinite(delta):
            raise InvalidArgumentError(f"the turn must be a finite number of degrees, got {delta}")
        await self._turn(await self.get_position_angle() + delta, f"turning by {delta}°")

    async def get_position_angle(self) -> float:
        return self._indi.vector(_ANGLE).number("ANGLE") % 360.0

    async def move_mechanical(self, angle: float) -> None:
        await self._turn(angle, f"turning to mechanical angle {angle}°")

    async def get_mechanical_angle(self) -> float:
        return await self.get_position_angle()

    async def set_rotator_reversed(self, reverse: bool) -> None:
        if not self._indi.has("ROTATOR_REVERSE"):
            raise NotSupportedError(f"{self._indi.where} cannot reverse its direction (no ROTATOR_REVERSE)")
        member = "INDI_ENABLED" if reverse else "INDI_DISABLED"
        await self._indi.switch("ROTATOR_REVERSE", member, wait=self._indi.connect_timeout)

    async def get_rotator_reversed(self) -> bool:
        if not self._indi.has("ROTATOR_REVERSE"):
            return False
        return bool(self._indi.vector("ROTATOR_REVERSE").members.get("INDI_ENABLED"))

    # --- IMotion -------------------------------------------------------------------------------

    async def init(self) -> None:
        """Nothing to home; a rotator is ready where it is."""
        await self._set_motion_status(MotionStatus.IDLE)

    async def park(self) -> None:
        """Nothing to park; stays where it is."""

    async def _hw_stop(self) -> None:
        await self._indi.abort("ROTATOR_ABORT_MOTION")

    # --- IFitsHeaderBefore ---------------------------------------------------------------------

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {"ROTPA": (round(await self.get_position_angle(), 3), "Rotator sky position angle [deg]")}
