"""Focusers: a base position plus an offset, kept within the focuser's mechanical range."""

from __future__ import annotations

import logging
import math
from abc import abstractmethod
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.interfaces import FitsCard, IFitsHeaderBefore, IFocuser, IFocusRange, MotionStatus
from nightcrew.modules.motion import BaseMotion
from nightcrew.timeout import timeout

__all__ = ["BaseFocuser"]

log = logging.getLogger(__name__)

#: Positions closer than this (mm) are the same (a device reports whole steps).
_SAME_POSITION_MM = 1e-3


class BaseFocuser(BaseMotion, IFocuser, IFocusRange, IFitsHeaderBefore):
    """A focuser; a driver implements ``_hw_move_focus`` and ``_hw_stop``.

    A focuser has nothing to park: ``init()`` and ``park()`` leave it where it is.
    FITS cards: FOCUS (base + offset, mm) and FOCOFFS (offset, mm).

    Args:
        min_focus: Lowest reachable position in mm.
        max_focus: Highest reachable position in mm.
        focus: Position at start-up in mm (the driver may know better and set ``_focus``).
        **kwargs: Module options.
    """

    def __init__(
        self, *, min_focus: float = 0.0, max_focus: float = 50.0, focus: float | None = None, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        if not (math.isfinite(min_focus) and math.isfinite(max_focus) and min_focus < max_focus):
            raise ConfigError(f"need min_focus < max_focus, got {min_focus}..{max_focus}", key="max_focus")
        start = (min_focus + max_focus) / 2.0 if focus is None else focus
        if not min_focus <= start <= max_focus:
            raise ConfigError(f"must be within {min_focus:g}..{max_focus:g} mm, got {start}", key="focus")
        self._min_focus, self._max_focus = float(min_focus), float(max_focus)
        self._focus = float(start)
        self._offset = 0.0
        self._chosen: tuple[float, float] | None = None  # (focus, offset) last moved to

    @abstractmethod
    async def _hw_move_focus(self, position: float) -> None:
        """Move to ``position`` mm (base + offset); return when there."""

    def _hw_travel_time(self, position: float) -> float | None:
        """Clock seconds a move from here to ``position`` mm takes (part of the timeout a move
        announces); None (the default) when the driver does not know its speed."""
        return None

    async def _move(self, focus: float, offset: float) -> None:
        if not (math.isfinite(focus) and math.isfinite(offset)):
            raise InvalidArgumentError(f"focus and offset must be finite, got {focus} and {offset}")
        position = focus + offset
        if not self._min_focus <= position <= self._max_focus:
            raise InvalidArgumentError(
                f"focus {focus:.4f} mm + offset {offset:.4f} mm = {position:.4f} mm is outside the "
                f"focuser range {self._min_focus:g}..{self._max_focus:g} mm"
            )
        self._motion.check_idle()

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.MOVING)
            await self._guarded(self._hw_move_focus(position), f"focuser failed to move to {position:.4f} mm")
            self._focus, self._offset = self._chosen = focus, offset
            await self._set_motion_status(MotionStatus.IDLE)

        await self._run_motion("moving focus", motion())

    async def _restore_focus(self) -> None:
        """Move back to the position last moved to if the device is elsewhere, e.g. it came back from
        a restart at its default position (drivers call this after reading the device)."""
        if self._chosen is None:
            return
        focus, offset = self._chosen
        if abs((focus + offset) - (self._focus + self._offset)) < _SAME_POSITION_MM:
            return
        log.warning(
            "%s: the focuser came back at %.4f mm: moving back to %.4f mm",
            self.name,
            self._focus + self._offset,
            focus + offset,
        )
        await self._hw_move_focus(focus + offset)
        self._focus, self._offset = focus, offset

    # Announced: the travel at the focuser's speed where the driver knows it (else 300 s).
    @timeout(
        lambda self, focus, **_: self._announced_move_timeout(
            lambda: self._hw_travel_time(focus + self._offset), IFocuser.set_focus
        )
    )
    async def set_focus(self, focus: float) -> None:
        await self._move(focus, self._offset)

    async def get_focus(self) -> float:
        return self._focus

    async def get_focus_range(self) -> tuple[float, float]:
        return self._min_focus, self._max_focus

    @timeout(
        lambda self, offset, **_: self._announced_move_timeout(
            lambda: self._hw_travel_time(self._focus + offset), IFocuser.set_focus_offset
        )
    )
    async def set_focus_offset(self, offset: float) -> None:
        await self._move(self._focus, offset)

    async def get_focus_offset(self) -> float:
        return self._offset

    async def init(self) -> None:
        await self._set_motion_status(MotionStatus.IDLE)

    async def park(self) -> None:
        """Nothing to park; stays where it is."""

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {
            "FOCUS": (round(self._focus + self._offset, 4), "Focuser position [mm]"),
            "FOCOFFS": (round(self._offset, 4), "Focus offset included in FOCUS [mm]"),
        }
