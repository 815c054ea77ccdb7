"""A rotating dome on an Alpaca Dome device: the shutter as the roof, the azimuth as the slit.

The shutter is :class:`~nightcrew.modules.alpaca.roof.AlpacaRoof`'s. ``SlewToAzimuth`` turns the
dome and ``Slewing`` is polled until it stops; ``AbortSlew`` stops shutter and rotation. Slaving is
nightcrew's, not the device's: with ``follow`` the dome turns to where the followed telescope's
optical axis meets the dome (``dome_radius`` and ``mount_offset``, see
:mod:`nightcrew.modules.roof.geometry`), so the device's own ``Slaved`` is switched off at connect.

Example (``examples/alpaca/dome.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaDome
    server: http://127.0.0.1:11111
    device_number: 0
    follow: telescope
    dome_radius: 2.5
    mount_offset: [0.0, 0.3, 0.5]
"""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.errors import ConfigError, MoveError, NightcrewError, NotSupportedError
from nightcrew.modules.alpaca.roof import AlpacaRoof
from nightcrew.modules.roof import BaseDome
from nightcrew.modules.roof.dome import AZIMUTH

__all__ = ["AlpacaDome"]

log = logging.getLogger(__name__)


class AlpacaDome(AlpacaRoof, BaseDome):
    """A dome with a shutter and a rotating slit on an Alpaca Dome device.

    Args:
        rotation_timeout: Wall seconds a turn of the dome may take (below the interfaces' 300 s).
        **kwargs: Alpaca options, roof options (``shutter_timeout``), dome options (``follow``,
            ``follow_tolerance``, ``follow_interval``, ``dome_radius``, ``mount_offset``) and
            module options.
    """

    def __init__(self, *, rotation_timeout: float = 240.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not 0 < rotation_timeout < 300:
            raise ConfigError(
                f"must be within 0..300 seconds, got {rotation_timeout}", key="rotation_timeout"
            )
        self._rotation_timeout = float(rotation_timeout)

    async def _on_connected(self) -> None:
        await super()._on_connected()
        if not await self._get("cansetazimuth"):
            raise NotSupportedError(
                f"{self.device.name} cannot turn (CanSetAzimuth false); drive a roll-off roof with AlpacaRoof"
            )
        try:
            if await self._get("slaved"):
                await self._put("slaved", Slaved=False)
                log.info(
                    "%s: switched off %s's own slaving; nightcrew follows instead",
                    self.name,
                    self.device.name,
                )
        except NotSupportedError:
            pass  # a dome that cannot slave is not slaved

    async def _hw_move_azimuth(self, az: float) -> None:
        await self._put("slewtoazimuth", Azimuth=az)
        await self._poll_until(
            "slewing",
            lambda slewing: slewing is False,
            self._rotation_timeout,
            f"turning to {az:.1f}°",
            MoveError,
        )

    async def stop_motion(self, device: str | None = None) -> None:
        await super().stop_motion(device)
        # Stopping only the rotation cancels nightcrew's wait; the dome itself needs AbortSlew, which
        # stops a moving shutter too, so it is left out while the shutter moves.
        if device == AZIMUTH and not self._motion.busy:
            await self._put("abortslew")

    async def _hw_get_azimuth(self) -> float:
        value = await self._get("azimuth")
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise NightcrewError(f"{self.device.name}: Azimuth {value!r} is not a number")
        return float(value) % 360.0
