"""Following a moving target (minor planet, comet, planet, satellite) by its ephemeris.

``move_ephemeris`` takes a moving target as a task file gives it: a mapping with ``type``
(``ORBITAL_ELEMENTS``, ``MPC_ELEMENTS``, ``MAJOR_BODY`` or ``SATELLITE``; see docs/tasks.md). The
mount follows it until the next move, park or stop. ``get_tracking_rates`` gives the offset rates
added to sidereal tracking, arcseconds per second, RA as an angle of right ascension (not times
cos dec); (0, 0) when the mount tracks sidereally or follows by position updates.
"""

from __future__ import annotations

from abc import abstractmethod
from typing import Any

from nightcrew.interfaces.base import Interface
from nightcrew.timeout import timeout

__all__ = ["INonSidereal"]


class INonSidereal(Interface):
    """A mount that points at a moving target and follows it (non-sidereal tracking)."""

    @timeout(300)
    @abstractmethod
    async def move_ephemeris(self, target: dict[str, Any]) -> None:
        """Slew to the moving ``target`` (as in a task file) and follow it until the next move."""

    @abstractmethod
    async def get_tracking_rates(self) -> tuple[float, float]:
        """The offset rates (d(ra)/dt, d(dec)/dt) added to sidereal tracking now, in arcsec/s."""
