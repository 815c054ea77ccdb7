"""Running tasks: the :class:`TaskRunner` picks a :class:`Script` for each configuration.

The mastermind takes the task due now and hands it to its runner::

    runner = self.add_child(TaskRunner(scripts={...}))
    if await runner.can_run(task):
        await runner.run_task(task, progress)   # progress(TaskProgress) after every exposure

A task with several configurations (AUTO_FOCUS then EXPOSE) runs each by its script, in order.
Scripts are keyed by configuration type name, or ``SCRIPT:<name>`` for SCRIPT configurations whose
``extra_params.script`` is ``<name>``. A script sees a task holding only the configuration it runs
and reports that configuration's progress; the runner reports the whole task's.

A task is resumed from the progress its status records (a FAILED attempt keeps it): configurations
already done are skipped and scripts take only the missing exposures, so a retry after bad weather
does not repeat frames that are already there.
"""

from nightcrew.robotic.runner._narrow import configuration_task, merged_progress
from nightcrew.robotic.runner._runner import SCRIPT_PREFIX, TaskRunner, script_key
from nightcrew.robotic.runner._script import (
    ProgressCallback,
    ProgressReporter,
    Script,
    ScriptError,
    the_configuration,
)

__all__ = [
    "SCRIPT_PREFIX",
    "ProgressCallback",
    "ProgressReporter",
    "Script",
    "ScriptError",
    "TaskRunner",
    "configuration_task",
    "merged_progress",
    "script_key",
    "the_configuration",
]
