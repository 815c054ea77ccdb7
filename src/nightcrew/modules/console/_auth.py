"""Who may use the console: accounts with hashed passwords, sessions, and a brake on guessing.

Passwords are hashed and checked by :mod:`nightcrew.security` (scrypt), which the chat modules share.
Sessions live in memory (a restart logs everyone out) and are identified by a random token in an
HttpOnly cookie; each carries its own CSRF token. Wall time throughout: logins are about people.
"""

from __future__ import annotations

import secrets
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.security import check_password_hash, dummy_password_hash, verify_password

__all__ = [
    "Account",
    "Role",
    "Session",
    "Sessions",
    "accounts_from_config",
    "check_login",
    "is_read_method",
]

#: Read methods (by name) a viewer may call; everything else changes something.
_READ_PREFIXES = ("get_", "is_", "list_")


class Role(StrEnum):
    """What an account may do: a viewer sees everything and calls only read methods."""

    VIEWER = "viewer"
    OPERATOR = "operator"


def is_read_method(method: str) -> bool:
    """Whether ``method`` only reads (by the house's naming: get_*, is_*, list_*, *_status)."""
    return method.startswith(_READ_PREFIXES) or method.endswith("_status")


@dataclass(frozen=True)
class Account:
    """A console user: name, stored password hash, role."""

    user: str
    password_hash: str
    role: Role

    def __repr__(self) -> str:  # never the hash in logs or tracebacks
        return f"Account({self.user!r}, role={self.role.value})"


def accounts_from_config(config: Mapping[str, Any]) -> dict[str, Account]:
    """Accounts from ``{user: {password_hash: ..., role: viewer|operator}}``, each checked."""
    accounts = {}
    for user, entry in config.items():
        key = f"accounts.{user}"
        if not isinstance(entry, Mapping):
            raise ConfigError("expected password_hash and role", key=key)
        unknown = set(entry) - {"password_hash", "role"}
        if unknown:
            raise ConfigError(f"unknown keys {', '.join(sorted(unknown))}", key=key)
        stored = entry.get("password_hash")
        if not isinstance(stored, str):
            raise ConfigError("missing password_hash", key=f"{key}.password_hash")
        try:
            check_password_hash(stored)
        except ValueError as exc:
            raise ConfigError(f"not a password hash: {exc}", key=f"{key}.password_hash") from None
        try:
            role = Role(entry.get("role", "viewer"))
        except ValueError:
            roles = ", ".join(r.value for r in Role)
            raise ConfigError(
                f"must be one of {roles}, got {entry.get('role')!r}", key=f"{key}.role"
            ) from None
        accounts[str(user)] = Account(str(user), stored, role)
    return accounts


def check_login(accounts: Mapping[str, Account], user: str, password: str) -> Account | None:
    """The account if ``user`` and ``password`` match, else None (same cost either way)."""
    account = accounts.get(user)
    ok = verify_password(password, account.password_hash if account else dummy_password_hash())
    return account if ok and account is not None else None


@dataclass
class Session:
    """A logged-in browser."""

    token: str
    user: str
    role: Role
    csrf_token: str
    expires: float  # wall time (time.time())


class Sessions:
    """The open sessions, by cookie token; each expires ``lifetime`` wall seconds after its last use."""

    def __init__(self, lifetime: float, *, now: Callable[[], float] = time.time) -> None:
        self._lifetime = lifetime
        self._now = now
        self._sessions: dict[str, Session] = {}

    def create(self, account: Account) -> Session:
        session = Session(
            token=secrets.token_urlsafe(32),
            user=account.user,
            role=account.role,
            csrf_token=secrets.token_urlsafe(32),
            expires=self._now() + self._lifetime,
        )
        self._sessions[session.token] = session
        return session

    def get(self, token: str | None) -> Session | None:
        """The live session of ``token`` (its lifetime renewed), or None."""
        session = self._sessions.get(token) if token else None
        if session is None:
            return None
        now = self._now()
        if session.expires <= now:
            del self._sessions[session.token]
            return None
        session.expires = now + self._lifetime
        return session

    def end(self, token: str) -> None:
        self._sessions.pop(token, None)
