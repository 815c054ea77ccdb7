"""The safety watchdog: closes the roof and parks the telescope when a safety module goes silent.

Independent of the mastermind, every ``interval`` clock seconds it asks each watched module (the
weather module, the mastermind …) for its state; an answer within ``answer_timeout`` saying READY
is a heartbeat. A module without a heartbeat for longer than its limit (silent, frozen, crashed,
offline or in error state) raises the alarm: a SafetyAlarmEvent (roofs close and telescopes park
by themselves on it, and refuse to open until it is cleared), and the watchdog itself tells the roof
to close and the telescope to park, again on every round while the alarm lasts. The alarm clears
(SafetyClearedEvent) only when every heartbeat is back and, if a ``weather`` module is named, it
says the weather is good.

Every round also sends a WatchdogHeartbeatEvent: a roof or telescope that names this module as its
``watchdog`` closes or parks by itself when these stop (the dead-man's switch), so a frozen or dead
watchdog does not leave the roof open. When the XMPP server itself is gone, nobody reaches the roof:
the roof closes by itself after its ``park_when_offline`` limit (see nightcrew.modules.motion.base).

Example (``examples/sim-processes/watchdog.yaml``)::

    class: nightcrew.modules.safety.SafetyWatchdog
    watch: {weather: 120, mastermind: 300}   # module → clock seconds it may be silent
    roof: roof
    telescope: telescope
    weather: weather
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import SafetyAlarmEvent, SafetyClearedEvent, WatchdogHeartbeatEvent
from nightcrew.interfaces import IModule, IRoof, ITelescope, IWeather, ModuleState
from nightcrew.interfaces.quantities import Period, Timeout
from nightcrew.modules.module import Module
from nightcrew.modules.safety.heartbeats import HeartbeatMonitor

__all__ = ["SafetyWatchdog"]

log = logging.getLogger(__name__)


class SafetyWatchdog(Module):
    """Watches the safety modules' heartbeats; closes and parks when one stops.

    Args:
        watch: Module name → clock seconds it may go without a heartbeat (0.01 to 86400).
        roof: The roof module to close (None: none).
        telescope: The telescope module to park (None: none).
        weather: The weather module whose verdict must be good before the alarm clears (None: not
            asked; watch it too, so that its silence raises the alarm).
        interval: Clock seconds between two rounds of heartbeats (0.01 to 86400).
        answer_timeout: Clock seconds a module may take to answer (0.01 to 86400).
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        watch: dict[str, Timeout],
        roof: str | None = "roof",
        telescope: str | None = "telescope",
        weather: str | None = None,
        interval: Period = 10.0,
        answer_timeout: Timeout = 10.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not watch:
            raise ConfigError("name at least one module to watch (name: seconds)", key="watch")
        for name, limit in watch.items():
            if not limit > 0:
                raise ConfigError(f"must be > 0 seconds, got {limit}", key=f"watch.{name}")
        for key, value in (("interval", interval), ("answer_timeout", answer_timeout)):
            if not value > 0:
                raise ConfigError(f"must be > 0 seconds, got {value}", key=key)
        if roof is None and telescope is None:
            raise ConfigError("name a roof or a telescope to secure", key="roof")
        self._limits = {name: float(limit) for name, limit in watch.items()}
        self._roof = roof
        self._telescope = telescope
        self._weather = weather
        self._interval = float(interval)
        self._answer_timeout = float(answer_timeout)
        self._alarm: str | None = None
        self._securing: asyncio.Task[None] | None = None
        self.add_background_task(self._watch_loop)

    @property
    def alarm(self) -> str | None:
        """Why the alarm is raised, or None."""
        return self._alarm

    async def close(self) -> None:
        if self._securing is not None:
            self._securing.cancel()
            await asyncio.gather(self._securing, return_exceptions=True)
        await super().close()

    # --- the loop ------------------------------------------------------------------------------

    async def _watch_loop(self) -> None:
        monitor = HeartbeatMonitor(self._limits, self.clock.time())
        while True:
            await self._beat()
            problems = await asyncio.gather(*(self._ask(name) for name in self._limits))
            now = self.clock.time()
            for name, problem in zip(self._limits, problems, strict=True):
                monitor.beat(name, now, problem)
            late = monitor.overdue(now)
            if late:
                await self._raise_alarm("; ".join(late.values()))
            elif self._alarm is not None and all(p is None for p in problems):
                await self._maybe_clear()
            await self.clock.sleep(self._interval)

    async def _beat(self) -> None:
        """Tell the roofs and telescopes that name us that we watch (their dead-man's switch)."""
        try:
            await self.comm.send_event(WatchdogHeartbeatEvent())
        except NightcrewError as exc:  # offline: they close by themselves, which is right
            log.debug("%s: heartbeat not sent: %s", self.name, exc)

    async def _ask(self, name: str) -> str | None:
        """None for a heartbeat, else what is wrong with ``name``."""
        try:
            async with self.comm.timeout(self._answer_timeout):
                module = await self.comm.proxy(name, IModule)
                state = ModuleState(await module.get_state())
                if state is ModuleState.ERROR:
                    return f"error state ({await module.get_error_string()})"
        except TimeoutError:
            return "no answer"
        except Exception as exc:
            return f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
        return None if state is ModuleState.READY else f"state {state.value}"

    async def _raise_alarm(self, reason: str) -> None:
        if self._alarm is None:
            log.error("%s: SAFETY ALARM: %s; closing the roof and parking the telescope", self.name, reason)
            await self.comm.send_event(SafetyAlarmEvent(reason=reason))
        self._alarm = reason
        if self._securing is None or self._securing.done():  # again every round: a roof may come back
            self._securing = asyncio.get_running_loop().create_task(self._secure())

    async def _secure(self) -> None:
        async def close_roof(name: str) -> None:
            await (await self.comm.proxy(name, IRoof)).close_roof()

        async def park(name: str) -> None:
            await (await self.comm.proxy(name, ITelescope)).park()

        jobs = [close_roof(self._roof)] if self._roof else []
        jobs += [park(self._telescope)] if self._telescope else []
        for result in await asyncio.gather(*jobs, return_exceptions=True):
            if isinstance(result, Exception):
                log.warning("%s: securing the observatory: %s", self.name, result)

    async def _maybe_clear(self) -> None:
        if self._weather is not None:
            try:
                async with self.comm.timeout(self._answer_timeout):
                    good = await (await self.comm.proxy(self._weather, IWeather)).is_weather_good()
            except Exception as exc:
                log.warning("%s: cannot ask %s about the weather: %s", self.name, self._weather, exc)
                return
            if not good:
                return
        log.info(
            "%s: every heartbeat is back%s: alarm cleared",
            self.name,
            " and the weather is good" if self._weather else "",
        )
        self._alarm = None
        await self.comm.send_event(SafetyClearedEvent())
