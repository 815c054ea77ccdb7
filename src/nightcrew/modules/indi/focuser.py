"""A focuser behind an INDI driver: ``ABS_FOCUS_POSITION`` in steps, nightcrew's focus in mm.

Example (``examples/indi/focuser.yaml``)::

    class: nightcrew.modules.indi.IndiFocuser
    host: 192.168.1.20
    device: Focuser Simulator
    steps_per_mm: 1000
    max_focus: 100
"""

from __future__ import annotations

import math
from typing import Any

from nightcrew.bridges.indi import IndiUpdate, PropertyState
from nightcrew.errors import ConfigError
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.focuser import BaseFocuser
from nightcrew.modules.indi.link import IndiModule

__all__ = ["IndiFocuser"]

_POSITION = "ABS_FOCUS_POSITION"
_MEMBER = "FOCUS_ABSOLUTE_POSITION"


class IndiFocuser(IndiModule, BaseFocuser):
    """An INDI focuser.

    Args:
        steps_per_mm: Motor steps per millimetre of focus travel (> 0).
        **kwargs: INDI options (``host``, ``port``, ``device`` ...) and focuser options
            (``min_focus``, ``max_focus`` in mm).
    """

    indi_needs = (_POSITION,)

    def __init__(self, *, steps_per_mm: float = 1000.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not (math.isfinite(steps_per_mm) and steps_per_mm > 0):
            raise ConfigError(f"must be > 0, got {steps_per_mm}", key="steps_per_mm")
        self._steps_per_mm = float(steps_per_mm)

    async def _on_indi_ready(self) -> None:
        # The device knows where it is; the offset stays what nightcrew set.
        self._focus = self._indi.vector(_POSITION).number(_MEMBER) / self._steps_per_mm - self._offset
        if not self._motion.busy:
            await self._restore_focus()  # a restarted driver comes back at its default position
            await self._set_motion_status(MotionStatus.IDLE)

    async def _on_indi_update(self, update: IndiUpdate) -> None:
        """Report moves started elsewhere (another client, a hand controller)."""
        if update.name != _POSITION or self._motion.busy or update.vector is None:
            return
        if update.vector.state is PropertyState.BUSY:
            await self._set_motion_status(MotionStatus.MOVING)
        elif update.vector.state is PropertyState.ALERT:
            await self._set_motion_status(MotionStatus.ERROR)
        else:
            self._focus = update.vector.number(_MEMBER) / self._steps_per_mm - self._offset
            await self._set_motion_status(MotionStatus.IDLE)

    async def _hw_move_focus(self, position: float) -> None:
        steps = round(position * self._steps_per_mm)
        await self._indi.send(
            _POSITION,
            {_MEMBER: steps},
            wait=self._move_timeout,
            done=lambda v: round(v.number(_MEMBER)) == steps,
        )

    async def _hw_stop(self) -> None:
        await self._indi.abort("FOCUS_ABORT_MOTION")
