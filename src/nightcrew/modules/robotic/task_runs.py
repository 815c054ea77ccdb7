"""Running the scheduled task for the mastermind: under watch, recorded, riding out device faults.

A task is checked (can the runner run it now? - after waiting for device modules that are away),
marked started, run under watch for the slot's
abort causes (weather, roof, Sun, a stop) and recorded as finished or failed. When a device fails
under it (:func:`~nightcrew.robotic.mastermind.device_fault`) the task is not given up at once: the
device module gets ``device_wait`` clock seconds to be back and READY (:class:`DeviceWatch`), then
the task restarts from its progress, at most ``device_retries`` times. A device that stays away
fails the task as a device fault (retryable: the scheduler plans it again the same night); the
task's own failure is not retried. Either way it does not run again in this slot. A camera module
that restarts while the task runs (its frame in flight lost, its settings back to defaults) makes
the task restart from its progress at once, so it sets the camera up again.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable, Coroutine
from datetime import datetime
from typing import Any

from nightcrew.errors import ConfigError, ModuleError, NightcrewError
from nightcrew.modules.module import Module
from nightcrew.modules.robotic.device_watch import DeviceWatch
from nightcrew.robotic.mastermind import (
    AbortCheck,
    ScheduleReader,
    Slot,
    TaskRecorder,
    device_fault,
    interruption_reason,
    resumed,
    run_watched,
)
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.tasks import Task

__all__ = ["TaskRuns"]

log = logging.getLogger(__name__)


class TaskRuns:
    """Runs one scheduled task at a time for ``host`` (the mastermind).

    Args:
        host: The mastermind (comm, clock, log prefix).
        runner: Runs a task's configurations.
        recorder: Records start, progress and end.
        schedule: Told of a slot in which a task must not run again.
        abort_cause: Why a task in a slot must stop now, or None.
        wake: Set when something happened that may be an abort cause (events).
        poll_interval: Clock seconds between two looks at the abort cause.
        abort_timeout: Clock seconds an aborted task may take to clean up.
        device_wait: Clock seconds to wait for a failed device module to be back and READY.
        device_retries: Restarts of a task in one run after a device came back.
    """

    def __init__(
        self,
        host: Module,
        runner: TaskRunner,
        recorder: TaskRecorder,
        schedule: ScheduleReader,
        abort_cause: Callable[[Slot], Awaitable[str | None]],
        wake: asyncio.Event,
        *,
        poll_interval: float,
        abort_timeout: float,
        device_wait: float,
        device_retries: int,
    ) -> None:
        if not device_wait >= 0:
            raise ConfigError(f"must be >= 0 seconds, got {device_wait}", key="device_wait")
        if isinstance(device_retries, bool) or not isinstance(device_retries, int) or device_retries < 0:
            raise ConfigError(f"must be an integer >= 0, got {device_retries!r}", key="device_retries")
        self._host, self._runner, self._recorder, self._schedule = host, runner, recorder, schedule
        self._abort_cause, self._wake = abort_cause, wake
        self._poll, self._abort_timeout = poll_interval, abort_timeout
        self._device_wait, self._device_retries = float(device_wait), device_retries
        self._devices = DeviceWatch(host, on_return=wake.set)
        self.times: tuple[datetime, datetime] | None = None  # (start, eta) of the running task

    async def open(self) -> None:
        """Start noticing device modules going and coming (after the host's comm is open)."""
        await self._devices.open()

    @property
    def _name(self) -> str:
        return self._host.context_name

    async def run(self, slot: Slot, task: Task) -> None:
        """Run the task of ``slot`` under watch and record how it ended."""
        if not await self._can_run_now(slot, task):
            log.warning(
                "%s: the runner cannot run task %s (%s); skipping its slot", self._name, task.id, task.name
            )
            self._schedule.failed_in(task.id, slot.start)
            return
        recorder = self._recorder
        task = await recorder.started(task, eta=slot.end)
        self.times = (self._host.clock.now(), slot.end)
        reason: str | None = None
        interrupted = True  # from outside (weather, roof, Sun, shutdown): it may run again later
        by_device = False
        try:
            cause = await self._through_device_faults(slot, task)
            if cause is not None:
                reason = interruption_reason(cause, task, recorder.progress)
        except asyncio.CancelledError:
            reason = interruption_reason("the mastermind shutting down", task, recorder.progress)
            raise
        except Exception as exc:  # not again in this slot: a device fault is planned again later
            self._schedule.failed_in(task.id, slot.start)
            by_device = interrupted = device_fault(exc) is not None
            reason = str(exc) or type(exc).__name__
            if not isinstance(exc, NightcrewError):
                raise  # a bug: the loop's fail-safe closes and parks
        finally:
            self.times = None
            await recorder.ended(task, reason, retryable=interrupted, device_fault=by_device)

    async def _through_device_faults(self, slot: Slot, task: Task) -> str | None:
        """Run the task under watch; after a device fault wait for the device and restart the task
        from its progress (``device_retries`` times). The cause if it was stopped, as run_watched.

        Raises:
            NightcrewError: The task's own failure, or a device fault the device did not recover from.
        """
        restarts = 0
        while True:  # bounded: each round is a restart
            since, restarted = self._devices.returns(), list[str]()

            async def check(since: dict[str, int] = since, restarted: list[str] = restarted) -> str | None:
                camera = await self._devices.restarted_camera(since)
                if camera is None:
                    return await self._abort_cause(slot)
                restarted.append(camera)
                return f"a restart of {camera}"

            try:
                cause = await self._watched(self._runner.run_task(task, self._recorder.on_progress), check)
            except NightcrewError as exc:
                fault = device_fault(exc)
                if fault is None or restarts >= self._device_retries:
                    raise
                restarts += 1
                log.warning("%s: task %s: a device failed: %s", self._name, task.id, fault.reason)

                async def device_back(error: NightcrewError = exc, module: str | None = fault.module) -> None:
                    if not await self._devices.wait_back(module, self._device_wait):
                        raise error

                cause = await self._watched(device_back(), lambda: self._abort_cause(slot))
                if cause is not None:
                    return cause
            else:
                if not restarted:
                    return cause
                # A camera module restarted under the task: what the task set up there is gone.
                if restarts >= self._device_retries:
                    raise ModuleError(f"{restarted[0]} restarted during the task", module=restarted[0])
                restarts += 1
            task = resumed(task, self._recorder.progress)
            log.info("%s: restarting task %s from its progress", self._name, task.id)

    async def _watched(self, work: Coroutine[Any, Any, Any], check: AbortCheck) -> str | None:
        """``work`` under watch: stopped when ``check`` gives a cause (see run_watched)."""
        return await run_watched(
            work,
            check,
            wake=self._wake,
            clock=self._host.clock,
            poll_interval=self._poll,
            abort_timeout=self._abort_timeout,
        )

    async def _can_run_now(self, slot: Slot, task: Task) -> bool:
        """Whether the runner can run the task; while device modules are away (restarting), asked
        again once they are back, if they are within ``device_wait``."""
        if await self._can_run(task):
            return True
        if not self._devices.away:
            return False
        back: list[bool] = []

        async def wait() -> None:
            back.append(await self._devices.wait_back(None, self._device_wait))

        cause = await self._watched(wait(), lambda: self._abort_cause(slot))
        return cause is None and back == [True] and await self._can_run(task)

    async def _can_run(self, task: Task) -> bool:
        try:
            return await self._runner.can_run(task)
        except NightcrewError as exc:
            log.warning("%s: cannot check task %s: %s", self._name, task.id, exc)
            return False
