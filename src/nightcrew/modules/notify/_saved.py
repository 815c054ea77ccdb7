"""Sessions kept across restarts: who is logged in where, at which log level (a small JSON file).

Without it a restarted chat module would tell nobody about trouble until each person logged in
again. The file gives a session to whoever can write it: it is written with mode 0600, replaced
atomically, and a session is restored only for a person still configured with the same account.
"""

from __future__ import annotations

import json
import logging
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from nightcrew.modules.notify._commands import LOG_LEVELS
from nightcrew.modules.notify._dispatch import Session
from nightcrew.modules.notify._users import ChatUser

__all__ = ["load_sessions", "save_sessions", "sessions_text"]

log = logging.getLogger(__name__)


def sessions_text(sessions: Iterable[Session]) -> str:
    """The file's text for ``sessions`` (sorted, so that an unchanged set gives the same text)."""
    entries = {
        s.user.key: {"account": s.user.account, "address": s.address, "level": s.level} for s in sessions
    }
    return json.dumps(dict(sorted(entries.items())), indent=1)


def save_sessions(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` (owner only), replacing the old file in one step."""
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".partial")
    descriptor = os.open(partial, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(descriptor, "w", encoding="utf-8") as stream:
        stream.write(text)
    os.replace(partial, path)


def load_sessions(path: Path, users: Mapping[str, ChatUser]) -> list[tuple[ChatUser, str, str]]:
    """(user, address, level) of each saved session still valid; a missing or broken file is none."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return []
    except (OSError, ValueError) as exc:
        log.warning("cannot read the saved sessions %s (%s); everybody logs in again", path, exc)
        return []
    restored = []
    for key, entry in data.items() if isinstance(data, dict) else ():
        user = users.get(key)
        if (
            user is None
            or not isinstance(entry, dict)
            or entry.get("account") != user.account
            or not isinstance(entry.get("address"), str)
            or entry.get("level") not in LOG_LEVELS
        ):
            continue  # removed, or given another account, since: log in again
        restored.append((user, entry["address"], entry["level"]))
    return restored
