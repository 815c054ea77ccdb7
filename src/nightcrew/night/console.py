"""The web console of ``nightcrew sim --console`` (options/console.yaml of the observatory) and
``nightcrew console``: a console that says where it is, with a one-time operator account when none
is configured."""

from __future__ import annotations

import os
import secrets
import sys
from typing import Any

from nightcrew.interfaces import ModuleState
from nightcrew.modules.console import WebConsole, hash_password

__all__ = ["PASSWORD_VARIABLE", "AnnouncedConsole", "one_time_accounts"]

#: Environment variable with the password of the one-time account.
PASSWORD_VARIABLE = "NIGHTCREW_CONSOLE_PASSWORD"


def one_time_accounts() -> tuple[dict[str, Any], str]:
    """Accounts with one operator, and its password ($NIGHTCREW_CONSOLE_PASSWORD or random)."""
    password = os.environ.get(PASSWORD_VARIABLE) or secrets.token_urlsafe(12)
    return {"operator": {"password_hash": hash_password(password), "role": "operator"}}, password


class AnnouncedConsole(WebConsole):
    """A console that prints where it is (and the one-time password) once it is ready.

    Args:
        accounts: As for WebConsole; none: a one-time account ``operator`` (:func:`one_time_accounts`).
        password: The one-time account's password to print, when the accounts are made elsewhere.
        **kwargs: WebConsole options.
    """

    def __init__(
        self, *, accounts: dict[str, Any] | None = None, password: str | None = None, **kwargs: Any
    ) -> None:
        if not accounts:
            accounts, password = one_time_accounts()
        super().__init__(accounts=accounts, **kwargs)
        self._password = password

    def on_state_changed(self, old: ModuleState, new: ModuleState) -> None:
        if new is ModuleState.READY and old is ModuleState.STARTING:
            login = f"; log in as 'operator' with password {self._password}" if self._password else ""
            print(f"nightcrew console at {self.url}{login}", file=sys.stderr, flush=True)
