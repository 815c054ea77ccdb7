"""The audit trail: every state-changing call, one JSON object per line, appended, never rewritten.

A record holds time (UTC), caller, module, method, the arguments (each shortened) and the outcome
(``ok``, ``forbidden`` or the error class). Getters (``get_*``, ``is_*``, ``list_*``) are not
recorded: they change nothing and would drown the rest. The file survives restarts: a new
:class:`AuditLog` on the same path appends.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from dataclasses import asdict, dataclass
from datetime import UTC, datetime
from fnmatch import fnmatchcase
from pathlib import Path
from typing import Any

__all__ = ["GETTER_PREFIXES", "AuditLog", "AuditRecord", "is_state_changing", "read_audit"]

#: Methods named so only read: not audited, and open to everyone under the closed default policy.
GETTER_PREFIXES = ("get_", "is_", "list_", "has_")
_ARGUMENT_CHARS = 200


def is_state_changing(method: str) -> bool:
    """Whether a call of ``method`` belongs in the audit trail (not a getter)."""
    return not method.startswith(GETTER_PREFIXES)


@dataclass(frozen=True)
class AuditRecord:
    time: str
    caller: str
    module: str
    method: str
    arguments: list[str]
    outcome: str


class AuditLog:
    """Appends records to the JSON-lines file ``path`` (created with its directory if missing)."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)

    def record(self, caller: str, module: str, method: str, args: list[Any], outcome: str) -> None:
        entry = AuditRecord(
            time=datetime.now(UTC).isoformat(timespec="milliseconds"),
            caller=caller,
            module=module,
            method=method[:_ARGUMENT_CHARS],
            arguments=[_shown(arg) for arg in args[:16]],
            outcome=outcome,
        )
        self.path.parent.mkdir(parents=True, exist_ok=True)
        # Created 0600: the trail names accounts and arguments, not for every local user to read.
        # One write of one line in append mode: records of several processes do not interleave.
        line = (json.dumps(asdict(entry), ensure_ascii=False) + "\n").encode()
        descriptor = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o600)
        try:
            os.write(descriptor, line)
        finally:
            os.close(descriptor)


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= _ARGUMENT_CHARS else f"{text[:_ARGUMENT_CHARS]}... ({len(text)} characters)"


def read_audit(
    path: str | os.PathLike[str],
    *,
    caller: str | None = None,
    module: str | None = None,
    method: str | None = None,
    outcome: str | None = None,
) -> Iterator[AuditRecord]:
    """The records of the file, oldest first, filtered (``method`` may be a pattern); bad lines skipped."""
    with Path(path).open(encoding="utf-8", errors="replace") as stream:
        for line in stream:
            try:
                record = AuditRecord(**json.loads(line))
            except (ValueError, TypeError):
                continue
            if caller is not None and record.caller != caller:
                continue
            if module is not None and record.module != module:
                continue
            if method is not None and not fnmatchcase(record.method, method):
                continue
            if outcome is not None and record.outcome != outcome:
                continue
            yield record
