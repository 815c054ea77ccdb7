"""Sim-only interfaces: the truth a simulated camera needs and a real device could never tell."""

from __future__ import annotations

from abc import abstractmethod
from typing import Any

from nightcrew.interfaces.base import Interface
from nightcrew.sim.mount import PierCollision

__all__ = ["ISimFocuserTruth", "ISimTelescopeTruth", "ISimWeatherTruth"]


class ISimTelescopeTruth(Interface):
    """Where a simulated telescope really points (pointing error, drift and periodic error included)."""

    @abstractmethod
    async def get_true_radec(self) -> tuple[float, float]:
        """True ICRS (ra, dec) in degrees; get_radec() gives what the mount reports."""

    @abstractmethod
    async def get_true_motion(self) -> tuple[tuple[float, float], dict[str, Any] | None]:
        """The offset rates the mount tracks at now (arcsec/s of RA and Dec) and the moving target
        it follows (as given to move_ephemeris; None when it follows none)."""

    @abstractmethod
    async def get_pier_collisions(self) -> list[PierCollision]:
        """Every time a German-equatorial mount passed a pier limit (none for other mounts)."""


class ISimFocuserTruth(Interface):
    """The best focus of a simulated focuser now (it drifts with temperature)."""

    @abstractmethod
    async def get_best_focus(self) -> float:
        """Position in mm at which stars are sharpest now; compare with get_focus() + offset."""


class ISimWeatherTruth(Interface):
    """What a simulated sky is like, beyond what weather sensors report."""

    @abstractmethod
    async def get_cloud_cover(self) -> float:
        """Fraction of the sky covered by clouds now (0..1)."""
