"""AlpacaFilterWheel: an ASCOM Alpaca filter wheel on the filter-wheel base.

Filter names come from the device (``Names``) unless the configuration gives its own (one per
slot, same count). Changing filters sets ``Position`` and polls it until the wheel reports the
new slot (it reports -1 while moving). The device's ``FocusOffsets`` (focuser steps) are the
read-only config option ``focus_offsets`` (filter name -> steps). After a reconnect (e.g. the
server restarted) the filter last asked for is moved back into the beam before the module is ready.
"""

from __future__ import annotations

from typing import Any

from nightcrew.errors import ConfigError, MoveError
from nightcrew.modules.alpaca.device import AlpacaModule
from nightcrew.modules.filters import BaseFilterWheel

__all__ = ["AlpacaFilterWheel"]

#: Stands for the names until the device has told them.
_UNKNOWN = "(not connected)"


class AlpacaFilterWheel(AlpacaModule, BaseFilterWheel):
    """A filter wheel reached over ASCOM Alpaca.

    Args:
        filters: Names of the slots, overriding the device's; the device's by default.
        move_timeout: Wall seconds a filter change may take.
        **kwargs: ``server``, ``device_number`` and the other Alpaca options (AlpacaModule).
    """

    device_type = "filterwheel"

    def __init__(
        self, *, filters: list[str] | None = None, move_timeout: float = 60.0, **kwargs: Any
    ) -> None:
        super().__init__(filters=list(filters) if filters else [_UNKNOWN], **kwargs)
        if not move_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {move_timeout}", key="move_timeout")
        self._configured = list(filters) if filters else None
        self._move_timeout = float(move_timeout)
        self._focus_offsets: list[int] = []

    async def _on_connected(self) -> None:
        names = [str(n) for n in await self._get("names")]
        if self._configured is not None and len(self._configured) != len(names):
            raise ConfigError(
                f"{len(self._configured)} names configured, but {self.device.name} has {len(names)} slots",
                key="filters",
            )
        self._filters = self._configured or names
        self._focus_offsets = [int(v) for v in await self._get("focusoffsets")]
        position = int(await self._get("position"))
        if 0 <= position < len(self._filters):
            self._filter = self._filters[position]
        await self._restore_filter()

    async def _hw_move_filter(self, filter_name: str) -> None:
        slot = self._filters.index(filter_name)
        await self._put("position", Position=slot)
        await self._poll_until(
            "position",
            lambda at: at == slot,
            self._move_timeout,
            f"move to filter {filter_name!r}",
            MoveError,
        )

    async def _hw_stop(self) -> None:
        """A filter wheel cannot be stopped halfway; the change ends by itself."""

    def _get_config_focus_offsets(self) -> dict[str, int]:
        return dict(zip(self._filters, self._focus_offsets, strict=False))
