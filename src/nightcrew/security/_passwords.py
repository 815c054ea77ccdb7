"""Secrets people log in with (console passwords, chat secrets): hashing, checking, a brake on guessing.

Secrets are stored as ``scrypt$N$r$p$SALT$HASH`` (salt and hash base64): stdlib
:func:`hashlib.scrypt`, a memory-hard key derivation made for passwords, so no extra dependency.
"""

from __future__ import annotations

import base64
import functools
import hashlib
import hmac
import secrets
import time
from collections import deque
from collections.abc import Callable

__all__ = ["LoginLimiter", "check_password_hash", "dummy_password_hash", "hash_password", "verify_password"]

_SCRYPT = {"n": 2**14, "r": 8, "p": 1}
_MAX_TRACKED_KEYS = 10_000


def hash_password(password: str, *, salt: bytes | None = None) -> str:
    """The stored form of ``password`` (a fresh random salt unless given)."""
    salt = salt if salt is not None else secrets.token_bytes(16)
    digest = hashlib.scrypt(password.encode(), salt=salt, dklen=32, **_SCRYPT)
    encoded = [base64.b64encode(x).decode() for x in (salt, digest)]
    return f"scrypt${_SCRYPT['n']}${_SCRYPT['r']}${_SCRYPT['p']}${encoded[0]}${encoded[1]}"


def _parse_hash(stored: str) -> tuple[int, int, int, bytes, bytes]:
    parts = stored.split("$")
    if len(parts) != 6 or parts[0] != "scrypt":
        raise ValueError("expected scrypt$N$r$p$SALT$HASH (make one with: nightcrew console --hash-password)")
    n, r, p = (int(x) for x in parts[1:4])
    return n, r, p, base64.b64decode(parts[4], validate=True), base64.b64decode(parts[5], validate=True)


def check_password_hash(stored: str) -> None:
    """Raise ValueError, saying what is expected, when ``stored`` is not a stored hash."""
    _parse_hash(stored)


def verify_password(password: str, stored: str) -> bool:
    """Whether ``password`` matches the stored hash (constant-time comparison)."""
    n, r, p, salt, digest = _parse_hash(stored)
    candidate = hashlib.scrypt(password.encode(), salt=salt, n=n, r=r, p=p, dklen=len(digest), maxmem=2**26)
    return hmac.compare_digest(candidate, digest)


@functools.cache
def dummy_password_hash() -> str:
    """Checked against when the user is unknown, so that a wrong name costs as long as a wrong password."""
    return hash_password("", salt=b"\0" * 16)


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
