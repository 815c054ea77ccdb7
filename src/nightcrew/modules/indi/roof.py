"""A roll-off roof behind an INDI driver: open and closed are ``DOME_PARK`` (parked: closed), stop
``DOME_ABORT_MOTION``.

INDI drives roll-off roofs with its dome interface but without a shutter or an azimuth: the
driver (``indi_rolloff_dome`` and its kind) opens the roof when unparked and closes it when parked.
The state is read from the device at every (re)connection and followed when someone else moves it.

Example (``nightcrew init --indi`` writes it for a driver named roll-off)::

    class: nightcrew.modules.indi.IndiRoof
    host: 192.168.1.20
    device: RollOff Simulator
"""

from __future__ import annotations

from nightcrew.bridges.indi import IndiUpdate, PropertyState, Vector
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.indi.link import IndiModule
from nightcrew.modules.roof import BaseRoof

__all__ = ["IndiRoof"]

_PARK = "DOME_PARK"


class IndiRoof(IndiModule, BaseRoof):
    """An INDI roll-off roof (``host``, ``port``, ``device`` ... and the roof's options)."""

    indi_needs = (_PARK,)

    def _park_status(self, park: Vector) -> MotionStatus:
        closed = bool(park.members.get("PARK"))
        if park.state is PropertyState.BUSY:
            return MotionStatus.PARKING if closed else MotionStatus.MOVING
        return MotionStatus.PARKED if closed else MotionStatus.IDLE

    async def _on_indi_ready(self) -> None:
        if not self._motion.busy:
            await self._set_motion_status(self._park_status(self._indi.vector(_PARK)))

    async def _on_indi_update(self, update: IndiUpdate) -> None:
        """Report the roof moved by someone else."""
        if update.name == _PARK and update.vector is not None and not self._motion.busy:
            await self._set_motion_status(self._park_status(update.vector))

    async def _park(self, member: str) -> None:
        await self._indi.send(
            _PARK,
            {"PARK": member == "PARK", "UNPARK": member == "UNPARK"},
            wait=self._move_timeout,
            done=lambda v: v.members.get(member) is True,
        )

    async def _hw_open(self) -> None:
        await self._park("UNPARK")

    async def _hw_close(self) -> None:
        await self._park("PARK")

    async def _hw_stop(self) -> None:
        await self._indi.abort("DOME_ABORT_MOTION")
