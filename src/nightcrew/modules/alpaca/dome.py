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
from collections.abc import Iterator, Mapping
from typing import Any

from nightcrew.errors import ConfigError, MoveError, NotSupportedError
from nightcrew.modules.alpaca.roof import AlpacaRoof
from nightcrew.modules.roof import BaseDome, DomeGeometry
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

    wait_limits = {**AlpacaRoof.wait_limits, "rotation_timeout": 300.0}

    @classmethod
    def config_value_problems(cls, values: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
        yield from super().config_value_problems(values)
        if values.get("dome_radius") is not None:
            try:
                DomeGeometry(values["dome_radius"], *values.get("mount_offset", (0.0, 0.0, 0.0)))
            except ConfigError as exc:
                yield exc.key or "dome_radius", exc.message
            except TypeError:
                pass  # wrong types or lengths: the hints' checks report those

    def __init__(self, *, rotation_timeout: float = 240.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._rotation_timeout = self._checked_wait("rotation_timeout", rotation_timeout)

    async def _on_connected(self) -> None:
        await super()._on_connected()
        if not await self._get_flag("cansetazimuth"):
            raise NotSupportedError(
                f"{self.device.name} cannot turn (CanSetAzimuth false); drive a roll-off roof with AlpacaRoof"
            )
        try:
            if await self._get_flag("slaved"):
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
        slewing = await self._poll_until(
            "slewing",
            lambda value: value is not True,
            self._rotation_timeout,
            f"turning to {az:.1f}°",
            MoveError,
        )
        if slewing is not False:
            raise self._bad_value("slewing", slewing, "true or false")

    async def stop_motion(self, device: str | None = None) -> None:
        await super().stop_motion(device)
        # Stopping only the rotation cancels nightcrew's wait; the dome itself needs AbortSlew, which
        # stops a moving shutter too, so it is left out while the shutter moves.
        if device == AZIMUTH and not self._motion.busy:
            await self._put("abortslew")

    async def _hw_get_azimuth(self) -> float:
        return await self._get_number("azimuth") % 360.0
