"""The mastermind: runs the scheduled task due now whenever it can, and keeps the observatory safe.

Every ``poll_interval`` clock seconds (at once on weather, roof and schedule events) it observes the world
(weather verdict, roof, telescope, Sun), reads the schedule around now and lets
:func:`nightcrew.robotic.mastermind.decide` choose: run the due task, open up for it, close and
park, or wait. While a task runs it keeps watching and cancels the task when
:func:`~nightcrew.robotic.mastermind.abort_cause` says so (bad weather, roof not open, dawn).

Decisions:

* **Weather**: with a ``weather`` module its verdict is polled, and Bad/GoodWeatherEvents act at
  once; a module that does not answer means bad weather. Without one only the events count, and
  until the first GoodWeatherEvent the weather is unknown, i.e. bad: the roof stays closed.
* **Roof**: the mastermind opens the roof (and initialises the telescope) when a sky task is due
  and may run, and closes it and parks the telescope on bad weather, at dawn, at the end of the
  schedule and before a gap longer than ``keep_open`` until the roof is used again - by a sky task
  (the next one from when it may start early, see below), or by the focus it opens up for
  ``keep_open`` before a task (so it does not close for a few minutes at dusk). Bad weather, dawn,
  a stop and an error close at once. Roof and telescope also close and park by themselves on a
  BadWeatherEvent; the mastermind does not rely on them, nor they on it.
* **Tasks**: an aborted task becomes FAILED with ``interrupted by <cause>: N of M exposures done``
  (and, when a science frame was stopped and kept, ``, 1 cut short after 143 of 300 s (kept)``: it
  is in the progress too, but not done, so a retry takes it again) and its progress - FAILED tasks
  are schedulable, so it is back in the pool, never lost. It may run
  again in the same slot once the cause has passed (good weather), or where the scheduler puts it.
  A task that failed by its own error is not retried in the same slot.
* **Device faults**: when a device fails under a task (its module offline, restarting or in error,
  a device error, a call that timed out - :func:`~nightcrew.robotic.mastermind.device_fault`), the
  mastermind waits up to ``device_wait`` clock seconds for that module to be back and READY and
  then restarts the task from its progress (at most ``device_retries`` times per run). A device
  that stays away fails the task with ``TaskFailedEvent(retryable=True, device_fault=True)``: the
  scheduler plans it again later the same night. A device fault never closes the roof. A camera
  module that restarts under a running task restarts the task too (its settings were lost). See
  :class:`~nightcrew.modules.robotic.task_runs.TaskRuns`.
* **Focus**: with an ``autofocus`` module, before the first task that images stars (not before
  twilight flats) and whenever the temperature moved by more than ``refocus_temperature_change``
  since the last focus, or ``refocus_interval`` clock seconds after it (if set) - once the Sun
  is below ``focus_max_sun_altitude``, and already while
  waiting for that task with the roof open (at dusk: after the flats, before full darkness). The
  telescope first slews to a star field chosen from the offline catalogue near where it points
  (``focus_field``: enough stars of the right brightness, none too bright, high up) and tracks it -
  left where the flats pointed (alt/az, not tracking), the stars would trail. A failed series is
  tried on another field (``focus_attempts`` fields in all); then the focus is kept as it was and
  tried again ``focus_retry_interval`` clock seconds later.
* **Time left**: a sky task is started (or opened up and focused for) only when what it has left
  (its recorded progress, default overheads) ends inside its window and before its Sun (with the
  cap), airmass or Moon limit stops holding - the early start's minute grid. Otherwise it is passed
  over at that step (not failed; asked again at the next one), so it is not aborted at dawn half
  done. The Sun still aborts a task that runs longer than estimated.
* **Rapid response**: on a RapidResponseEvent (trusted only from the senders the access policy
  names for it) the announced RAPID_RESPONSE tasks that fit now run at the next safe point: a
  running task of lower priority is stopped as for bad weather (its frame in flight stopped and
  kept, the task FAILED with its progress, planned again later) and the rapid-response task runs
  in a slot from now, ahead of the plan (docs/rapid-response.md). It does not wait for a due
  refocus (only for the first focus since the start).
* **Cancelled while running** (a retracted alert, an operator): on a TasksChangedEvent saying so,
  the task the archive holds as CANCELED is stopped at once, its frame in flight kept; it stays
  CANCELED.
* **Early start**: when nothing is due, the next task may start up to ``early_start`` seconds
  before its slot if it can be observed from now on (a task that ended early leaves no gap).
* **Progress** of a task is recorded in the archive in the background: the exposure loop does not
  wait for the database; the end of a task is recorded after its last progress.
* **Start/stop** (IStartStop): stopping aborts the running task, then closes and parks.
* **Errors**: an error in the loop closes the roof and parks; the loop restarts with backoff. A task
  left RUNNING by a mastermind that was killed is marked FAILED (with its progress) at start-up.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from dataclasses import replace
from datetime import datetime, timedelta
from typing import Any, ClassVar

from nightcrew.errors import ConfigError
from nightcrew.events import (
    BadWeatherEvent,
    GoodWeatherEvent,
    RapidResponseEvent,
    RoofClosingEvent,
    ScheduleChangedEvent,
    TasksChangedEvent,
)
from nightcrew.focus.sources import source_from_config
from nightcrew.interfaces import (
    FitsCard,
    IAutoFocus,
    IAutonomous,
    IFitsHeaderBefore,
    IRobotic,
    IRoof,
    IStartStop,
    ITelescope,
    IWeather,
    RoboticStatus,
)
from nightcrew.interfaces.quantities import Altitude, ExposureTime, Period
from nightcrew.modules.module import Module
from nightcrew.modules.robotic._archive_option import built_option
from nightcrew.modules.robotic.rapid_response import AnnouncedTasks, Withdrawals
from nightcrew.modules.robotic.task_runs import TaskRuns
from nightcrew.robotic.archives import ScheduleStore, TaskArchive
from nightcrew.robotic.mastermind import (
    Action,
    CloseAndPark,
    Conditions,
    EarlyStarts,
    Focus,
    FocusFields,
    FocusKeeper,
    ObservatoryControl,
    OpenUp,
    RapidResponse,
    RunTask,
    ScheduleReader,
    Slot,
    TaskRecorder,
    abort_cause,
    ahead_of_plan,
    decide,
    focus_now,
    preemption_cause,
    robotic_status,
    task_cards,
    time_left,
    within_constraints,
    without_refocus,
)
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.scripts.focus_fields import catalogue_rules
from nightcrew.robotic.tasks import Task, target_radec

__all__ = ["Mastermind"]

log = logging.getLogger(__name__)


class Mastermind(Module, IAutonomous, IStartStop, IFitsHeaderBefore, IRobotic):
    """Runs the schedule unattended: the task due now, whenever weather, roof and Sun allow.

    Args:
        archive: Where tasks come from and their fate goes (an object or its description).
        schedule: Where the schedule is read; the archive when it is also a ScheduleStore.
        runner: Runs a task (TaskRunner or its description).
        roof: Module offering IRoof.
        telescope: Module offering ITelescope.
        weather: Module offering IWeather; None: only weather events count (unknown is bad).
        autofocus: Module offering IAutoFocus; None: never focus.
        focus_temperature: Where the refocus temperature is read: ``{module: NAME, sensor: NAME}``
            (ITemperatures) or ``{module: NAME, weather_sensor: temperature}`` (IWeather); None:
            the ``weather`` module's temperature.
        max_sun_altitude: Highest Sun altitude for science tasks, degrees.
        twilight_max_sun_altitude: Highest Sun altitude for twilight (SKY_FLAT) tasks, degrees.
        keep_open: Clock seconds the roof stays open waiting to be used again (a sky task - the
            next one from when it may start early - or the focus run up to ``keep_open`` before a
            task that needs it); never in bad weather.
        early_start: Clock seconds a task may start before its slot when it can be observed.
        poll_interval: Clock seconds between two looks at the world.
        abort_timeout: Clock seconds an aborted task may take to clean up.
        refocus_temperature_change: Refocus after this temperature change, °C.
        refocus_interval: Refocus after this many clock seconds since the last focus; None: never
            for time alone.
        focus_max_sun_altitude: Highest Sun altitude for focusing, degrees (stars must show).
        focus_count, focus_step, focus_exposure_time: Arguments of ``auto_focus``.
        focus_field: Rules for the focus field (:class:`~nightcrew.astro.star_fields.StarFieldRules`:
            ``radius``, ``magnitudes``, ``min_stars``, ``min_altitude``, ``max_distance``); None:
            the defaults.
        focus_attempts: Fields tried before a focus run counts as failed.
        focus_retry_interval: Clock seconds after a failed focus before it is tried again.
        device_wait: Clock seconds to wait for a device module that failed under a task to be
            back and READY before the task is given up.
        device_retries: How often a task is restarted in one run after a device came back.
        autostart: Start robotic mode when the module opens.
        **kwargs: Module options (``site`` is required: the Sun decides a lot).
    """

    #: Built here (a relative path read against the file's folder), opened and closed with the module.
    config_builds_itself: ClassVar[frozenset[str]] = Module.config_builds_itself | {"archive", "schedule"}

    def __init__(
        self,
        *,
        archive: TaskArchive | dict[str, Any],
        schedule: ScheduleStore | dict[str, Any] | None = None,
        runner: TaskRunner | dict[str, Any],
        roof: str | IRoof = "roof",
        telescope: str | ITelescope = "telescope",
        weather: str | IWeather | None = "weather",
        autofocus: str | IAutoFocus | None = None,
        focus_temperature: dict[str, str] | None = None,
        max_sun_altitude: Altitude = -12.0,
        twilight_max_sun_altitude: Altitude = 0.0,
        keep_open: float = 900.0,
        early_start: float = 0.0,
        poll_interval: Period = 10.0,
        abort_timeout: float = 60.0,
        refocus_temperature_change: float = 2.0,
        refocus_interval: Period | None = None,
        focus_max_sun_altitude: Altitude = -10.0,
        focus_count: int = 7,
        focus_step: float = 0.05,
        focus_exposure_time: ExposureTime = 5.0,
        focus_field: dict[str, Any] | None = None,
        focus_attempts: int = 2,
        focus_retry_interval: Period = 1800.0,
        device_wait: float = 60.0,
        device_retries: int = 2,
        autostart: bool = True,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        site = self.site
        if site is None:
            raise ConfigError("the mastermind needs the observatory's site (for the Sun)", key="site")
        self._sky_site = site  # checked above (the base class keeps it optional)
        for key, value in (
            ("poll_interval", poll_interval),
            ("abort_timeout", abort_timeout),
            ("focus_retry_interval", focus_retry_interval),
        ):
            if not value > 0:
                raise ConfigError(f"must be > 0 seconds, got {value}", key=key)
        self._archive_option = built_option(archive, TaskArchive, "archive", self)
        self._archive: TaskArchive = self._archive_option.value
        store = (
            self._archive
            if schedule is None
            else built_option(schedule, ScheduleStore, "schedule", self).value
        )
        if not isinstance(store, ScheduleStore):
            raise ConfigError("the archive keeps no schedule: configure a ScheduleStore", key="schedule")
        self._runner: TaskRunner = self.add_child(built_option(runner, TaskRunner, "runner", self).value)
        self._observatory = ObservatoryControl(
            self,
            site,
            roof=roof,
            telescope=telescope,
            weather=weather,
            temperature=(
                None
                if focus_temperature is None
                else source_from_config(focus_temperature, "focus_temperature")
            ),
        )
        # Checked even without autofocus.
        if not (isinstance(focus_attempts, int) and focus_attempts >= 1):
            raise ConfigError(f"must be an integer >= 1, got {focus_attempts!r}", key="focus_attempts")
        fields = FocusFields(catalogue_rules(focus_field or {}, "focus_field"), site)
        self._focus_keeper = (
            None
            if autofocus is None
            else FocusKeeper(
                self,
                self._observatory,
                autofocus,
                max_sun_altitude=focus_max_sun_altitude,
                refocus_change=refocus_temperature_change,
                refocus_interval=refocus_interval,
                arguments=(focus_count, focus_step, focus_exposure_time),
                retry_interval=focus_retry_interval,
                fields=fields,
                attempts=focus_attempts,
            )
        )
        if not early_start >= 0:
            raise ConfigError(f"must be >= 0 seconds, got {early_start}", key="early_start")
        self._keep_open = timedelta(seconds=keep_open)
        self._early = EarlyStarts(site, timedelta(seconds=early_start), keep_open=self._keep_open)
        self._schedule = ScheduleReader(
            self,
            store,
            self._archive,
            horizon=self._keep_open + max(self._keep_open, self._early.early_start) + timedelta(hours=1),
            max_sun_altitude=max_sun_altitude,
            twilight_max_sun_altitude=twilight_max_sun_altitude,
        )
        self._rapid = AnnouncedTasks(
            self._archive,
            RapidResponse(
                site, max_sun_altitude=max_sun_altitude, twilight_max_sun_altitude=twilight_max_sun_altitude
            ),
        )
        self._withdrawals = Withdrawals(self._archive)
        self._recorder = TaskRecorder(self, self._archive)
        self._poll, self._abort_timeout = float(poll_interval), float(abort_timeout)
        self._running = autostart
        self._stop_cause: str | None = None  # why a running task must stop (operator)
        self._wake = asyncio.Event()
        self._task_runs = TaskRuns(
            self,
            self._runner,
            self._recorder,
            self._schedule,
            self._abort_cause,
            self._wake,
            poll_interval=self._poll,
            abort_timeout=self._abort_timeout,
            device_wait=device_wait,
            device_retries=device_retries,
        )
        self._safe_since_stop = False
        self._last_action: Action | None = None
        self._conditions: Conditions | None = None  # of the last look at the world
        self._unfit_logged: set[tuple[str, datetime]] = set()  # (task, slot start) said not to fit
        self.add_background_task(self._robotic_loop, name="robotic loop")

    # --- life cycle and events -----------------------------------------------------------------

    @property
    def task_archive(self) -> TaskArchive:
        """Where the tasks come from and their fate goes."""
        return self._archive

    async def open(self) -> None:
        await self._archive_option.open()
        await super().open()
        await self._task_runs.open()
        await self.comm.register_event(BadWeatherEvent, self.on_bad_weather)
        await self.comm.register_event(GoodWeatherEvent, self.on_good_weather)
        await self.comm.register_event(RoofClosingEvent, self.on_roof_closing)
        await self.comm.register_event(ScheduleChangedEvent, self.on_schedule_changed)
        await self.comm.register_event(RapidResponseEvent, self.on_rapid_response)
        await self.comm.register_event(TasksChangedEvent, self.on_tasks_changed)

    async def close(self) -> None:
        await super().close()
        await self._archive_option.close()

    async def on_bad_weather(self, event: BadWeatherEvent, sender: str) -> None:
        log.warning("%s: bad weather (%s)", self.name, event.reason or "no reason given")
        self._observatory.heard_bad_weather()
        self._wake.set()

    async def on_good_weather(self, event: GoodWeatherEvent, sender: str) -> None:
        log.info("%s: good weather%s", self.name, f" from {event.eta:%H:%M:%S}" if event.eta else "")
        self._observatory.heard_good_weather(event.eta)
        self._wake.set()

    async def on_roof_closing(self, event: RoofClosingEvent, sender: str) -> None:
        self._wake.set()

    async def on_schedule_changed(self, event: ScheduleChangedEvent, sender: str) -> None:
        self._wake.set()

    async def on_rapid_response(self, event: RapidResponseEvent, sender: str) -> None:
        log.info(
            "%s: rapid-response task%s %s from %s",
            self.name,
            "s"[: len(event.ids) > 1],
            ", ".join(event.ids),
            sender,
        )
        self._rapid.rapid.announce(event.ids)
        self._wake.set()

    async def on_tasks_changed(self, event: TasksChangedEvent, sender: str) -> None:
        if event.change == "cancelled" and await self._withdrawals.heard(event.ids, self._recorder.current):
            self._wake.set()  # the running task was cancelled: stopped at once

    # --- IStartStop, IAutonomous, IFitsHeaderBefore --------------------------------------------

    async def start(self) -> None:
        if not self._running:
            log.info("%s: robotic mode started", self.name)
        self._running, self._stop_cause, self._safe_since_stop = True, None, False
        self._wake.set()

    async def stop(self) -> None:
        if self._running:
            log.info("%s: robotic mode stopped", self.name)
            self._running, self._stop_cause = False, "robotic mode being stopped"
            self._wake.set()

    async def is_running(self) -> bool:
        return self._running

    async def is_autonomous(self) -> bool:
        return self._running

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        task = self._recorder.current
        return task_cards(task, self._recorder.progress) if task is not None else {}

    async def get_robotic_status(self) -> RoboticStatus:
        started, eta = self._task_runs.times or (None, None)
        return robotic_status(
            self.clock.now(),
            running=self._running,
            safe=self._safe_since_stop,
            action=self._last_action,
            conditions=self._conditions,
            task=self._recorder.current,
            progress=self._recorder.progress,
            task_started=started,
            task_eta=eta,
        )

    # --- the loop ------------------------------------------------------------------------------

    async def _robotic_loop(self) -> None:
        recovered = False
        while True:
            pause = self._poll
            try:
                if not recovered:
                    await self._schedule.recover_orphans(self.clock.now())
                    recovered = True
                if self._running:
                    pause = await self._step()
                elif not self._safe_since_stop:
                    self._safe_since_stop = await self._observatory.close_and_park("robotic mode was stopped")
            except Exception as exc:  # the traceback is logged by the restart below
                log.error("%s: error in the robotic loop (%s); closing the roof and parking", self.name, exc)
                await self._observatory.close_and_park("an error in the robotic loop")
                raise  # restarted with backoff by add_background_task
            await self._sleep(pause)

    async def _step(self) -> float:
        """Decide and act once; returns the clock seconds to wait before the next step."""
        conditions = self._conditions = await self._observatory.observe()
        slots, tasks = await self._schedule.read(conditions.now)
        rapid = await self._rapid.to_run(None, conditions.now)
        if rapid is not None:
            tasks[rapid.id] = rapid
            slots = ahead_of_plan(self._rapid.rapid.slot_now(rapid, conditions.now), slots, conditions.now)
        keeper = self._focus_keeper
        focus_below = await keeper.focus_below() if keeper is not None else None
        slots = without_refocus(slots, tasks, focused=keeper is not None and keeper.focused)
        while True:  # ends: each round takes one slot out
            # Marked again after a slot is taken out: with a due task that may not start, the
            # next one may start early at once, not only once a new plan leaves the first out.
            slots = self._early.mark(slots, tasks, conditions.now)
            action = decide(
                conditions,
                slots,
                keep_open=self._keep_open,
                focus_below=focus_below,
                early_start=self._early.early_start,
            )
            unfit = self._unfit_slot(action, tasks, conditions.now)
            if unfit is None:
                break
            # Not now (asked again at the next step, no failure): decide as if it were not there.
            slots = [replace(s, may_run=False) if s == unfit else s for s in slots]
        if action != self._last_action:
            log.info("%s: %s", self.name, action.describe())
            self._last_action = action
        if isinstance(action, RunTask):
            self._rapid.rapid.started(action.slot.task_id)
            await self._task_runs.run(action.slot, tasks[action.slot.task_id])
            return 0.0
        if isinstance(action, Focus):
            await self._focus(action.slot)
            return 0.0
        if isinstance(action, OpenUp):
            point_at = await self._first_pointing(
                action.slot, tasks[action.slot.task_id], conditions, focus_below
            )
            return 1.0 if await self._observatory.open_up(conditions, point_at) else self._poll
        if isinstance(action, CloseAndPark):
            await self._observatory.close_and_park(action.reason)
            return self._poll
        if action.until is not None:
            return max(0.0, min(self._poll, (action.until - conditions.now).total_seconds()))
        return self._poll

    def _unfit_slot(self, action: Action, tasks: dict[str, Task], now: datetime) -> Slot | None:
        """The slot of ``action`` if it starts a sky task that would outlast its constraints.

        Only a task about to start (due or early), with what it has left (its recorded progress):
        started anyway it would be aborted (Sun, airmass, window end) with frames missing. BIAS and
        DARK are never aborted by the sky; closing, waiting and a focus for a later task are
        never held back.
        """
        if not isinstance(action, RunTask | OpenUp | Focus):
            return None
        slot = action.slot
        if not slot.needs_sky or not (slot.is_due(now) or slot.startable_now):
            return None
        task = tasks[slot.task_id]
        left = time_left(task)
        if within_constraints(task.request, self._sky_site, now, left, max_sun_altitude=slot.sun.high):
            return None
        if (task.id, slot.start) not in self._unfit_logged:
            self._unfit_logged.add((task.id, slot.start))
            log.warning(
                "%s: not starting task %s (%s) now: with %.0f s left it would end at %s, after its "
                "window or its constraints (Sun %s, airmass, Moon) end",
                self.name,
                task.id,
                task.name,
                left.total_seconds(),
                f"{now + left:%H:%M:%S}",
                slot.sun.describe(),
            )
        return slot

    async def _first_pointing(
        self, slot: Slot, task: Task, conditions: Conditions, focus_below: float | None
    ) -> tuple[float, float] | None:
        """Where the telescope points first after opening up for ``slot``: the focus field if the
        focus comes first, else the task's first target (None: a task without one, e.g. flats)."""
        keeper = self._focus_keeper
        if keeper is not None and focus_now(slot, conditions, focus_below):
            return await keeper.first_field()
        target = task.request.configurations[0].target if task.request.configurations else None
        return None if target is None else target_radec(target, self.site, self.clock.time())

    async def _sleep(self, seconds: float) -> None:
        """Wait ``seconds`` of clock time or until woken by an event."""
        if seconds > 0:
            with contextlib.suppress(TimeoutError):
                async with self.clock.timeout(seconds):
                    await self._wake.wait()
        self._wake.clear()

    # --- running a task ------------------------------------------------------------------------

    async def _abort_cause(self, slot: Slot) -> str | None:
        running = self._recorder.current
        cause = self._stop_cause or self._withdrawals.cause(running)
        cause = cause or abort_cause(await self._observatory.observe(), slot)
        if cause is None and running is not None:  # a focus run is not pre-empted: it is short
            rapid = await self._rapid.to_run(running, self.clock.now())
            cause = None if rapid is None else preemption_cause(rapid)
        return cause

    async def _focus(self, slot: Slot) -> None:
        """Focus (for the task of ``slot``); stopped by weather, roof or the Sun above the limit."""
        assert self._focus_keeper is not None  # decide() focuses only when focus_below is given
        watched = replace(slot, sun=self._focus_keeper.limits)
        await self._focus_keeper.focus(
            lambda: self._abort_cause(watched),
            wake=self._wake,
            poll_interval=self._poll,
            abort_timeout=self._abort_timeout,
        )
