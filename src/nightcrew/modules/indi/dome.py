"""A dome behind an INDI driver: shutter ``DOME_SHUTTER``, azimuth ``ABS_DOME_POSITION``,
stop ``DOME_ABORT_MOTION``, and INDI's own slaving ``DOME_AUTOSYNC``.

Slaving either way: nightcrew's (``follow: telescope``, the BaseDome loop, with the dome geometry)
or the INDI driver's (``autosync: true``: the driver follows the mount it snoops itself).

Example (``examples/indi/dome.yaml``)::

    class: nightcrew.modules.indi.IndiDome
    host: 192.168.1.20
    device: Dome Simulator
    follow: telescope
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.indi import IndiUpdate, PropertyState, Vector
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.indi.link import IndiModule
from nightcrew.modules.roof import BaseDome, azimuth_difference

__all__ = ["IndiDome"]

_SHUTTER = "DOME_SHUTTER"
_AZIMUTH = "ABS_DOME_POSITION"
_AZ_MEMBER = "DOME_ABSOLUTE_POSITION"


class IndiDome(IndiModule, BaseDome):
    """An INDI dome.

    Args:
        autosync: Let the INDI driver slave the dome to its mount (DOME_AUTOSYNC) on every
            connection; False leaves the driver's setting alone.
        **kwargs: INDI options (``host``, ``port``, ``device`` ...) and dome options.
    """

    indi_needs = (_SHUTTER, _AZIMUTH)

    def __init__(self, *, autosync: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._autosync = bool(autosync)

    def _shutter_status(self, shutter: Vector) -> MotionStatus:
        if shutter.state is PropertyState.BUSY:
            return MotionStatus.MOVING if shutter.members.get("SHUTTER_OPEN") else MotionStatus.PARKING
        return MotionStatus.IDLE if shutter.members.get("SHUTTER_OPEN") else MotionStatus.PARKED

    async def _on_indi_ready(self) -> None:
        if self._autosync and self._indi.has("DOME_AUTOSYNC"):
            await self._indi.switch("DOME_AUTOSYNC", "DOME_AUTOSYNC_ENABLE", wait=self._indi.connect_timeout)
        if not self._motion.busy:
            await self._set_motion_status(self._shutter_status(self._indi.vector(_SHUTTER)))

    async def _on_indi_update(self, update: IndiUpdate) -> None:
        """Report the shutter moved by someone else."""
        if update.name == _SHUTTER and update.vector is not None and not self._motion.busy:
            await self._set_motion_status(self._shutter_status(update.vector))

    async def _shutter(self, member: str) -> None:
        await self._indi.send(
            _SHUTTER,
            {"SHUTTER_OPEN": member == "SHUTTER_OPEN", "SHUTTER_CLOSE": member == "SHUTTER_CLOSE"},
            wait=self._move_timeout,
            done=lambda v: v.members.get(member) is True,
        )

    async def _hw_open(self) -> None:
        await self._shutter("SHUTTER_OPEN")

    async def _hw_close(self) -> None:
        await self._shutter("SHUTTER_CLOSE")

    async def _hw_move_azimuth(self, az: float) -> None:
        await self._indi.send(
            _AZIMUTH,
            {_AZ_MEMBER: az},
            wait=self._move_timeout,
            done=lambda v: abs(azimuth_difference(v.number(_AZ_MEMBER), az)) < 0.1,
        )

    async def _hw_get_azimuth(self) -> float:
        return self._indi.vector(_AZIMUTH).number(_AZ_MEMBER) % 360.0

    async def _hw_stop(self) -> None:
        await self._indi.abort("DOME_ABORT_MOTION")
