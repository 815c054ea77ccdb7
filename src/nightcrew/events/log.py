"""Log records forwarded from a module to the bus (for log viewers and the web UI)."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from nightcrew.events.base import Event

__all__ = ["LogEvent"]


@dataclass(frozen=True, kw_only=True)
class LogEvent(Event):
    """One log record of level INFO or higher."""

    time: datetime  # UTC
    level: str  # logging level name: "INFO", "WARNING", ...
    logger: str  # the logger's name, usually the Python module
    message: str  # the formatted message
    filename: str | None = None  # source file of the logging call
    line: int | None = None  # line in that file
