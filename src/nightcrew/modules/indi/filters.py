"""A filter wheel behind an INDI driver: slot ``FILTER_SLOT`` (1-based), names from ``FILTER_NAME``.

The names are the device's: they are read on every connection (and when the device changes them);
``filters`` in the YAML file, if given, is what the wheel must hold.

Example (``examples/indi/filterwheel.yaml``)::

    class: nightcrew.modules.indi.IndiFilterWheel
    host: 192.168.1.20
    device: Filter Simulator
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.indi import IndiError, IndiUpdate, Vector
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.filters import BaseFilterWheel
from nightcrew.modules.indi.link import IndiModule

__all__ = ["IndiFilterWheel"]

_SLOT = "FILTER_SLOT"
_VALUE = "FILTER_SLOT_VALUE"
_NAMES = "FILTER_NAME"
#: Stands for the names until the device has told them (the base needs one at construction).
_UNKNOWN = "(not yet read from the device)"


class IndiFilterWheel(IndiModule, BaseFilterWheel):
    """An INDI filter wheel.

    Args:
        filters: The names the wheel should hold, in slot order; when given, a wheel holding
            others is an error (e.g. after someone swapped filters). By default: whatever it holds.
        **kwargs: INDI options (``host``, ``port``, ``device`` ...) and module options.
    """

    indi_needs = (_SLOT, _NAMES)

    def __init__(self, *, filters: list[str] | None = None, **kwargs: Any) -> None:
        super().__init__(filters=list(filters) if filters else [_UNKNOWN], **kwargs)
        self._expected = list(filters) if filters else None

    def _read_names(self, names: Vector) -> None:
        # Member order is slot order (FILTER_SLOT_NAME_1, _2, ...).
        found = [str(value) for value in names.members.values()]
        if not found or len(set(found)) != len(found):
            raise IndiError(
                f"filter names must be unique and present, got {found}", device=names.device, name=_NAMES
            )
        if self._expected is not None and found != self._expected:
            raise IndiError(
                f"the wheel holds {found}, the configuration (key 'filters') expects {self._expected}",
                device=names.device,
                name=_NAMES,
            )
        self._filters = found

    def _read_slot(self, slot: Vector) -> None:
        number = round(slot.number(_VALUE))
        if 1 <= number <= len(self._filters):
            self._filter = self._filters[number - 1]

    async def _on_indi_ready(self) -> None:
        self._read_names(self._indi.vector(_NAMES))
        self._read_slot(self._indi.vector(_SLOT))
        if not self._motion.busy:
            await self._restore_filter()  # a restarted driver comes back in its default slot
            await self._set_motion_status(MotionStatus.IDLE)

    async def _on_indi_update(self, update: IndiUpdate) -> None:
        if update.vector is None or self._motion.busy:
            return
        if update.name == _NAMES:
            self._read_names(update.vector)
        elif update.name == _SLOT:
            self._read_slot(update.vector)

    async def _hw_move_filter(self, filter_name: str) -> None:
        slot = self._filters.index(filter_name) + 1
        await self._indi.send(
            _SLOT, {_VALUE: slot}, wait=self._move_timeout, done=lambda v: round(v.number(_VALUE)) == slot
        )

    async def _hw_stop(self) -> None:
        """A wheel cannot stop between filters; the move runs to its end."""
