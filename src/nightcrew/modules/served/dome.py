"""The served dome: what Alpaca and INDI clients ask of a nightcrew IRoof or IDome, written once.

Any IRoof module (a roll-off roof or a dome's shutter) is served as a dome whose shutter opens and
closes; an IDome also turns to an azimuth. Closing always wins: it pre-empts an opening roof in
nightcrew, so adapters let a close replace a running open (not the other way round).
"""

from __future__ import annotations

from nightcrew.interfaces import IDome, IRoof, MotionStatus

__all__ = ["ServedDomeRole"]


class ServedDomeRole:
    """The IRoof module behind a served dome (IDome is checked on it)."""

    def __init__(self, roof: IRoof) -> None:
        self.roof = roof

    @property
    def dome(self) -> IDome | None:
        """The module as IDome if it turns, else None (a roof)."""
        return self.roof if isinstance(self.roof, IDome) else None

    async def status(self) -> MotionStatus:
        """The shutter's (the roof's) motion status."""
        return await self.roof.get_motion_status()

    async def open(self) -> None:
        await self.roof.open_roof()

    async def close(self) -> None:
        await self.roof.close_roof()

    async def stop(self) -> None:
        await self.roof.stop_motion()
