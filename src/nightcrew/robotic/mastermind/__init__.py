"""The mastermind's decisions as pure functions: what to do next, when to stop a task, what to record.

:func:`decide` takes the world (:class:`Conditions`) and the slots of the schedule around now and
returns one :data:`Action` (:class:`RunTask`, :class:`OpenUp`, :class:`CloseAndPark`,
:class:`Wait`); :func:`abort_cause` says why a running task must stop. The helpers in
:mod:`._tasks` read what deciding needs from a task. The module
:class:`nightcrew.modules.robotic.Mastermind` only observes, calls these and acts.
"""

from __future__ import annotations

from nightcrew.robotic.mastermind._decide import (
    Action,
    CloseAndPark,
    Conditions,
    OpenUp,
    RoofState,
    RunTask,
    Slot,
    SunLimits,
    Wait,
    abort_cause,
    decide,
)
from nightcrew.robotic.mastermind._tasks import (
    focus_due,
    interruption_reason,
    needs_sky,
    planned_exposures,
    slot_for,
    sun_limits,
    task_cards,
)

__all__ = [
    "Action",
    "CloseAndPark",
    "Conditions",
    "OpenUp",
    "RoofState",
    "RunTask",
    "Slot",
    "SunLimits",
    "Wait",
    "abort_cause",
    "decide",
    "focus_due",
    "interruption_reason",
    "needs_sky",
    "planned_exposures",
    "slot_for",
    "sun_limits",
    "task_cards",
]
