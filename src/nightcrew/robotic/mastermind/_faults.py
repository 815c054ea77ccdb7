"""Why a task failed: a device under it, or the task's own content.

A device failure - a device module offline or restarting, in error state, busy, a device that
refused or failed an action, a call that timed out - says nothing about the task: it may run again
once the device is back (the mastermind waits for it, then the scheduler retries it later the same
night). A failure of the task's own content - an invalid argument, something no device here can do,
a configuration no script runs - would fail again: it is not retried tonight.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from nightcrew.errors import (
    AbortedError,
    CalibratorError,
    CodecError,
    ConfigError,
    DeviceBusyError,
    ForbiddenError,
    GrabImageError,
    InterfaceError,
    InvalidArgumentError,
    ModuleError,
    MotionError,
    NightcrewError,
    NotSupportedError,
    RemoteError,
)
from nightcrew.robotic.tasks import Task, TaskProgress

__all__ = ["DeviceFault", "device_fault", "resumed"]

#: Errors that say the task asked for something wrong (checked first: ForbiddenError is a RemoteError).
_CONTENT_ERRORS = (
    ConfigError,
    InvalidArgumentError,
    NotSupportedError,
    CodecError,
    ForbiddenError,
    InterfaceError,
)
#: Errors that say a device (or its module) failed, whoever raised them.
_DEVICE_ERRORS = (
    ModuleError,
    RemoteError,
    MotionError,
    GrabImageError,
    CalibratorError,
    DeviceBusyError,
    AbortedError,
)


@dataclass(frozen=True)
class DeviceFault:
    """A device failed under a task.

    Args:
        module: The module that failed, when the error names it (it came over the comm).
        reason: The device's error, for a person.
    """

    module: str | None
    reason: str


def device_fault(error: BaseException) -> DeviceFault | None:
    """The device failure behind ``error`` (a script's error and the causes it was raised from), or
    None when the task failed by its own content.

    The first error along the chain that says either decides; an error raised by another module
    (it names the module) that says neither is that module's failure too.
    """
    for link in _chain(error):
        if isinstance(link, _CONTENT_ERRORS):
            return None
        if isinstance(link, NightcrewError) and (isinstance(link, _DEVICE_ERRORS) or link.module):
            return DeviceFault(module=link.module, reason=str(link) or type(link).__name__)
    return None


def resumed(task: Task, progress: TaskProgress) -> Task:
    """``task`` as it restarts after a device came back: from ``progress`` on (done frames are kept)."""
    return task.model_copy(update={"status": task.status.model_copy(update={"progress": progress})})


def _chain(error: BaseException) -> Iterator[BaseException]:
    seen: set[int] = set()
    link: BaseException | None = error
    while link is not None and id(link) not in seen:  # bounded: a cycle of causes ends it
        seen.add(id(link))
        yield link
        link = link.__cause__
