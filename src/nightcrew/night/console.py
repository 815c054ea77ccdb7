"""The web console of ``nightcrew sim --console`` and ``nightcrew console``: a console that says
where it is, with a one-time operator account when none is configured."""

from __future__ import annotations

import os
import secrets
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from nightcrew.clock import Clock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.interfaces import ModuleState
from nightcrew.modules import Module
from nightcrew.modules.console import WebConsole, hash_password
from nightcrew.night.build import IMAGES_ROOT
from nightcrew.site import Site
from nightcrew.vfs import LocalFile, VirtualFileSystem

__all__ = ["PASSWORD_VARIABLE", "AnnouncedConsole", "one_time_accounts", "sim_console"]

#: Environment variable with the password of the one-time account.
PASSWORD_VARIABLE = "NIGHTCREW_CONSOLE_PASSWORD"


def one_time_accounts() -> tuple[dict[str, Any], str]:
    """Accounts with one operator, and its password ($NIGHTCREW_CONSOLE_PASSWORD or random)."""
    password = os.environ.get(PASSWORD_VARIABLE) or secrets.token_urlsafe(12)
    return {"operator": {"password_hash": hash_password(password), "role": "operator"}}, password


class AnnouncedConsole(WebConsole):
    """A console that prints where it is (and the one-time password) once it is ready.

    Args:
        password: The one-time account's password to print; None when the accounts are configured.
        **kwargs: WebConsole options.
    """

    def __init__(self, *, password: str | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._password = password

    def on_state_changed(self, old: ModuleState, new: ModuleState) -> None:
        if new is ModuleState.READY and old is ModuleState.STARTING:
            login = f"; log in as 'operator' with password {self._password}" if self._password else ""
            print(f"nightcrew console at {self.url}{login}", file=sys.stderr, flush=True)


def sim_console(
    port: int, *, clock: Clock, site: Site, images: Path
) -> Callable[[LocalNetwork], list[Module]]:
    """What ``nightcrew sim --console PORT`` adds to the night: a console reading the frames in ``images``."""
    accounts, password = one_time_accounts()

    def build(network: LocalNetwork) -> list[Module]:
        vfs = VirtualFileSystem({IMAGES_ROOT: LocalFile(str(images))})
        comm = LocalComm("console", network=network)
        options = {"clock": clock, "site": site, "vfs": vfs, "port": port, "accounts": accounts}
        return [AnnouncedConsole(comm=comm, password=password, **options)]

    return build
