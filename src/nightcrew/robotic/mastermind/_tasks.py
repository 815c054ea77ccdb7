"""What the mastermind reads from a task: sky or not, Sun limits, exposures, FITS cards, reasons."""

from __future__ import annotations

import math
from datetime import datetime, timedelta

from nightcrew.focus.refocus import FocusState, RefocusTriggers, refocus_cause
from nightcrew.interfaces import FitsCard
from nightcrew.robotic.mastermind._decide import Slot, SunLimits
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import ConfigurationType, Request, Task, TaskProgress, estimate_duration
from nightcrew.robotic.tasks.visibility import observable_stretches
from nightcrew.site import Site

__all__ = [
    "focus_due",
    "interruption_reason",
    "kept_progress",
    "needs_focus",
    "needs_sky",
    "observable_since",
    "planned_exposures",
    "slot_for",
    "startable_from",
    "startable_now",
    "sun_limits",
    "task_cards",
    "time_left",
    "window_begun",
    "within_constraints",
]

#: Configuration types that work with the roof closed.
_CLOSED_ROOF_TYPES = frozenset({ConfigurationType.BIAS, ConfigurationType.DARK, ConfigurationType.PANEL_FLAT})
#: Configuration types that do not need sharp stars.
_UNFOCUSED_TYPES = _CLOSED_ROOF_TYPES | {ConfigurationType.SKY_FLAT}


def needs_sky(task: Task) -> bool:
    """Whether the task needs the roof open: any configuration but BIAS, DARK and PANEL_FLAT (SCRIPT too)."""
    return any(c.type not in _CLOSED_ROOF_TYPES for c in task.request.configurations)


def needs_focus(task: Task) -> bool:
    """Whether the task images stars (anything but BIAS, DARK and SKY_FLAT): focus before it."""
    return any(c.type not in _UNFOCUSED_TYPES for c in task.request.configurations)


def sun_limits(task: Task, *, max_sun_altitude: float, twilight_max_sun_altitude: float) -> SunLimits:
    """The strictest Sun limits of the task's configurations, capped by the observatory.

    Twilight tasks (with a SKY_FLAT configuration) are capped at ``twilight_max_sun_altitude``, all
    others at ``max_sun_altitude``: a task may ask for a darker sky, never for a brighter one.
    """
    configurations = task.request.configurations
    high = min(c.constraints.max_sun_altitude for c in configurations)
    lows = [
        c.constraints.min_sun_altitude for c in configurations if c.constraints.min_sun_altitude is not None
    ]
    twilight = any(c.type is ConfigurationType.SKY_FLAT for c in configurations)
    cap = twilight_max_sun_altitude if twilight else max_sun_altitude
    return SunLimits(high=min(high, cap), low=max(lows) if lows else None)


def slot_for(
    planned: PlannedSlot,
    task: Task,
    *,
    max_sun_altitude: float,
    twilight_max_sun_altitude: float,
    failed_here: bool = False,
) -> Slot:
    """The :class:`Slot` of a planned slot; ``failed_here``: the task failed by its own fault in it."""
    return Slot(
        planned=planned,
        name=task.name,
        needs_sky=needs_sky(task),
        sun=sun_limits(
            task, max_sun_altitude=max_sun_altitude, twilight_max_sun_altitude=twilight_max_sun_altitude
        ),
        may_run=task.schedulable and not failed_here,
        needs_focus=needs_focus(task),
    )


def startable_now(task: Task, site: Site, now: datetime, start: datetime) -> bool:
    """Whether ``task``, planned to start at ``start``, may start at ``now`` already.

    Its window must have begun (:func:`window_begun`) and its request be observable from ``now``
    until ``start`` (:func:`observable_since`): from there on the scheduler found it observable.
    """
    since = startable_from(task.request, site, start, lookback=start - now)
    return since is not None and since <= now


def startable_from(request: Request, site: Site, start: datetime, *, lookback: timedelta) -> datetime | None:
    """The first time, at most ``lookback`` before ``start``, from which ``request`` may start early.

    From then on until ``start`` one of its windows has begun (:func:`window_begun`) and it is
    observable (:func:`observable_since`); None when it may not start before ``start``.
    """
    opened = [w.start for w in request.windows if w.start <= start <= w.end]
    since = observable_since(request, site, start, lookback=lookback) if opened else None
    return None if since is None else max(since, min(opened), start - lookback)


def time_left(task: Task) -> timedelta:
    """How long ``task`` takes from its recorded progress on (the default overheads, set-up included)."""
    return timedelta(seconds=estimate_duration(task.request, progress=task.status.progress).total_s)


def within_constraints(
    request: Request, site: Site, now: datetime, duration: timedelta, *, max_sun_altitude: float = 90.0
) -> bool:
    """Whether ``request``, started at ``now`` and taking ``duration``, ends before its constraints fail.

    One of its windows must hold ``now`` and its end (:func:`window_begun`), and it must be
    observable all along (:func:`observable_since`, each minute from ``now``), with the Sun also at
    most ``max_sun_altitude`` (the observatory's cap, :func:`sun_limits`): the check of an early
    start, so a task is not started only to be aborted at dawn or its window end.
    """
    if not window_begun(request, now, now + duration):
        return False
    # Whole minutes from now on: a grid counted back from the end would start up to a minute
    # before now and refuse a task at dusk for a Sun still too high in that minute.
    minutes = timedelta(minutes=math.ceil(duration / timedelta(minutes=1) - 1e-9))
    since = observable_since(_sun_capped(request, max_sun_altitude), site, now + minutes, lookback=minutes)
    return since is not None and since <= now


def window_begun(request: Request, now: datetime, start: datetime) -> bool:
    """Whether one of the request's windows holds both ``now`` and ``start``."""
    return any(w.start <= now and start <= w.end for w in request.windows)


def observable_since(
    request: Request, site: Site, start: datetime, *, lookback: timedelta
) -> datetime | None:
    """Since when, at most ``lookback`` before ``start``, ``request`` is observable until ``start``.

    Sun, airmass and Moon are checked each minute as the scheduler checks them, on minutes counted
    back from ``start``; None when it is not observable right before ``start``. Its windows are not
    looked at (:func:`window_begun`).
    """
    minute = timedelta(minutes=1)
    begin = start - minute * math.ceil(lookback / minute - 1e-9)
    stretches = observable_stretches(request, site, begin, start + minute, step=minute.total_seconds())
    return next((a for a, b in stretches if a <= start <= b), None)


def _sun_capped(request: Request, high: float) -> Request:
    """``request`` with no configuration allowing the Sun above ``high``."""
    configurations = tuple(
        c.model_copy(update={"constraints": c.constraints.model_copy(update={"max_sun_altitude": high})})
        if c.constraints.max_sun_altitude > high
        else c
        for c in request.configurations
    )
    return request.model_copy(update={"configurations": configurations})


def planned_exposures(request: Request) -> int:
    """Exposures the request asks for (one cycle of a REPEAT_EXPOSE)."""
    return sum(ic.exposure_count for c in request.configurations for ic in c.instrument_configs)


def interruption_reason(cause: str, task: Task, progress: TaskProgress) -> str:
    """``interrupted by bad weather: 3 of 10 exposures done`` - the FAILED reason of an aborted task.

    Frames cut short and kept follow: ``..., 1 cut short after 143 of 300 s (kept)``.
    """
    reason = (
        f"interrupted by {cause}: {progress.total_exposures} of "
        f"{planned_exposures(task.request)} exposures done"
    )
    if not progress.cut_short:
        return reason
    configurations = task.request.configurations
    parts = [
        f"{_seconds(f.exposed)} of "
        f"{_seconds(configurations[f.configuration].instrument_configs[f.instrument_config].exposure_time)} s"
        for f in progress.cut_short
    ]
    listed = parts[0] if len(parts) == 1 else f"{', '.join(parts[:-1])} and {parts[-1]}"
    return f"{reason}, {len(parts)} cut short after {listed} (kept)"


def _seconds(value: float) -> str:
    """Whole seconds, or tenths below 10 s (a 0.4-s frame is not "0 s")."""
    return f"{value:.0f}" if value >= 9.95 else f"{value:.1f}".removesuffix(".0")


def task_cards(task: Task, progress: TaskProgress | None = None) -> dict[str, FitsCard]:
    """The FITS cards naming the task an image belongs to, and its target (OBJECT).

    OBJECT names the target of the configuration being taken: the first one ``progress`` does not
    have all exposures of (a task without progress: the first); a configuration without a target
    (flats, darks) names its type, e.g. ``SKY_FLAT``.
    """
    cards: dict[str, FitsCard] = {
        "TASK-ID": (task.id, "Task archive id"),
        "TASK-NAM": (task.name, "Task (request group) name"),
        "TASK-GRP": (task.group_id, "Request group id"),
        "TASK-REQ": (task.request_index, "Request index in its group"),
        "PROPOSAL": (task.proposal, "Proposal"),
        "TASK-PRI": (task.effective_priority, "Task priority x IPP"),
    }
    configurations = task.request.configurations
    if configurations:
        done = progress.exposures_done if progress is not None else ()

        def unfinished(index: int) -> bool:
            if index >= len(done):
                return True
            counts = zip(done[index], configurations[index].instrument_configs, strict=False)
            return any(n < ic.exposure_count for n, ic in counts)

        running = next((c for index, c in enumerate(configurations) if unfinished(index)), configurations[-1])
        name = running.target.name if running.target is not None else running.type.value
        cards["OBJECT"] = (name, "Target name")
    return cards


def kept_progress(recorded: TaskProgress, this_run: TaskProgress) -> TaskProgress:
    """What to record: per instrument config the larger of the archived count and this run's.

    A retry starts from the recorded progress (scripts take only the missing exposures), so this
    run's counts include the earlier ones; the maximum keeps the record from ever shrinking, also
    when a run reports before it has caught up with the archive (e.g. a fresh runner's zero).
    Frames cut short: the longer of the two lists.
    """
    if not recorded.exposures_done:
        return this_run
    if not this_run.exposures_done:
        return recorded
    rows = zip(recorded.exposures_done, this_run.exposures_done, strict=True)
    # Cut-short frames are only ever appended, to the record a run started from: the longer list.
    cut_short = max(recorded.cut_short, this_run.cut_short, key=len)
    return TaskProgress(exposures_done=tuple(tuple(map(max, a, b)) for a, b in rows), cut_short=cut_short)


def focus_due(
    *,
    focused: bool,
    last_temperature: float | None,
    temperature: float | None,
    threshold: float,
    since_focus: float = 0.0,
    interval: float | None = None,
) -> str | None:
    """Why to focus before the next sky task, or None.

    Always when there was no focus yet; then when both temperatures are known and differ by more
    than ``threshold`` (°C: the tube's length follows the temperature), or when more than
    ``interval`` seconds passed since the focus (``since_focus`` of them have; None: never).
    """
    if not focused:
        return "no focus yet"
    triggers = RefocusTriggers(temperature_change=threshold, interval=interval)
    last = FocusState(time=0.0, temperature=last_temperature)
    return refocus_cause(triggers, last, time=since_focus, temperature=temperature)
