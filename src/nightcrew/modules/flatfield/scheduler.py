"""Several filter/binning combinations of flats per twilight: the longest-waiting first, in the order
the twilight allows."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Mapping, Sequence
from typing import Any

from nightcrew.astro import sun_altitude_at
from nightcrew.errors import AbortedError, ConfigError, DeviceBusyError, NightcrewError
from nightcrew.flatfield import (
    FlatTask,
    TwilightPlanner,
    last_taken_from_plain,
    prioritised,
    tasks_from_config,
)
from nightcrew.interfaces import Binning, IFlatField, IRunnable
from nightcrew.modules.module import Module

__all__ = ["FlatFieldScheduler"]

log = logging.getLogger(__name__)


class FlatFieldScheduler(Module, IRunnable):
    """Each :meth:`run` asks the flat-field module for every combination, by falling priority.

    A combination's priority grows with the time since it was last taken (see
    :mod:`nightcrew.flatfield.schedule`); those times are kept in ``state_file`` across restarts.
    With the exposure-time ``functions`` (the FlatField module's) and a ``site``, the run is
    planned for the twilight (:mod:`nightcrew.flatfield.twilight_plan`): the combinations that fit,
    by falling priority, in the order their openings close (at dusk those needing long exposures
    first), then the rest. A combination for which the twilight is over gives no flats and is
    simply tried again next time.

    Args:
        flatfield: Module offering IFlatField.
        flats: Combinations, e.g. ``[{filter: V, binning: 2x2, count: 10, weight: 1}, ...]``.
        state_file: VFS path (YAML) of when each combination was last taken; None: memory only.
        functions: Filter -> binning -> exposure time as a function of ``h``; None: priority only.
        min_exposure, max_exposure: T_min and T_max, as configured for the flat-field module.
        overhead: Seconds per flat besides the exposure (read-out, pointing), for the plan.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        flatfield: str | IFlatField,
        flats: list[dict[str, Any]],
        state_file: str | None = None,
        functions: dict[str, dict[str, str]] | None = None,
        min_exposure: float = 1.0,
        max_exposure: float = 30.0,
        overhead: float = 10.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self._combinations: Sequence[FlatTask] = tasks_from_config(flats, "flats")
        self._planner: TwilightPlanner | None = None
        if functions is not None:
            if self.site is None:
                raise ConfigError("planning for the twilight needs the observatory site", key="site")
            self._planner = TwilightPlanner(
                functions, min_exposure=min_exposure, max_exposure=max_exposure, overhead=overhead
            )
        self._flatfield, self._state_file = flatfield, state_file
        self._running: asyncio.Task[None] | None = None

    @property
    def last_taken(self) -> Mapping[str, Any]:
        return dict(self._last_taken)

    async def open(self) -> None:
        self._last_taken = await self._load_state()
        await super().open()

    async def run(self) -> None:
        if self._running is not None:
            raise DeviceBusyError(f"{self.name} is already running")
        self._running = asyncio.create_task(self._run_all())
        try:
            await self._running
        except asyncio.CancelledError:
            current = asyncio.current_task()
            if not (current and current.cancelling()):
                raise AbortedError("flat-field schedule aborted") from None
            raise
        finally:
            self._running = None

    async def abort(self) -> None:
        running = self._running
        if running is not None and not running.done():
            try:
                await (await self.proxy(self._flatfield, IFlatField)).abort()
            finally:
                running.cancel()
                await asyncio.wait([running])

    async def _run_all(self) -> None:
        flatfield = await self.proxy(self._flatfield, IFlatField)
        for task in self._order():
            log.info("%s: %d flats in %s", self.name, task.count, task.key)
            try:
                done, seconds = await flatfield.flat_field(
                    task.count, Binning(*task.binning), task.filter_name
                )
            except AbortedError:
                raise
            except NightcrewError as exc:
                log.warning("%s: %s failed: %s", self.name, task.key, exc)
                continue
            log.info("%s: %s gave %d flats, %.1f s in all", self.name, task.key, done, seconds)
            if done > 0:
                self._last_taken[task.key] = self.clock.now()
                await self._save_state()

    def _order(self) -> list[FlatTask]:
        """The combinations by priority, planned for the twilight if there is a planner."""
        by_priority = prioritised(self._combinations, self._last_taken, self.clock.now())
        if self._planner is None or self.site is None:
            return by_priority
        plan = self._planner.plan(by_priority, sun_altitude_at(self.site), self.clock.time())
        for planned in plan:
            if not planned.fits:
                log.info(
                    "%s: %s does not fit this twilight as modelled; tried last", self.name, planned.task.key
                )
        return [planned.task for planned in plan]

    async def _load_state(self) -> dict[str, Any]:
        path = self._state_file
        if path is None or not await self.vfs.exists(path):
            return {}
        try:
            state, problems = last_taken_from_plain(await self.vfs.read_yaml(path))
        except NightcrewError as exc:
            log.error("%s: cannot read %s, starting afresh: %s", self.name, path, exc)
            return {}
        for problem in problems:
            log.warning("%s: %s: skipped %s", self.name, path, problem)
        return dict(state)

    async def _save_state(self) -> None:
        if self._state_file is None:
            return
        plain = {key: when.isoformat() for key, when in self._last_taken.items()}
        try:
            await self.vfs.write_yaml(self._state_file, plain)
        except NightcrewError as exc:
            log.error("%s: cannot write %s: %s", self.name, self._state_file, exc)
