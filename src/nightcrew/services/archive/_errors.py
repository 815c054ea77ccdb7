"""The archive's refusals: an HTTP status and one message naming what is wrong.

Handlers and the layers below raise :class:`Rejected`; the server turns it into a JSON reply
``{"error": <status phrase>, "detail": <message>}`` in one place (``_server.py``).
:class:`DatabaseUnavailable` is a Rejected with 503 for a database that went away or is locked.
"""

from __future__ import annotations

from typing import Any

__all__ = ["DatabaseUnavailable", "Rejected"]


class Rejected(Exception):
    """A request the archive refuses.

    Args:
        status: The HTTP status of the reply.
        message: What is wrong and where (the parameter, keyword or file named).
        extra: More JSON fields for the reply, e.g. the existing frame of a duplicate.
    """

    def __init__(self, status: int, message: str, *, extra: dict[str, Any] | None = None) -> None:
        super().__init__(message)
        self.status = status
        self.message = message
        self.extra = extra or {}


class DatabaseUnavailable(Rejected):
    """The database cannot be reached or is locked; nothing was stored."""

    def __init__(self, why: str) -> None:
        super().__init__(503, f"the archive's database is unavailable ({why}); nothing was stored")
