"""Logs that last: the console (plain, JSON lines or journald's level prefixes) and a rotating file.

``nightcrew --log-file F --log-file-format json run ...`` keeps a module's log in ``F``, rotated at
``max_bytes`` with ``backups`` old files kept. Under systemd, ``--log-format systemd`` prefixes
each stderr line with its syslog priority (``<3>`` error … ``<7>`` debug), which journald reads as
the entry's level. The LogEvent forwarding to the bus (nightcrew.log) is independent of these.
"""

from __future__ import annotations

import json
import logging
import logging.handlers
from datetime import UTC, datetime
from pathlib import Path

__all__ = ["LOG_FORMATS", "configure_logging"]

LOG_FORMATS = ("text", "json", "systemd")
_TEXT = "%(asctime)s %(levelname)-7s %(name)s: %(message)s"
#: Handlers :func:`configure_logging` added, removed again by its next call.
_installed: list[logging.Handler] = []
_SYSLOG_PRIORITY = {logging.CRITICAL: 2, logging.ERROR: 3, logging.WARNING: 4, logging.INFO: 6}


class JsonLinesFormatter(logging.Formatter):
    """One JSON object per record: time (ISO, UTC), level, logger, module, message, exception."""

    def format(self, record: logging.LogRecord) -> str:
        from nightcrew.log import current_module

        entry = {
            "time": datetime.fromtimestamp(record.created, tz=UTC).isoformat(),
            "level": record.levelname,
            "logger": record.name,
            "module": current_module.get(),
            "message": record.getMessage(),
            "process": record.process,
        }
        if record.exc_info:
            entry["exception"] = self.formatException(record.exc_info)
        return json.dumps(entry, ensure_ascii=False)


class SystemdFormatter(logging.Formatter):
    """``<priority>logger: message``: journald takes the prefix as the level (sd-daemon(3))."""

    def __init__(self) -> None:
        super().__init__("%(name)s: %(message)s")

    def format(self, record: logging.LogRecord) -> str:
        priority = next((p for level, p in _SYSLOG_PRIORITY.items() if record.levelno >= level), 7)
        # Continuation lines (tracebacks) keep the level, so journald does not split them off as info.
        return "\n".join(f"<{priority}>{line}" for line in super().format(record).splitlines())


def _formatter(kind: str) -> logging.Formatter:
    if kind == "json":
        return JsonLinesFormatter()
    if kind == "systemd":
        return SystemdFormatter()
    if kind == "text":
        return logging.Formatter(_TEXT)
    raise ValueError(f"unknown log format {kind!r}; known: {', '.join(LOG_FORMATS)}")


def configure_logging(
    level: int,
    *,
    console_format: str = "text",
    log_file: Path | None = None,
    file_format: str = "text",
    max_bytes: int = 10_000_000,
    backups: int = 5,
) -> None:
    """Set up the root logger: stderr in ``console_format``, plus ``log_file`` if given (rotating).

    Like :func:`logging.basicConfig`, the console handler and level are set only when the root
    logger has no handlers yet (an application or test harness that set up logging keeps it);
    a second call replaces what the first one added.
    """
    root = logging.getLogger()
    for handler in _installed:
        root.removeHandler(handler)
        handler.close()
    _installed.clear()
    if not root.handlers:
        root.setLevel(level)
        console = logging.StreamHandler()
        console.setFormatter(_formatter(console_format))
        root.addHandler(console)
        _installed.append(console)
    if log_file is not None:
        log_file.parent.mkdir(parents=True, exist_ok=True)
        handler = logging.handlers.RotatingFileHandler(
            log_file, maxBytes=max_bytes, backupCount=backups, encoding="utf-8"
        )
        handler.setFormatter(_formatter("json" if file_format == "json" else "text"))
        root.addHandler(handler)
        _installed.append(handler)
        if root.level > level or root.level == logging.NOTSET:
            root.setLevel(level)
