"""The mastermind's decisions as pure functions: what to do next, when to stop a task, what to record.

:func:`decide` takes the world (:class:`Conditions`) and the slots of the schedule around now and
returns one :data:`Action` (:class:`RunTask`, :class:`OpenUp`, :class:`Focus`,
:class:`CloseAndPark`, :class:`Wait`); :func:`abort_cause` says why a running task must stop. The
helpers in :mod:`._tasks` read what deciding needs from a task; :func:`run_watched` runs a task (or
a focus run) and cancels it as soon as a check finds a cause; :class:`ObservatoryControl` senses
the weather, roof, telescope and Sun through proxies and opens up or closes down;
:class:`FocusKeeper` knows when a focus is due and runs it on a tracked star field chosen by
:class:`FocusFields`; :class:`ScheduleReader` reads the slots around now, :class:`EarlyStarts`
marks the next one that may start early, and :class:`TaskRecorder` records a task's start, progress
and end in the archive and on the bus; :func:`device_fault` tells a device's failure under a task
from the task's own; :class:`RapidResponse` picks an announced rapid-response task that
pre-empts the running one. The module :class:`nightcrew.modules.robotic.Mastermind` only observes, calls
these and acts.
"""

from __future__ import annotations

from nightcrew.robotic.mastermind._decide import (
    Action,
    CloseAndPark,
    Conditions,
    Focus,
    OpenUp,
    RoofState,
    RunTask,
    Slot,
    SunLimits,
    Wait,
    abort_cause,
    decide,
    focus_now,
)
from nightcrew.robotic.mastermind._early_start import EarlyStarts
from nightcrew.robotic.mastermind._faults import DeviceFault, device_fault, resumed
from nightcrew.robotic.mastermind._focusing import FocusKeeper
from nightcrew.robotic.mastermind._observatory import ObservatoryControl
from nightcrew.robotic.mastermind._preemption import (
    RapidResponse,
    ahead_of_plan,
    preempting_task,
    preemption_cause,
    without_refocus,
)
from nightcrew.robotic.mastermind._recording import TaskRecorder
from nightcrew.robotic.mastermind._schedule import ScheduleReader
from nightcrew.robotic.mastermind._status import robotic_status
from nightcrew.robotic.mastermind._supervision import AbortCheck, all_done, run_watched
from nightcrew.robotic.mastermind._tasks import (
    focus_due,
    interruption_reason,
    kept_progress,
    needs_focus,
    needs_sky,
    observable_since,
    planned_exposures,
    slot_for,
    startable_from,
    startable_now,
    sun_limits,
    task_cards,
    time_left,
    window_begun,
    within_constraints,
)
from nightcrew.robotic.scripts.focus_fields import FocusFieldError, FocusFields, catalogue_stars

__all__ = [
    "AbortCheck",
    "Action",
    "CloseAndPark",
    "Conditions",
    "DeviceFault",
    "EarlyStarts",
    "Focus",
    "FocusFieldError",
    "FocusFields",
    "FocusKeeper",
    "ObservatoryControl",
    "OpenUp",
    "RapidResponse",
    "RoofState",
    "RunTask",
    "ScheduleReader",
    "Slot",
    "SunLimits",
    "TaskRecorder",
    "Wait",
    "abort_cause",
    "ahead_of_plan",
    "all_done",
    "catalogue_stars",
    "decide",
    "device_fault",
    "focus_due",
    "focus_now",
    "interruption_reason",
    "kept_progress",
    "needs_focus",
    "needs_sky",
    "observable_since",
    "planned_exposures",
    "preempting_task",
    "preemption_cause",
    "resumed",
    "robotic_status",
    "run_watched",
    "slot_for",
    "startable_from",
    "startable_now",
    "sun_limits",
    "task_cards",
    "time_left",
    "window_begun",
    "within_constraints",
    "without_refocus",
]
