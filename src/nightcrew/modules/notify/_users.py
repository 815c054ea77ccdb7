"""The people a chat module talks to: who they are on the chat, their policy account, their secret."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.security import check_password_hash

__all__ = ["ChatUser", "users_from_config"]


@dataclass(frozen=True)
class ChatUser:
    """A person: ``key`` on the chat (Telegram user id, bare JID), policy ``account``, secret hash."""

    key: str
    account: str
    secret_hash: str

    def __repr__(self) -> str:  # never the hash in logs or tracebacks
        return f"ChatUser({self.key!r}, account={self.account!r})"


def users_from_config(config: Mapping[Any, Any], *, normalise: Any = str) -> dict[str, ChatUser]:
    """Users from ``{key: {account: NAME, secret_hash: scrypt$...}}``, each checked (key ``users.KEY``)."""
    if not isinstance(config, Mapping):
        raise ConfigError("expected a mapping of users", key="users")
    users = {}
    for raw_key, entry in config.items():
        key = normalise(raw_key)
        where = f"users.{raw_key}"
        if not isinstance(entry, Mapping):
            raise ConfigError("expected account and secret_hash", key=where)
        unknown = set(entry) - {"account", "secret_hash"}
        if unknown:
            raise ConfigError(f"unknown keys {', '.join(sorted(map(str, unknown)))}", key=where)
        account, stored = entry.get("account"), entry.get("secret_hash")
        if not isinstance(account, str) or not account:
            raise ConfigError("expected the user's account in the access policy", key=f"{where}.account")
        if not isinstance(stored, str):
            raise ConfigError("missing secret_hash", key=f"{where}.secret_hash")
        try:
            check_password_hash(stored)
        except ValueError as exc:
            raise ConfigError(f"not a secret hash: {exc}", key=f"{where}.secret_hash") from None
        users[key] = ChatUser(key, account, stored)
    return users
