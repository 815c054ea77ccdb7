"""The task archive a robotic module's file names: built, given the module's clock, opened and
closed with the module.

A module file says ``archive: {class: nightcrew.robotic.archives.SqliteTaskArchive, path:
tasks.sqlite}`` (or a block source built around such an archive, which keeps it as ``archive``);
the module builds it (a relative ``path`` is read against the file's folder), opens it before its
own loops start and closes it after they stopped. An archive handed over as an object stays its
maker's: the module opens it (opening is idempotent) but does not close it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.modules.module import Module
from nightcrew.robotic.archives import TaskArchive

__all__ = ["ArchiveOption", "built_option"]


@dataclass(frozen=True)
class ArchiveOption:
    """What an ``archive`` (or ``store``/``schedule``) option gave.

    Attributes:
        value: The object (the archive, a block source, a schedule store ...).
        archive: The task archive in it: ``value`` itself, or the ``archive`` a block source wraps.
        owned: Whether the module built it from a description (then it also closes it).
    """

    value: Any
    archive: TaskArchive | None
    owned: bool

    async def open(self) -> None:
        if self.archive is not None:
            await self.archive.open()  # idempotent; a shared archive may be open already

    async def close(self) -> None:
        if self.owned and self.archive is not None:
            await self.archive.close()


def built_option(
    value: Any, expected: type[Any] | tuple[type[Any], ...], key: str, owner: Module
) -> ArchiveOption:
    """``value``, or the object its description builds (ours to close), checked against ``expected``.

    An archive the description builds without a ``clock`` of its own gets ``owner``'s: "now" of a
    simulated night is the module's clock.
    """
    owned = isinstance(value, Mapping)
    built = build_object(value) if owned else value
    if not isinstance(built, expected):
        raise ConfigError(f"expected a {_names(expected)}, got {type(built).__name__}", key=key)
    archive = built if isinstance(built, TaskArchive) else getattr(built, "archive", None)
    if not isinstance(archive, TaskArchive):
        archive = None
    if owned and archive is not None and not _gives_clock(value, wrapped=archive is not built):
        archive.clock = owner.clock
    return ArchiveOption(built, archive, owned)


def _gives_clock(description: Mapping[str, Any], *, wrapped: bool) -> bool:
    inner = description.get("archive") if wrapped else description
    return isinstance(inner, Mapping) and "clock" in inner


def _names(expected: type[Any] | tuple[type[Any], ...]) -> str:
    kinds = expected if isinstance(expected, tuple) else (expected,)
    return " or ".join(kind.__name__ for kind in kinds)
