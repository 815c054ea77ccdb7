"""Task archives (where tasks come from, where their fate goes) and schedule stores.

- :class:`TaskArchive` / :class:`ScheduleStore`: the abstract interfaces.
- :class:`SqliteTaskArchive`: the embedded default (one file; ``nightcrew tasks`` works on it),
  :data:`DEFAULT_TASKS_DB` by name in the observatory directory.
- :class:`YamlTaskArchive`: request groups in a YAML file written by hand, reloaded on change.
- :class:`LcoPortalArchive`: an LCO observation portal over its HTTP API.
"""

from __future__ import annotations

from nightcrew.robotic.archives._base import (
    ScheduleStore,
    TaskArchive,
    TaskChange,
    TaskListener,
)
from nightcrew.robotic.archives._lco import LcoPortalArchive
from nightcrew.robotic.archives._lco_client import LcoPortalClient, PortalError
from nightcrew.robotic.archives._local import LocalTaskArchive
from nightcrew.robotic.archives._sqlite import SqliteTaskArchive
from nightcrew.robotic.archives._yaml import YamlTaskArchive

#: The task database's file name, shared by ``nightcrew tasks`` (in the directory it runs in, the
#: observatory directory), the scheduler's and mastermind's module files and the examples.
DEFAULT_TASKS_DB = "tasks.sqlite"

__all__ = [
    "DEFAULT_TASKS_DB",
    "LcoPortalArchive",
    "LcoPortalClient",
    "LocalTaskArchive",
    "PortalError",
    "ScheduleStore",
    "SqliteTaskArchive",
    "TaskArchive",
    "TaskChange",
    "TaskListener",
    "YamlTaskArchive",
]
