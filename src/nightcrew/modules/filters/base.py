"""Filter wheels: named filters, one in the beam."""

from __future__ import annotations

import logging
from abc import abstractmethod
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.events import FilterChangedEvent
from nightcrew.interfaces import FitsCard, IFilters, IFitsHeaderBefore, MotionStatus
from nightcrew.modules.motion import BaseMotion

__all__ = ["BaseFilterWheel"]

log = logging.getLogger(__name__)


class BaseFilterWheel(BaseMotion, IFilters, IFitsHeaderBefore):
    """A filter wheel; a driver implements ``_hw_move_filter`` and ``_hw_stop``.

    FITS card: FILTER. Sends FilterChangedEvent when a new filter is in the beam.

    Args:
        filters: Names of the filters in the wheel, e.g. ``[U, B, V, R, I, clear]``.
        filter_name: Filter in the beam at start-up; the first one by default.
        **kwargs: Module options.
    """

    def __init__(self, *, filters: list[str], filter_name: str | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        names = [str(f) for f in filters]
        if not names or any(not n.strip() for n in names):
            raise ConfigError("need at least one filter, each with a non-empty name", key="filters")
        if len(set(names)) != len(names):
            raise ConfigError(f"filter names must be unique, got {', '.join(names)}", key="filters")
        current = names[0] if filter_name is None else filter_name
        if current not in names:
            raise ConfigError(
                f"unknown filter {current!r}; known filters: {', '.join(names)}", key="filter_name"
            )
        self._filters = names
        self._filter = current
        self._chosen: str | None = None  # the filter last asked for (restored after a device restart)

    @abstractmethod
    async def _hw_move_filter(self, filter_name: str) -> None:
        """Move ``filter_name`` into the beam; return when there."""

    async def list_filters(self) -> list[str]:
        return list(self._filters)

    async def get_filter(self) -> str:
        return self._filter

    async def set_filter(self, filter_name: str) -> None:
        if filter_name not in self._filters:
            raise InvalidArgumentError(
                f"unknown filter {filter_name!r}; known filters: {', '.join(self._filters)}"
            )
        self._motion.check_idle()
        self._chosen = filter_name
        if filter_name == self._filter:
            return

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.MOVING)
            await self._guarded(
                self._hw_move_filter(filter_name), f"filter wheel failed to move to {filter_name!r}"
            )
            self._filter = filter_name
            await self._set_motion_status(MotionStatus.IDLE)
            await self.comm.send_event(FilterChangedEvent(filter_name=filter_name))

        await self._run_motion(f"moving to filter {filter_name}", motion())

    async def _restore_filter(self) -> None:
        """Put the filter last asked for back in the beam if the device moved away from it, e.g. it
        came back from a restart in its default slot (drivers call this after reading the device)."""
        chosen = self._chosen
        if chosen is None or chosen == self._filter or chosen not in self._filters:
            return
        log.warning("%s: the wheel came back at %s: moving back to %s", self.name, self._filter, chosen)
        await self._hw_move_filter(chosen)
        self._filter = chosen

    async def init(self) -> None:
        await self._set_motion_status(MotionStatus.IDLE)

    async def park(self) -> None:
        """Nothing to park; the filter stays in the beam."""

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {"FILTER": (self._filter, "Filter in the beam")}
