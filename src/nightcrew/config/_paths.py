"""File paths in configurations: relative to the file they are written in, inputs checked.

A constructor marks a parameter that takes a path with one of two hints (both are plain ``str``
to type checkers):

* :data:`InputPath` — a file that must exist before anything starts (a CA certificate, a task
  file): building refuses a missing one, naming file, line and key, so ``nightcrew check`` does too;
* :data:`DataPath` — a place the object creates when missing (a database, a VFS root).

A relative path in a YAML file is read against the folder of the file it is written in (an
included fragment: the fragment's folder), never against the working directory, so a directory of
module files works wherever it is started from. Values given in code (no file) are left as they are.
"""

from __future__ import annotations

import os
import typing
from enum import Enum
from typing import Annotated, Any

from nightcrew.config._hints import union_members

__all__ = ["DataPath", "InputPath", "PathRole", "path_role", "resolve_path"]


class PathRole(Enum):
    """What a path parameter names (see the module doc)."""

    INPUT = "input"
    DATA = "data"


#: A file that must exist (relative: to the configuration file's folder).
InputPath = Annotated[str, PathRole.INPUT]
#: A file or folder the object creates when missing (relative: to the configuration file's folder).
DataPath = Annotated[str, PathRole.DATA]


def path_role(hint: Any) -> PathRole | None:
    """The role a hint kept with its extras (``typing.get_type_hints(..., include_extras=True)``)
    marks, also inside ``X | None``; None for hints that are not paths."""
    members = union_members(hint)
    for member in members if members is not None else (hint,):
        if typing.get_origin(member) is Annotated:
            roles = [extra for extra in member.__metadata__ if isinstance(extra, PathRole)]
            if roles:
                return roles[0]
    return None


def resolve_path(value: str, file: str | None) -> str:
    """``value`` (``~`` expanded) against the folder of ``file``, where it is relative and a file
    is known."""
    path = os.path.expanduser(value)
    if file is None or not path or os.path.isabs(path):
        return path
    return os.path.normpath(os.path.join(os.path.dirname(file), path))
