"""Domes: a roof (the shutter) plus a slit azimuth that can follow the telescope."""

from __future__ import annotations

import logging
import math
from abc import abstractmethod
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError, NightcrewError
from nightcrew.interfaces import FitsCard, IDome, IFitsHeaderBefore, IPointingAltAz, MotionStatus
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.motion import MotionRunner
from nightcrew.modules.roof.base import BaseRoof
from nightcrew.modules.roof.geometry import DomeGeometry, slit_azimuth

__all__ = ["BaseDome", "azimuth_difference"]

log = logging.getLogger(__name__)

#: Device name of the rotation in get_motion_status(device).
AZIMUTH = "azimuth"


def azimuth_difference(a: float, b: float) -> float:
    """Signed shortest turn from azimuth ``b`` to ``a`` in degrees (-180..180)."""
    return (a - b + 180.0) % 360.0 - 180.0


class BaseDome(BaseRoof, IDome, IFitsHeaderBefore):
    """A dome; a driver adds ``_hw_move_azimuth`` and ``_hw_get_azimuth`` to the roof hooks.

    The rotation runs independently of the shutter; a new azimuth replaces the one being moved to.

    Args:
        follow: Name of the telescope whose azimuth the slit follows; None: no following.
        follow_tolerance: Degrees the slit may lag before it turns.
        follow_interval: Clock seconds between two looks at the telescope.
        dome_radius: Radius of the dome in metres; with ``mount_offset``, where the followed
            telescope's axis meets the dome (None: the slit follows the telescope's azimuth).
        mount_offset: Metres (east, north, up) from the dome centre to the telescope's pivot.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        follow: str | None = None,
        follow_tolerance: float = 2.0,
        follow_interval: Period = 5.0,
        dome_radius: float | None = None,
        mount_offset: tuple[float, float, float] = (0.0, 0.0, 0.0),
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not follow_tolerance > 0:
            raise ConfigError(f"must be > 0 degrees, got {follow_tolerance}", key="follow_tolerance")
        if not follow_interval > 0:
            raise ConfigError(f"must be > 0 seconds, got {follow_interval}", key="follow_interval")
        self._follow = follow
        self._follow_tolerance = float(follow_tolerance)
        self._follow_interval = float(follow_interval)
        if len(mount_offset) != 3:
            raise ConfigError(f"give [east, north, up] in metres, got {mount_offset!r}", key="mount_offset")
        if dome_radius is None and any(mount_offset):
            raise ConfigError("an offset telescope needs the dome's radius too", key="dome_radius")
        self._geometry = None if dome_radius is None else DomeGeometry(dome_radius, *map(float, mount_offset))
        self._rotation = MotionRunner("dome rotation")
        if follow:
            self.add_background_task(self._follow_loop)

    @abstractmethod
    async def _hw_move_azimuth(self, az: float) -> None:
        """Turn the slit to ``az``; return when there."""

    @abstractmethod
    async def _hw_get_azimuth(self) -> float:
        """Current slit azimuth in degrees."""

    async def move_azimuth(self, az: float) -> None:
        if not math.isfinite(az):
            raise InvalidArgumentError(f"azimuth must be a finite number of degrees, got {az}")
        await self._rotation.run(
            f"turning to {az % 360.0:.1f}°", self._hw_move_azimuth(az % 360.0), preempt=True
        )

    async def get_azimuth(self) -> float:
        return await self._hw_get_azimuth()

    async def get_motion_status(self, device: str | None = None) -> MotionStatus:
        if device == AZIMUTH:
            return MotionStatus.MOVING if self._rotation.busy else MotionStatus.IDLE
        return await super().get_motion_status(device)

    async def stop_motion(self, device: str | None = None) -> None:
        await self._rotation.stop("stop_motion() called")
        if device != AZIMUTH:
            await super().stop_motion(device)

    async def close(self) -> None:
        await self._rotation.stop("module closing")
        await super().close()

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {"DOME-AZ": (round(await self._hw_get_azimuth(), 3), "Dome slit azimuth [deg]")}

    async def _follow_loop(self) -> None:
        assert self._follow is not None
        while True:
            await self.clock.sleep(self._follow_interval)
            if self._rotation.busy:
                continue
            try:
                telescope = await self.proxy(self._follow, IPointingAltAz)
                alt, az = await telescope.get_altaz()
            except NightcrewError as exc:
                log.warning("%s: cannot follow %s: %s", self.name, self._follow, exc)
                continue
            target = az if self._geometry is None else slit_azimuth(self._geometry, alt, az)
            if abs(azimuth_difference(target, await self._hw_get_azimuth())) > self._follow_tolerance:
                try:
                    await self.move_azimuth(target)
                except NightcrewError as exc:  # e.g. replaced by a manual move: look again later
                    log.info("%s: following %s: %s", self.name, self._follow, exc)
