"""A simulated filter wheel: every change takes the same time."""

from __future__ import annotations

from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.modules.filters import BaseFilterWheel

__all__ = ["SimFilterWheel"]


class SimFilterWheel(BaseFilterWheel):
    """A filter wheel in the simulated observatory.

    Args:
        change_time: Seconds a filter change takes.
        **kwargs: Filter wheel options (``filters``, ``filter_name``) and module options.
    """

    def __init__(self, *, change_time: float = 3.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if change_time < 0:
            raise ConfigError(f"must be >= 0 seconds, got {change_time}", key="change_time")
        self._change_time = float(change_time)

    async def _hw_move_filter(self, filter_name: str) -> None:
        await self.clock.sleep(self._change_time)

    async def _hw_stop(self) -> None:
        """The wheel stays on the old filter when stopped midway."""
