"""Who may use the console: accounts with hashed passwords, sessions, and a brake on guessing.

Passwords are stored as ``scrypt$N$r$p$SALT$HASH`` (salt and hash base64): stdlib
:func:`hashlib.scrypt`, a memory-hard key derivation made for passwords, so no extra dependency.
Sessions live in memory (a restart logs everyone out) and are identified by a random token in an
HttpOnly cookie; each carries its own CSRF token. Wall time throughout: logins are about people.
"""

from __future__ import annotations

import base64
import hashlib
import hmac
import secrets
import time
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from nightcrew.errors import ConfigError

__all__ = [
    "Account",
    "LoginLimiter",
    "Role",
    "Session",
    "Sessions",
    "accounts_from_config",
    "check_login",
    "hash_password",
    "is_read_method",
    "verify_password",
]

_SCRYPT = {"n": 2**14, "r": 8, "p": 1}
#: Read methods (by name) a viewer may call; everything else changes something.
_READ_PREFIXES = ("get_", "is_", "list_")
_MAX_TRACKED_KEYS = 10_000


class Role(StrEnum):
    """What an account may do: a viewer sees everything and calls only read methods."""

    VIEWER = "viewer"
    OPERATOR = "operator"


def is_read_method(method: str) -> bool:
    """Whether ``method`` only reads (by the house's naming: get_*, is_*, list_*, *_status)."""
    return method.startswith(_READ_PREFIXES) or method.endswith("_status")


def hash_password(password: str, *, salt: bytes | None = None) -> str:
    """The stored form of ``password`` (a fresh random salt unless given)."""
    salt = salt if salt is not None else secrets.token_bytes(16)
    digest = hashlib.scrypt(password.encode(), salt=salt, dklen=32, **_SCRYPT)
    encoded = [base64.b64encode(x).decode() for x in (salt, digest)]
    return f"scrypt${_SCRYPT['n']}${_SCRYPT['r']}${_SCRYPT['p']}${encoded[0]}${encoded[1]}"


def _parse_hash(stored: str) -> tuple[int, int, int, bytes, bytes]:
    """The parameters of a stored hash; ValueError when it is not one."""
    parts = stored.split("$")
    if len(parts) != 6 or parts[0] != "scrypt":
        raise ValueError("expected scrypt$N$r$p$SALT$HASH (make one with: nightcrew console --hash-password)")
    n, r, p = (int(x) for x in parts[1:4])
    return n, r, p, base64.b64decode(parts[4], validate=True), base64.b64decode(parts[5], validate=True)


def verify_password(password: str, stored: str) -> bool:
    """Whether ``password`` matches the stored hash (constant-time comparison)."""
    n, r, p, salt, digest = _parse_hash(stored)
    candidate = hashlib.scrypt(password.encode(), salt=salt, n=n, r=r, p=p, dklen=len(digest), maxmem=2**26)
    return hmac.compare_digest(candidate, digest)


#: Checked against when the user name is unknown, so that a wrong name costs as long as a wrong password.
_DUMMY_HASH = hash_password("", salt=b"\0" * 16)


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
            _parse_hash(stored)
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
    ok = verify_password(password, account.password_hash if account else _DUMMY_HASH)
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


class LoginLimiter:
    """At most ``attempts`` failed logins per key (user name, client address) in ``window`` seconds."""

    def __init__(self, attempts: int, window: float, *, now: Callable[[], float] = time.monotonic) -> None:
        self._attempts = attempts
        self._window = window
        self._now = now
        self._failures: dict[str, deque[float]] = {}

    def retry_after(self, keys: list[str]) -> float:
        """Seconds until any of ``keys`` may try again; 0 when all may now."""
        now = self._now()
        wait = 0.0
        for key in keys:
            failures = self._recent(key, now)
            if len(failures) >= self._attempts:
                wait = max(wait, failures[0] + self._window - now)
        return wait

    def failed(self, keys: list[str]) -> None:
        now = self._now()
        if len(self._failures) > _MAX_TRACKED_KEYS:  # many names tried: drop the stale ones
            for key in list(self._failures):
                self._recent(key, now)
        for key in keys:
            self._failures.setdefault(key, deque()).append(now)

    def _recent(self, key: str, now: float) -> deque[float]:
        failures = self._failures.get(key)
        if failures is None:
            return deque()
        while failures and failures[0] <= now - self._window:
            failures.popleft()
        if not failures:
            del self._failures[key]
        return failures
