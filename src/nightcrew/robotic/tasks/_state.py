"""The life of a task: its states, the allowed changes between them, and what was done so far.

::

    PENDING ──> SCHEDULED ──> RUNNING ──> COMPLETED
       │  <────────┘  │          │
       │              │          ├──> FAILED (reason) ──> SCHEDULED / RUNNING / PENDING (retry)
       └──────────────┴──────────┴──> CANCELED (reason)          WINDOW_EXPIRED

A FAILED task may be tried again while a window is left (the scheduler sees it, like PENDING);
COMPLETED, CANCELED and WINDOW_EXPIRED are final. Every change goes through
:meth:`TaskStatus.transition`, which checks :data:`ALLOWED_TRANSITIONS`.
"""

from __future__ import annotations

from datetime import datetime
from enum import StrEnum
from typing import Annotated

from pydantic import Field, Strict

from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.tasks._base import Number, TaskModel, UtcDatetime
from nightcrew.robotic.tasks._configuration import ConfigurationType
from nightcrew.robotic.tasks._errors import InvalidTransitionError
from nightcrew.robotic.tasks._request import Request

__all__ = [
    "ALLOWED_TRANSITIONS",
    "FINAL_STATES",
    "SCHEDULABLE_STATES",
    "CutShortFrame",
    "TaskProgress",
    "TaskState",
    "TaskStatus",
]


class TaskState(StrEnum):
    """Where a task is in its life."""

    PENDING = "PENDING"  # waiting to be scheduled
    SCHEDULED = "SCHEDULED"  # in the current schedule
    RUNNING = "RUNNING"  # being observed
    COMPLETED = "COMPLETED"  # done
    FAILED = "FAILED"  # the last attempt failed (see the reason); may be tried again
    CANCELED = "CANCELED"  # withdrawn by a person
    WINDOW_EXPIRED = "WINDOW_EXPIRED"  # the last window ended before it was done


_S = TaskState
#: State -> the states it may change to.
ALLOWED_TRANSITIONS: dict[TaskState, frozenset[TaskState]] = {
    _S.PENDING: frozenset({_S.SCHEDULED, _S.RUNNING, _S.CANCELED, _S.WINDOW_EXPIRED}),
    _S.SCHEDULED: frozenset({_S.PENDING, _S.RUNNING, _S.CANCELED, _S.WINDOW_EXPIRED}),
    _S.RUNNING: frozenset({_S.COMPLETED, _S.FAILED, _S.CANCELED}),
    _S.FAILED: frozenset({_S.PENDING, _S.SCHEDULED, _S.RUNNING, _S.CANCELED, _S.WINDOW_EXPIRED}),
    _S.COMPLETED: frozenset(),
    _S.CANCELED: frozenset(),
    _S.WINDOW_EXPIRED: frozenset(),
}
#: States from which nothing follows.
FINAL_STATES = frozenset(state for state, following in ALLOWED_TRANSITIONS.items() if not following)
#: States whose tasks the scheduler may place.
SCHEDULABLE_STATES = frozenset({_S.PENDING, _S.SCHEDULED, _S.FAILED})
#: States that need a reason.
_STATES_WITH_REASON = frozenset({_S.FAILED, _S.CANCELED})

ExposureCount = Annotated[int, Strict(), Field(ge=0)]
#: An index into the request's configurations or a configuration's instrument configs.
Index = Annotated[int, Strict(), Field(ge=0)]


class CutShortFrame(TaskModel):
    """A frame of instrument config ``instrument_config`` of configuration ``configuration`` that
    was stopped after ``exposed`` seconds (e.g. bad weather) and kept (its header: CUTSHORT = T).

    It does not count as an exposure done: its exposure time was not met, so a retry takes it again.
    """

    configuration: Index
    instrument_config: Index
    exposed: Annotated[Number, Field(ge=0.0)]


class TaskProgress(TaskModel):
    """What was done: ``exposures_done[c][i]`` exposures of instrument config ``i`` of configuration ``c``,
    and the frames cut short but kept (``cut_short``, in the order they were taken).

    Empty means nothing was recorded. Kept when a task fails, so a retry (or a person) knows what
    is already there. Rows stored before ``cut_short`` existed read as having none.
    """

    exposures_done: tuple[tuple[ExposureCount, ...], ...] = ()
    cut_short: tuple[CutShortFrame, ...] = ()

    @classmethod
    def nothing_done(cls, request: Request) -> TaskProgress:
        """Zero exposures for every instrument config of ``request``."""
        return cls(exposures_done=tuple((0,) * len(c.instrument_configs) for c in request.configurations))

    def count(self, configuration: int, instrument_config: int) -> int:
        """Exposures done of one instrument config (0 if nothing was recorded)."""
        try:
            return self.exposures_done[configuration][instrument_config]
        except IndexError:
            return 0

    def with_exposures(
        self, request: Request, configuration: int, instrument_config: int, count: int = 1
    ) -> TaskProgress:
        """A copy with ``count`` more exposures of one instrument config of ``request``."""
        done = [
            list(row) for row in (self.exposures_done or TaskProgress.nothing_done(request).exposures_done)
        ]
        done[configuration][instrument_config] += count
        return self.model_copy(update={"exposures_done": tuple(tuple(row) for row in done)})

    def with_cut_short(
        self, request: Request, configuration: int, instrument_config: int, exposed: float
    ) -> TaskProgress:
        """A copy that also records a frame of one instrument config of ``request`` stopped after
        ``exposed`` seconds and kept; the exposures done do not change."""
        frame = CutShortFrame(
            configuration=configuration, instrument_config=instrument_config, exposed=exposed
        )
        return self.or_nothing(request).model_copy(update={"cut_short": (*self.cut_short, frame)})

    def cut_short_count(self, configuration: int, instrument_config: int) -> int:
        """Frames of one instrument config cut short and kept."""
        return sum(
            1
            for f in self.cut_short
            if (f.configuration, f.instrument_config) == (configuration, instrument_config)
        )

    @property
    def cut_short_time(self) -> float:
        """Seconds the cut-short frames exposed (light kept, but no exposure done)."""
        return sum(f.exposed for f in self.cut_short)

    def of_configuration(self, configuration: int) -> TaskProgress:
        """The progress of configuration ``configuration`` alone, as the progress of a request
        holding only that configuration (nothing recorded stays nothing)."""
        if not self.exposures_done:
            return TaskProgress()
        return TaskProgress(
            exposures_done=(self.exposures_done[configuration],),
            cut_short=tuple(
                f.model_copy(update={"configuration": 0})
                for f in self.cut_short
                if f.configuration == configuration
            ),
        )

    def with_configuration(self, configuration: int, part: TaskProgress) -> TaskProgress:
        """A copy with configuration ``configuration`` replaced by ``part``, the progress of a
        request holding only that configuration (:meth:`of_configuration` undone). ``self`` must
        have one row per configuration (e.g. from :meth:`nothing_done`)."""
        rows = list(self.exposures_done)
        (rows[configuration],) = part.exposures_done
        others = [f for f in self.cut_short if f.configuration != configuration]
        ours = [f.model_copy(update={"configuration": configuration}) for f in part.cut_short]
        return TaskProgress(
            exposures_done=tuple(rows),
            cut_short=tuple(sorted([*others, *ours], key=lambda f: f.configuration)),
        )

    def or_nothing(self, request: Request) -> TaskProgress:
        """This progress, or :meth:`nothing_done` for ``request`` if nothing was recorded."""
        return self if self.exposures_done else TaskProgress.nothing_done(request)

    def remaining(self, request: Request, configuration: int, instrument_config: int) -> int:
        """Exposures of one instrument config still to take (a retry takes only these)."""
        wanted = request.configurations[configuration].instrument_configs[instrument_config].exposure_count
        return max(0, wanted - self.count(configuration, instrument_config))

    def repeat_time_left(self, request: Request, configuration: int) -> float:
        """Seconds of a REPEAT_EXPOSE's ``repeat_duration`` not yet spent exposing.

        Exposure time is a lower bound of the time an interrupted run used (read-outs are not
        recorded), so a resumed repeat never stops short of its duration.
        """
        config = request.configurations[configuration]
        exposed = sum(
            self.count(configuration, i) * instrument_config.exposure_time
            for i, instrument_config in enumerate(config.instrument_configs)
        )
        return max(0.0, (config.repeat_duration or 0.0) - exposed)

    def nothing_left(self, request: Request, configuration: int) -> bool:
        """Whether a retry can skip the configuration: every exposure taken (a REPEAT_EXPOSE: at
        least one cycle and its duration used up). A configuration without instrument configs
        (e.g. a SCRIPT) records no exposures, so it always runs again."""
        config = request.configurations[configuration]
        if not config.instrument_configs or not self.configuration_complete(request, configuration):
            return False
        if config.type is ConfigurationType.REPEAT_EXPOSE:
            return self.repeat_time_left(request, configuration) <= 0.0
        return True

    @property
    def total_exposures(self) -> int:
        """All exposures done."""
        return sum(sum(row) for row in self.exposures_done)

    def check_fits(self, request: Request) -> None:
        """Raise InvalidArgumentError unless the shape matches ``request`` (or nothing is recorded)."""
        if not self.exposures_done:
            return
        expected = [len(c.instrument_configs) for c in request.configurations]
        if [len(row) for row in self.exposures_done] != expected:
            raise InvalidArgumentError(
                f"progress has {[len(row) for row in self.exposures_done]} instrument configs per "
                f"configuration, the request {expected}"
            )
        for n, frame in enumerate(self.cut_short):
            if (
                frame.configuration >= len(expected)
                or frame.instrument_config >= expected[frame.configuration]
            ):
                raise InvalidArgumentError(
                    f"progress cut_short[{n}] names instrument config {frame.instrument_config} of "
                    f"configuration {frame.configuration}; the request has {expected} per configuration"
                )

    def exposure_time_done(self, request: Request) -> float:
        """Seconds of exposure done."""
        return sum(
            self.count(c, i) * instrument_config.exposure_time
            for c, configuration in enumerate(request.configurations)
            for i, instrument_config in enumerate(configuration.instrument_configs)
        )

    def configuration_complete(self, request: Request, configuration: int) -> bool:
        """Whether every exposure of a configuration was taken (a REPEAT_EXPOSE: at least one cycle)."""
        config = request.configurations[configuration]
        if config.type is ConfigurationType.REPEAT_EXPOSE:
            return all(self.count(configuration, i) >= 1 for i in range(len(config.instrument_configs)))
        return all(
            self.count(configuration, i) >= instrument_config.exposure_count
            for i, instrument_config in enumerate(config.instrument_configs)
        )


class TaskStatus(TaskModel):
    """A task's state and what goes with it.

    Args:
        state: Where the task is.
        reason: Why it FAILED or was CANCELED ("" otherwise).
        progress: Exposures done (kept across failures).
        started_at: When the last attempt started.
        finished_at: When it reached its last COMPLETED/FAILED/CANCELED/WINDOW_EXPIRED.
        modified_at: When the status last changed.
    """

    state: TaskState = TaskState.PENDING
    reason: str = ""
    progress: TaskProgress = Field(default=TaskProgress())
    started_at: UtcDatetime | None = None
    finished_at: UtcDatetime | None = None
    modified_at: UtcDatetime | None = None

    def transition(
        self, state: TaskState, *, at: datetime, reason: str = "", progress: TaskProgress | None = None
    ) -> TaskStatus:
        """The status after changing to ``state`` at ``at``.

        Raises:
            InvalidTransitionError: :data:`ALLOWED_TRANSITIONS` forbids the change, or a FAILED or
                CANCELED state comes without a reason.
        """
        if state not in ALLOWED_TRANSITIONS[self.state]:
            raise InvalidTransitionError(f"a {self.state} task cannot become {state}")
        if state in _STATES_WITH_REASON and not reason.strip():
            raise InvalidTransitionError(f"a task can only become {state} with a reason")
        ends = state in FINAL_STATES or state is TaskState.FAILED
        return TaskStatus(
            state=state,
            reason=reason,
            progress=self.progress if progress is None else progress,
            started_at=at if state is TaskState.RUNNING else self.started_at,
            finished_at=at if ends else None,
            modified_at=at,
        )

    def with_progress(self, progress: TaskProgress, *, at: datetime) -> TaskStatus:
        """The status with new progress; only while RUNNING."""
        if self.state is not TaskState.RUNNING:
            raise InvalidTransitionError(f"progress can only be recorded while RUNNING, not {self.state}")
        return self.model_copy(update={"progress": progress, "modified_at": at})
