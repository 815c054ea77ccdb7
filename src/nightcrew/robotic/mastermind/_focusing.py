"""Keeping the telescope in focus: whether a focus is due, and the auto-focus run under watch.

A failed focus run (e.g. a series whose widths form no clear V) leaves the focus as it was - the
focus module puts the focuser back - and the night goes on with it: observing slightly out of focus
beats not observing. The focus stays due, but is tried again only after ``retry_interval`` clock
seconds, so a sky that cannot be focused on (clouds, too few stars) costs one series per interval
instead of one before every task.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable

from nightcrew.errors import NightcrewError
from nightcrew.interfaces import IAutoFocus
from nightcrew.object import Object
from nightcrew.robotic.mastermind._decide import SunLimits
from nightcrew.robotic.mastermind._observatory import ObservatoryControl
from nightcrew.robotic.mastermind._supervision import run_watched
from nightcrew.robotic.mastermind._tasks import focus_due

__all__ = ["FocusKeeper"]

log = logging.getLogger(__name__)


class FocusKeeper:
    """Remembers the last focus (and its temperature) and runs the auto-focus when asked.

    Args:
        host: The module whose comm and clock are used (and whose name prefixes log lines).
        observatory: Where the temperature comes from.
        autofocus: Module offering IAutoFocus (or a local object).
        max_sun_altitude: Highest Sun altitude for focusing, degrees (stars must show).
        refocus_change: Refocus after this temperature change, °C.
        arguments: (count, step, exposure_time) of ``auto_focus``.
        retry_interval: Clock seconds after a failed focus run before the next attempt.
    """

    def __init__(
        self,
        host: Object,
        observatory: ObservatoryControl,
        autofocus: str | IAutoFocus,
        *,
        max_sun_altitude: float,
        refocus_change: float,
        arguments: tuple[int, float, float],
        retry_interval: float = 1800.0,
    ) -> None:
        self._host, self._observatory, self._autofocus = host, observatory, autofocus
        self.limits = SunLimits(high=float(max_sun_altitude))
        self._refocus_change, self._arguments = refocus_change, arguments
        self._retry_interval = float(retry_interval)
        self._focused = False
        self._temperature: float | None = None
        self._retry_at: float | None = None  # clock time before which a failed focus is not retried

    async def focus_below(self) -> float | None:
        """The highest Sun altitude to focus at if a focus is due, else None."""
        if self._retry_at is not None and self._host.clock.time() < self._retry_at:
            return None
        temperature = await self._observatory.temperature() if self._focused else None
        due = focus_due(
            focused=self._focused,
            last_temperature=self._temperature,
            temperature=temperature,
            threshold=self._refocus_change,
        )
        return self.limits.high if due else None

    async def focus(
        self,
        check: Callable[[], Awaitable[str | None]],
        *,
        wake: asyncio.Event,
        poll_interval: float,
        abort_timeout: float,
    ) -> None:
        """Run the auto-focus, aborted when ``check`` gives a cause (then it stays due)."""
        name = self._host.context_name
        temperature = await self._observatory.temperature()
        log.info("%s: focusing (temperature %s, last focus at %s)", name, temperature, self._temperature)
        autofocus = await self._host.proxy(self._autofocus, IAutoFocus)
        try:
            cause = await run_watched(
                autofocus.auto_focus(*self._arguments),
                check,
                wake=wake,
                clock=self._host.clock,
                poll_interval=poll_interval,
                abort_timeout=abort_timeout,
                on_abort=autofocus.abort,
            )
        except NightcrewError as exc:
            self._retry_at = self._host.clock.time() + self._retry_interval
            log.warning(
                "%s: focusing failed (%s); going on with the focus as it is, next try in %.0f s",
                name,
                exc,
                self._retry_interval,
            )
            return
        if cause is not None:
            log.warning("%s: focusing aborted: %s", name, cause)
            return
        self._focused, self._temperature, self._retry_at = True, temperature, None
