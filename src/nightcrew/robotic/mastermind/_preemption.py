"""Rapid response: which announced task pre-empts the running one, and the plan it runs in now.

A rapid-response task announced by a ``RapidResponseEvent`` (from an account the access policy
allows) is run at the next safe point: a running task of lower priority is stopped (its frame in
flight stopped and kept, as for bad weather; the task comes back later, FAILED with its progress),
and the rapid-response task runs in a slot made for it from now, ahead of the planned ones due now.
It must be a RAPID_RESPONSE task, still to do, and fit now (window, Sun, airmass, Moon for the time
it takes); otherwise it waits for the scheduler, which places it as early as it can.

A RAPID_RESPONSE task does not wait for a due refocus (:func:`without_refocus`): an afterglow fades
by the minute, and a focus a few degrees old blurs it far less than minutes lost. Only when there
has been no focus at all yet (the focuser where it was left) is the focus run first.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import replace
from datetime import datetime, timedelta

from nightcrew.robotic.mastermind._decide import Slot
from nightcrew.robotic.mastermind._tasks import slot_for, time_left, within_constraints
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import ObservationType, Task
from nightcrew.site import Site

__all__ = ["RapidResponse", "ahead_of_plan", "preempting_task", "preemption_cause", "without_refocus"]


def preempting_task(
    candidates: Iterable[Task], running: Task | None, fits_now: Callable[[Task], bool]
) -> Task | None:
    """The candidate to run now: the rapid-response task of highest priority that is still to do and
    fits now, if it outranks the ``running`` task (None: nothing runs); else None."""
    best = max(
        (
            task
            for task in candidates
            if task.observation_type is ObservationType.RAPID_RESPONSE and task.schedulable and fits_now(task)
        ),
        key=lambda task: task.effective_priority,
        default=None,
    )
    if best is None or running is None:
        return best
    if best.id == running.id or best.effective_priority <= running.effective_priority:
        return None
    return best


def preemption_cause(task: Task) -> str:
    """Why a running task was stopped for ``task`` (its reason reads "interrupted by <this>")."""
    return f"rapid-response task {task.id} ({task.name})"


class RapidResponse:
    """The rapid-response tasks announced to the mastermind, until each has been started once.

    Args:
        site: The observatory (for the constraints of a start now).
        max_sun_altitude, twilight_max_sun_altitude: The observatory's Sun caps (as the schedule's).
    """

    def __init__(self, site: Site, *, max_sun_altitude: float, twilight_max_sun_altitude: float) -> None:
        self._site = site
        self._max_sun, self._twilight_max_sun = max_sun_altitude, twilight_max_sun_altitude
        self._announced: dict[str, None] = {}  # task ids, in the order they came

    @property
    def announced(self) -> tuple[str, ...]:
        """Ids of the announced tasks not started yet."""
        return tuple(self._announced)

    def announce(self, ids: Iterable[str]) -> None:
        """Tasks ``ids`` were submitted as rapid response."""
        self._announced.update(dict.fromkeys(ids))

    def started(self, task_id: str) -> None:
        """Task ``task_id`` started: it pre-empts nothing any more (a retry waits for the plan)."""
        self._announced.pop(task_id, None)

    def forget(self, task_ids: Iterable[str]) -> None:
        """Tasks no longer to do (done, cancelled, expired, gone from the archive)."""
        for task_id in task_ids:
            self._announced.pop(task_id, None)

    def slot_now(self, task: Task, now: datetime) -> Slot:
        """A slot for ``task`` from ``now`` for the time it has left."""
        left = max(time_left(task), timedelta(minutes=1))
        return slot_for(
            PlannedSlot(task.id, now, now + left),
            task,
            max_sun_altitude=self._max_sun,
            twilight_max_sun_altitude=self._twilight_max_sun,
        )

    def fits_now(self, task: Task, now: datetime) -> bool:
        """Whether ``task`` started ``now`` ends inside its window and constraints."""
        sun = self.slot_now(task, now).sun
        return within_constraints(task.request, self._site, now, time_left(task), max_sun_altitude=sun.high)

    def choose(self, candidates: Iterable[Task], running: Task | None, now: datetime) -> Task | None:
        """The announced task to run now (see :func:`preempting_task`)."""
        return preempting_task(candidates, running, lambda task: self.fits_now(task, now))


def ahead_of_plan(rapid: Slot, slots: Sequence[Slot], now: datetime) -> list[Slot]:
    """``slots`` with ``rapid`` first and the slots due now left out (read again after it ran)."""
    return [rapid, *(slot for slot in slots if slot.task_id != rapid.task_id and not slot.is_due(now))]


def without_refocus(slots: Sequence[Slot], tasks: Mapping[str, Task], *, focused: bool) -> list[Slot]:
    """``slots`` with the RAPID_RESPONSE tasks' focus left out once there has been a focus
    (``focused``): they skip a due refocus; before the first focus they are focused for too."""
    if not focused:
        return list(slots)
    rapid = {key for key, task in tasks.items() if task.observation_type is ObservationType.RAPID_RESPONSE}
    return [replace(slot, needs_focus=False) if slot.task_id in rapid else slot for slot in slots]
