"""Which XMPP accounts a set of module configurations needs."""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from nightcrew.comm.xmpp import parse_jid
from nightcrew.config import ConfigNode, load_config
from nightcrew.config._paths import resolve_path
from nightcrew.errors import ConfigError
from nightcrew.security import starting_policy

__all__ = ["Account", "accounts_from_configs", "policies_named", "policy_for_accounts"]


@dataclass(frozen=True)
class Account:
    """One login: ``user@domain`` with its password; ``person``: a person's (an operator command's
    comm file), not a module's. Modules own the room, people are its members."""

    user: str
    domain: str
    password: str
    person: bool = False

    @property
    def jid(self) -> str:
        return f"{self.user}@{self.domain}"


def accounts_from_configs(
    paths: Iterable[str | os.PathLike[str]], *, environ: Mapping[str, str] | None = None
) -> list[Account]:
    """The accounts of every module config whose ``comm:`` has a ``jid``, and of every comm
    description alone in a file (``jid`` at the top level, as ``--comm`` files for the operator
    commands are: a person's); ``${VAR}`` resolved.

    Raises:
        ConfigError: A file cannot be read, a JID is malformed or has no password, or one JID
            appears twice with different passwords.
    """
    found: dict[str, Account] = {}
    for path in paths:
        config = load_config(path, environ=environ)
        comm, prefix = (config, "") if "jid" in config else (config.get("comm"), "comm.")
        if not isinstance(comm, Mapping) or "jid" not in comm:
            continue
        user, domain, _ = parse_jid(str(comm["jid"]))
        password = comm.get("password")
        if not password:
            raise ConfigError(f"{os.fspath(path)}: key '{prefix}password': missing")
        account = Account(user, domain, str(password), person=not prefix)
        previous = found.get(account.jid)
        if previous is not None and previous.password != account.password:
            raise ConfigError(f"{os.fspath(path)}: {account.jid} appears twice with different passwords")
        found[account.jid] = account
    return list(found.values())


def policy_for_accounts(
    accounts: Iterable[Account], operators: Iterable[str] = ("operator",)
) -> dict[str, Any]:
    """The starting access policy (plain data) for these accounts: modules call each other, the
    people named in ``operators`` everything, other people only what reads."""
    given = list(accounts)
    chosen = set(operators)
    people = {a.user: "operator" if a.user in chosen else "observer" for a in given if a.person}
    return starting_policy([a.user for a in given if not a.person], people)


def policies_named(
    paths: Iterable[str | os.PathLike[str]], *, environ: Mapping[str, str] | None = None
) -> list[Path | None]:
    """For each module file (a ``class`` with a ``comm.jid``), the access policy file its comm
    names, resolved as the comm resolves it (against the file the key is written in); None where
    it names none or says ``policy: open``."""
    named: list[Path | None] = []
    for path in paths:
        config = load_config(path, environ=environ)
        comm = config.get("comm")
        if "jid" in config or not isinstance(comm, ConfigNode) or "jid" not in comm:
            continue  # a person's file, or a module without an XMPP account
        policy = comm.get("policy")
        if not isinstance(policy, str) or policy == "open":
            named.append(None)
            continue
        location = comm.location_of("policy")
        named.append(Path(resolve_path(policy, location.file if location else os.fspath(path))))
    return named
