"""Observing procedures that modules run on request: flat fields, acquisition, guiding, pointing series."""

from __future__ import annotations

from abc import abstractmethod
from typing import Any

from nightcrew.interfaces.camera import Binning, IExposureTime
from nightcrew.interfaces.control import IAbortable, IRunning, IStartStop
from nightcrew.interfaces.enums import LoopState
from nightcrew.timeout import timeout

__all__ = ["IAcquisition", "IAutoGuiding", "IFlatField", "IPointingSeries"]


class IFlatField(IAbortable):
    """Taking flat fields (twilight or dome)."""

    @timeout(3600)
    @abstractmethod
    async def flat_field(
        self, count: int, binning: Binning | None = None, filter_name: str | None = None
    ) -> tuple[int, float]:
        """Take ``count`` flats (binning, filter_name None: current); return (frames, total exposure s)."""


class IAcquisition(IRunning, IAbortable):
    """Centring the current target on the detector by iterated exposures and offsets."""

    @timeout(600)
    @abstractmethod
    async def acquire_target(self) -> dict[str, Any]:
        """Acquire the target; return what was done (e.g. final offsets in degrees, iterations)."""


class IAutoGuiding(IStartStop, IExposureTime):
    """Closed-loop guiding on a guide camera; start/stop open and close the loop."""

    @abstractmethod
    async def get_loop_state(self) -> LoopState:
        """State of the guiding loop."""


class IPointingSeries(IAbortable):
    """Measuring a pointing model by solving images across the sky."""

    # A full series may take hours; implementations with a known length may override.
    @timeout(7200)
    @abstractmethod
    async def start_pointing_series(self) -> str:
        """Run a pointing series and return the VFS path of the measured positions."""
