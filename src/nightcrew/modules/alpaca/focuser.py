"""AlpacaFocuser: an ASCOM Alpaca focuser on the focuser base (positions in mm, the device's in steps).

``StepSize`` (µm per step, or the ``step_size`` option when the device has none) converts; the
range is 0..MaxStep steps. An absolute focuser moves with ``Move(position)``; a relative one with
``Move(steps)`` in chunks of at most ``MaxIncrement``, its position counted from where it was at
connect (0). Moves poll ``IsMoving``; stop_motion sends ``Halt``. ``Temperature`` is offered as
ITemperatures (for the focus model) and as the FITS card FOCTEMP. After a reconnect (e.g. the
server restarted) an absolute focuser moves back to the position last set before the module is ready.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from nightcrew.errors import ConfigError, MoveError, NightcrewError
from nightcrew.interfaces import FitsCard, ITemperatures
from nightcrew.modules.alpaca.device import AlpacaModule
from nightcrew.modules.focuser import BaseFocuser

__all__ = ["AlpacaFocuser"]

log = logging.getLogger(__name__)


class AlpacaFocuser(AlpacaModule, BaseFocuser, ITemperatures):
    """A focuser reached over ASCOM Alpaca.

    Args:
        step_size: Microns per step if the device does not say (StepSize not implemented).
        move_timeout: Wall seconds a move may take.
        **kwargs: ``server``, ``device_number`` and the other Alpaca options (AlpacaModule), and the
            focuser's (``min_focus``/``max_focus`` are replaced by the device's range on connect).
    """

    device_type = "focuser"

    def __init__(self, *, step_size: float = 1.0, move_timeout: float = 120.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not step_size > 0:
            raise ConfigError(f"must be > 0 microns, got {step_size}", key="step_size")
        if not move_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {move_timeout}", key="move_timeout")
        self._step_um = float(step_size)
        self._move_timeout = float(move_timeout)
        self._absolute = True
        self._max_increment = 0
        self._steps = 0  # where a relative focuser is, counted by us

    async def _on_connected(self) -> None:
        try:
            self._step_um = float(await self._get("stepsize"))
        except NightcrewError:
            log.info("%s: the device gives no StepSize; using %g µm", self.name, self._step_um)
        self._absolute = bool(await self._get("absolute"))
        max_step = int(await self._get("maxstep"))
        self._max_increment = int(await self._get("maxincrement"))
        self._min_focus, self._max_focus = 0.0, self._mm(max_step)
        if self._absolute:
            self._steps = int(await self._get("position"))
        self._focus = self._mm(self._steps) - self._offset
        if self._absolute:  # a relative focuser that restarted does not know where it is
            await self._restore_focus()

    def _mm(self, steps: int) -> float:
        return steps * self._step_um / 1000.0

    def _to_steps(self, mm: float) -> int:
        return round(mm * 1000.0 / self._step_um)

    async def _hw_move_focus(self, position: float) -> None:
        target = self._to_steps(position)
        try:
            if self._absolute:
                await self._put("move", Position=target)
                await self._wait_stopped(target)
            else:
                while self._steps != target:
                    step = max(-self._max_increment, min(self._max_increment, target - self._steps))
                    await self._put("move", Position=step)
                    await self._wait_stopped(target)
                    self._steps += step
        except asyncio.CancelledError:
            await asyncio.shield(self._put_best_effort("halt"))
            raise
        if self._absolute:
            self._steps = int(await self._get("position"))

    async def _wait_stopped(self, target: int) -> None:
        await self._poll_until(
            "ismoving",
            lambda moving: moving is False,
            self._move_timeout,
            f"move to step {target}",
            MoveError,
        )

    async def _hw_stop(self) -> None:
        await self._put_best_effort("halt")
        if self._absolute:
            self._steps = int(await self._get("position"))

    async def get_temperatures(self) -> dict[str, float]:
        return {"focuser": float(await self._get("temperature"))}

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        cards = await super().get_fits_header_before(namespaces)
        try:
            cards["FOCTEMP"] = (round(float(await self._get("temperature")), 2), "Focuser temperature [degC]")
        except NightcrewError as exc:
            log.debug("%s: no focuser temperature: %s", self.name, exc)
        return cards
