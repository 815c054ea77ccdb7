"""Errors of the task model and the task archives (all below :class:`NightcrewError`)::

NightcrewError
└── TaskError                   something about a task went wrong
    ├── InvalidTaskError        a request group breaks the model; every problem names its field
    ├── TaskNotFoundError       no task with this id
    └── InvalidTransitionError  a state change the state table does not allow
"""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.errors import NightcrewError

__all__ = ["InvalidTaskError", "InvalidTransitionError", "TaskError", "TaskNotFoundError", "TaskProblem"]


class TaskError(NightcrewError):
    """Base of the errors about tasks and task archives."""


@dataclass(frozen=True)
class TaskProblem:
    """One thing wrong with a request group: where (``requests[0].windows[1].end``) and what."""

    path: str
    message: str

    def __str__(self) -> str:
        return f"{self.path}: {self.message}" if self.path else self.message


class InvalidTaskError(TaskError):
    """A request group is invalid.

    The text names the first problem (``requests[0].configurations[1].instrument_configs[0]
    .exposure_time: must be > 0``) and how many more there are; :attr:`problems` has them all.

    Args:
        problems: Everything wrong, in document order (at least one).
        source: The file the group came from, if any; it prefixes the text.
    """

    def __init__(self, problems: list[TaskProblem] | tuple[TaskProblem, ...], *, source: str = "") -> None:
        self.problems = tuple(problems)
        self.source = source
        first = str(self.problems[0]) if self.problems else "invalid request group"
        more = len(self.problems) - 1
        text = first + (f" (and {more} more problem{'s' if more > 1 else ''})" if more > 0 else "")
        super().__init__(f"{source}: {text}" if source else text)


class TaskNotFoundError(TaskError):
    """The archive has no task with the given id."""


class InvalidTransitionError(TaskError):
    """A task cannot go from its state to the one asked for (e.g. COMPLETED -> RUNNING)."""
