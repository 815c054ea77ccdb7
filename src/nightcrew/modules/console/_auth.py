"""Who may use the console: accounts with hashed passwords, sessions, and a brake on guessing.

Passwords are hashed and checked by :mod:`nightcrew.security` (scrypt), which the chat modules share.
Sessions live in memory (a restart logs everyone out) and are identified by a random token in an
HttpOnly cookie; each carries its own CSRF token. Wall time throughout: logins are about people.
"""

from __future__ import annotations

import ipaddress
import secrets
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.security import LoginLimiter, check_password_hash, dummy_password_hash, verify_password

__all__ = [
    "Account",
    "LoginThrottle",
    "Role",
    "Session",
    "Sessions",
    "accounts_from_config",
    "check_login",
    "is_read_method",
]

#: A client address wider than one address family allows is not an address (and not a key to keep).
_ADDRESS_CHARS = 45
_Network = ipaddress.IPv4Network | ipaddress.IPv6Network

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


class LoginThrottle:
    """The brake on guessing passwords, keyed so that nobody locks others out.

    Failures count per user name *and* client address (``attempts`` in ``window`` wall seconds),
    and per client address across names (``address_factor`` times as many). The client address is
    the connection's, or - only when the connection comes from one of ``trusted_proxies`` - the
    one those proxies put in ``X-Forwarded-For`` (the right-most address not itself a trusted
    proxy: what a client writes there itself is further left and never believed).
    """

    def __init__(
        self,
        attempts: int,
        window: float,
        trusted_proxies: Iterable[str] = (),
        *,
        address_factor: int = 4,
        now: Callable[[], float] = time.monotonic,
    ) -> None:
        self._trusted = _networks(trusted_proxies)
        self._per_user = LoginLimiter(attempts, window, now=now)
        self._per_address = LoginLimiter(address_factor * attempts, window, now=now)

    def client_address(self, remote: str | None, forwarded_for: Iterable[str]) -> str:
        """The client behind a connection from ``remote`` with these ``X-Forwarded-For`` values."""
        client = remote or "?"
        if not self._trusted_hop(client):
            return client
        hops = [hop.strip() for value in forwarded_for for hop in value.split(",")]
        for hop in reversed(hops):
            if not self._trusted_hop(hop):
                # Not an address: the proxy passed something odd on; count it on the proxy.
                return hop if _address(hop) is not None else client
            client = hop
        return client

    def retry_after(self, user: str, client: str) -> float:
        """Wall seconds until ``user`` may try again from ``client``; 0 when now."""
        return max(
            self._per_user.retry_after([_user_key(user, client)]), self._per_address.retry_after([client])
        )

    def failed(self, user: str, client: str) -> None:
        self._per_user.failed([_user_key(user, client)])
        self._per_address.failed([client])

    def _trusted_hop(self, hop: str) -> bool:
        address = _address(hop)
        return address is not None and any(address in network for network in self._trusted)


def _user_key(user: str, client: str) -> str:
    return f"{client} {user}"  # an address has no space: the key is unambiguous


def _address(text: str) -> ipaddress.IPv4Address | ipaddress.IPv6Address | None:
    if len(text) > _ADDRESS_CHARS:
        return None
    try:
        return ipaddress.ip_address(text)
    except ValueError:
        return None


def _networks(values: Iterable[str]) -> tuple[_Network, ...]:
    if isinstance(values, str) or not isinstance(values, Iterable):
        raise ConfigError("expected a list of addresses or networks (10.0.0.0/8)", key="trusted_proxies")
    networks = []
    for index, value in enumerate(values):
        try:
            networks.append(ipaddress.ip_network(str(value), strict=False))
        except ValueError:
            raise ConfigError(
                f"not an address or network: {str(value)[:60]!r}", key=f"trusted_proxies[{index}]"
            ) from None
    return tuple(networks)
