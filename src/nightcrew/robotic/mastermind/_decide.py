"""What the mastermind does next, decided from plain values: :func:`decide` and :func:`abort_cause`.

Between tasks the mastermind looks at the world (:class:`Conditions`) and the schedule around now
(:class:`Slot` values: the planned slots with what their tasks need) and takes one
:data:`Action`; while a task runs it asks :func:`abort_cause` whether the task must stop. The rules, in order:

1. **Bad (or unknown) weather** and anything open or unparked: :class:`CloseAndPark`.
2. A slot is **due** (``start <= now < end``, its task may run; of overlapping ones the earliest
   that can run now): a task that needs no sky (BIAS,
   DARK) runs at once; a sky task needs good weather and the Sun within its limits, then the roof
   open and the telescope ready (:class:`OpenUp` first), then :class:`RunTask` - or first
   :class:`Focus` when the focus is due (``focus_below``), the task needs a sharp image and the
   Sun is low enough. A roof moving by someone else's hand is waited for.
3. Nothing due, and the next slot starts within ``early_start`` and its task can be observed from
   now on (``startable_now``): it is taken as due (rule 2), so a task that ended early leaves no
   idle gap.
4. Otherwise, with the roof open or the telescope unparked: it **stays open** only if it will be
   used again within ``keep_open``: a sky task is due or may start within ``keep_open`` - at its
   slot, or the next one early, when it becomes startable (``early_from``, rule 3) - and the Sun
   allows it now (or is setting towards its limit), or - the focus due and the Sun low enough for
   it or setting - a task that needs the focus starts within twice ``keep_open`` (rule 5 opens up
   for that focus ``keep_open`` before the task: closing now would mean opening again within
   ``keep_open``). Else :class:`CloseAndPark` (dawn, end of the schedule, a long gap). Bad weather
   never waits (rule 1).
5. Nothing due, the focus due, the Sun low enough and a task that needs it within ``keep_open``:
   :class:`Focus` now (opening up first), so the wait before it (at dusk: between the twilight
   tasks and full darkness) is not lost to focusing later.
6. Otherwise :class:`Wait`.

A running sky task is aborted on bad weather, a roof that is not open, or the Sun leaving its
limits (dawn); a task that needs no sky is never aborted by these.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime, timedelta
from enum import StrEnum

from nightcrew.interfaces import MotionStatus
from nightcrew.robotic.planning import PlannedSlot

__all__ = [
    "Action",
    "CloseAndPark",
    "Conditions",
    "Focus",
    "OpenUp",
    "RoofState",
    "RunTask",
    "Slot",
    "SunLimits",
    "Wait",
    "abort_cause",
    "decide",
    "focus_now",
]


class RoofState(StrEnum):
    """The roof as the mastermind sees it; anything it cannot tell is UNKNOWN (treated as not open)."""

    OPEN = "open"
    CLOSED = "closed"
    OPENING = "opening"
    CLOSING = "closing"
    UNKNOWN = "unknown"

    @classmethod
    def of_motion(cls, status: MotionStatus) -> RoofState:
        """The roof state shown by a roof's motion status (IDLE is open, PARKED closed)."""
        return _ROOF_BY_MOTION.get(status, cls.UNKNOWN)


_ROOF_BY_MOTION = {
    MotionStatus.IDLE: RoofState.OPEN,
    MotionStatus.PARKED: RoofState.CLOSED,
    MotionStatus.MOVING: RoofState.OPENING,
    MotionStatus.INITIALIZING: RoofState.OPENING,
    MotionStatus.PARKING: RoofState.CLOSING,
}


@dataclass(frozen=True)
class SunLimits:
    """The Sun's altitude must be within ``[low, high]`` degrees (``low`` None: no lower limit)."""

    high: float
    low: float | None = None

    def allows(self, altitude: float) -> bool:
        """Whether a task with these limits may run with the Sun at ``altitude``."""
        return altitude <= self.high and (self.low is None or altitude >= self.low)

    def describe(self) -> str:
        """For people: ``≤ -12°`` or ``-10° .. -3°``."""
        return f"≤ {self.high:g}°" if self.low is None else f"{self.low:g}° .. {self.high:g}°"


@dataclass(frozen=True)
class Conditions:
    """The world at ``now``.

    Args:
        now: Clock time (aware).
        sun_altitude: Degrees.
        sun_rising: Whether the Sun's altitude is increasing (morning).
        weather_good: The weather allows opening; False when unknown.
        roof: The roof's state.
        telescope_ready: Initialised and able to point (not parked, not in error).
    """

    now: datetime
    sun_altitude: float
    sun_rising: bool
    weather_good: bool
    roof: RoofState
    telescope_ready: bool

    @property
    def closed_and_parked(self) -> bool:
        """The safe state: roof closed and telescope not ready to point (parked)."""
        return self.roof is RoofState.CLOSED and not self.telescope_ready


@dataclass(frozen=True)
class Slot:
    """A planned slot with what deciding needs from its task.

    Args:
        planned: The slot as the scheduler planned it: its task begins at ``start`` and is not
            started at or after ``end``.
        name: The task's name (for logs).
        needs_sky: It needs the roof open (anything but BIAS, DARK and PANEL_FLAT).
        sun: Where the Sun must be (the observatory's cap applied).
        may_run: False when the task is no longer to do (done, cancelled) or already failed by its
            own fault in this very slot (so a broken task is not retried in a loop).
        needs_focus: It images the sky and wants sharp stars (sky tasks but twilight flats).
        startable_now: Its task can be observed from now until ``start`` (window begun, target
            within its limits), so it may start early.
        early_from: When it becomes startable before ``start`` (from then on ``startable_now``),
            None: not before ``start``; the roof is kept open for it from then on (rule 4).
    """

    planned: PlannedSlot
    name: str
    needs_sky: bool
    sun: SunLimits
    may_run: bool = True
    needs_focus: bool = False
    startable_now: bool = False
    early_from: datetime | None = None

    @property
    def task_id(self) -> str:
        """The archive's task id."""
        return self.planned.task_id

    @property
    def start(self) -> datetime:
        """When the plan wants the task to begin."""
        return self.planned.start

    @property
    def end(self) -> datetime:
        """When its slot ends."""
        return self.planned.end

    def is_due(self, now: datetime) -> bool:
        """Its slot has begun and not ended."""
        return self.start <= now < self.end


@dataclass(frozen=True)
class RunTask:
    """Run the task of ``slot`` now."""

    slot: Slot

    def describe(self) -> str:
        return f"running task {self.slot.task_id} ({self.slot.name})"


@dataclass(frozen=True)
class OpenUp:
    """Open the roof and initialise the telescope for the sky task of ``slot``."""

    slot: Slot

    def describe(self) -> str:
        return f"opening up for task {self.slot.task_id} ({self.slot.name})"


@dataclass(frozen=True)
class Focus:
    """Focus the telescope now, for the task of ``slot`` (due or next)."""

    slot: Slot

    def describe(self) -> str:
        return f"focusing for task {self.slot.task_id} ({self.slot.name})"


@dataclass(frozen=True)
class CloseAndPark:
    """Close the roof and park the telescope, because of ``reason``."""

    reason: str

    def describe(self) -> str:
        return f"closing and parking: {self.reason}"


@dataclass(frozen=True)
class Wait:
    """Nothing to do before ``until`` (None: until something changes), because of ``reason``."""

    reason: str
    until: datetime | None = None

    def describe(self) -> str:
        return f"waiting: {self.reason}"


Action = RunTask | OpenUp | Focus | CloseAndPark | Wait


def decide(
    conditions: Conditions,
    slots: Sequence[Slot],
    *,
    keep_open: timedelta,
    focus_below: float | None = None,
    early_start: timedelta = timedelta(0),
) -> Action:
    """The next action; see the module docstring for the rules.

    ``focus_below``: the focus is due, at a Sun altitude up to this (degrees); None: not due.
    ``early_start``: how long before its slot a task that can be observed already may start.
    """
    if not conditions.weather_good and not conditions.closed_and_parked:
        return CloseAndPark("the weather is bad")
    now = conditions.now
    runnable = sorted((slot for slot in slots if slot.may_run and slot.end > now), key=lambda s: s.start)
    blocked: list[tuple[Slot, str]] = []
    due_now = [slot for slot in runnable if slot.is_due(now)]
    for due in due_now:  # overlapping slots: earliest first
        if not due.needs_sky:
            return RunTask(due)
        blocker = _sky_blocker(due, conditions)
        if not blocker:
            return _prepared_or_run(due, conditions, focus_below)
        blocked.append((due, blocker))
    upcoming = next((slot for slot in runnable if slot.start > now), None)
    if not due_now and upcoming and upcoming.startable_now and upcoming.start <= now + early_start:
        if not upcoming.needs_sky:
            return RunTask(upcoming)
        if not _sky_blocker(upcoming, conditions):
            return _prepared_or_run(upcoming, conditions, focus_below)
    if not conditions.closed_and_parked and not _keep_open(runnable, conditions, keep_open, focus_below):
        return CloseAndPark(_closing_reason(runnable, conditions, keep_open))
    if blocked:
        return Wait(f"{blocked[0][0].name}: {blocked[0][1]}")
    if upcoming is None:
        return Wait("nothing scheduled")
    sharp = next((slot for slot in runnable if slot.start > now and slot.needs_focus), None)
    soon = sharp is not None and sharp.start <= now + keep_open
    if sharp and soon and conditions.weather_good and focus_now(sharp, conditions, focus_below):
        return _prepared_or_run(sharp, conditions, focus_below)  # opens up, then focuses
    return Wait(f"next: {upcoming.name} at {upcoming.start:%H:%M:%S}", until=upcoming.start)


def abort_cause(conditions: Conditions, slot: Slot) -> str | None:
    """Why the running task of ``slot`` must stop now, or None if it may go on."""
    if not slot.needs_sky:
        return None
    if not conditions.weather_good:
        return "bad weather"
    if conditions.roof is not RoofState.OPEN:
        return f"the roof ({conditions.roof})"
    if not slot.sun.allows(conditions.sun_altitude):
        return f"the Sun at {conditions.sun_altitude:.2f}° (the task needs {slot.sun.describe()})"
    return None


def _sky_blocker(slot: Slot, conditions: Conditions) -> str:
    """Why the sky task of ``slot`` cannot start now ("" if it can)."""
    if not conditions.weather_good:
        return "waiting for good weather"
    if not slot.sun.allows(conditions.sun_altitude):
        return f"the Sun is at {conditions.sun_altitude:.1f}°, the task needs {slot.sun.describe()}"
    return ""


def _prepared_or_run(slot: Slot, conditions: Conditions, focus_below: float | None) -> Action:
    if _ready(conditions):
        return Focus(slot) if focus_now(slot, conditions, focus_below) else RunTask(slot)
    if conditions.roof in (RoofState.OPENING, RoofState.CLOSING):
        # Someone else moves it (a closing roof refuses to open): look again when it stopped.
        return Wait(f"the roof is {conditions.roof}")
    return OpenUp(slot)


def _ready(conditions: Conditions) -> bool:
    """Weather good, roof open and telescope ready: the sky can be imaged."""
    return conditions.weather_good and conditions.roof is RoofState.OPEN and conditions.telescope_ready


def focus_now(slot: Slot, conditions: Conditions, focus_below: float | None) -> bool:
    """Whether the task of ``slot`` is focused for first (the focus is due and stars show)."""
    # Focus stars need a dark enough sky; a task run without a due focus beats not running it.
    return slot.needs_focus and focus_below is not None and conditions.sun_altitude <= focus_below


def _keep_open(
    runnable: Sequence[Slot], conditions: Conditions, keep_open: timedelta, focus_below: float | None
) -> bool:
    """Whether the open roof will be used within ``keep_open``: by a sky task or the focus before one."""
    horizon = conditions.now + keep_open
    focus_soon = focus_below is not None and (
        conditions.sun_altitude <= focus_below or not conditions.sun_rising
    )
    for slot in runnable:
        if not slot.needs_sky or not _sun_fits_soon(slot.sun, conditions):
            continue
        # An early start (rule 3) opens up before the slot; the focus keep_open before it (rule 5).
        opens_at = slot.early_from or slot.start
        if focus_soon and slot.needs_focus:
            opens_at = min(opens_at, slot.start - keep_open)
        if opens_at <= horizon:
            return True
    return False


def _sun_fits_soon(limits: SunLimits, conditions: Conditions) -> bool:
    # At dusk a Sun still too high for a science task is coming down to it; at dawn it is not.
    altitude = conditions.sun_altitude
    return limits.allows(altitude) or (not conditions.sun_rising and altitude > limits.high)


def _closing_reason(runnable: Sequence[Slot], conditions: Conditions, keep_open: timedelta) -> str:
    sky = [slot for slot in runnable if slot.needs_sky]
    if conditions.sun_rising and not any(slot.sun.allows(conditions.sun_altitude) for slot in sky):
        return f"dawn: the Sun is at {conditions.sun_altitude:.1f}° and rising"
    if not sky:
        return "the end of the schedule"
    return f"no sky task within {keep_open.total_seconds() / 60:g} min"
