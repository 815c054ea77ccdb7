"""Fixtures of the chat modules' tests: the Bot API stand-in, people with secrets, a policy.

Modules are built with comms that carry the test's access policy and audit trail, on an
observatory whose clock follows the wall clock (sped up): the chat modules talk to real sockets
(the stand-in, Prosody), whose timeouts a virtual clock would skip (docs/concepts.md#clock).
"""

from __future__ import annotations

import functools
from collections.abc import AsyncIterator, Callable
from pathlib import Path
from typing import Any, TypeVar

import pytest

from nightcrew.comm.local import LocalComm
from nightcrew.modules import Module
from nightcrew.modules.console import hash_password
from nightcrew.testing import Observatory

# The session's Prosody, as tests/comm starts it (imported to be found here).
from tests.comm.conftest import prosody_server  # noqa: F401
from tests.comm.xmpp_servers import XmppServer

from .telegram_standin import BotApiStandIn
from .xmpp_person import Person

M = TypeVar("M", bound=Module)

TOKEN = "123456:test-token-never-shown"
#: Telegram user ids and XMPP accounts of the people, their policy accounts and secrets.
OPERATOR_ID, OBSERVER_ID, STRANGER_ID = 1001, 1002, 1003
OPERATOR, OBSERVER = "olga", "oscar"
SECRETS = {OPERATOR: "olga-secret-1", OBSERVER: "oscar-secret-2"}

POLICY = """\
roles:
  observer: ["*.get_*", IModule]
  operator: ["*"]
  chat: ["*"]
  modules: ["*"]
  safety: []
accounts:
  olga: [operator]
  oscar: [observer]
  telegram: [chat]
  xmppchat: [chat]
  weather: [modules, safety]
  weatherstation: [modules]
  roof: [modules]
  recorder: [modules]
safety_roles: [safety]
events:
  BadWeatherEvent: [safety]
  GoodWeatherEvent: [safety]
"""


@functools.cache
def secret_hash(account: str) -> str:
    return hash_password(SECRETS[account])


def users(key_of: dict[str, Any]) -> dict[Any, dict[str, str]]:
    """The chat ``users`` option: the people's keys on the chat → policy account and secret hash."""
    return {key: {"account": account, "secret_hash": secret_hash(account)} for account, key in key_of.items()}


class SecuredObservatory(Observatory):
    """The test observatory, every module's comm carrying the policy and the audit trail."""

    def __init__(self, directory: Path, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.policy = directory / "policy.yaml"
        self.policy.write_text(POLICY)
        self.audit = directory / "audit.jsonl"

    def comm(self, name: str) -> LocalComm:
        return LocalComm(name, network=self.network, policy=str(self.policy), audit=str(self.audit))


@pytest.fixture
async def observatory(tmp_path: Path) -> AsyncIterator[SecuredObservatory]:
    """Sped up ten times from the wall clock: real sockets keep real timeouts."""
    obs = SecuredObservatory(tmp_path, speed=10.0)
    try:
        yield obs
    finally:
        await obs.close()


@pytest.fixture
async def bot_api() -> AsyncIterator[BotApiStandIn]:
    """The Bot API stand-in (Telegram's servers cannot be reached from tests)."""
    standin = BotApiStandIn(TOKEN)
    await standin.start()
    try:
        yield standin
    finally:
        await standin.close()


@pytest.fixture
def prosody(request: pytest.FixtureRequest) -> XmppServer:
    """The session's Prosody (tests/comm/conftest.py starts it)."""
    server: XmppServer = request.getfixturevalue("prosody_server")
    return server


@pytest.fixture
async def people(prosody: XmppServer) -> AsyncIterator[Callable[[str], Person]]:
    """Makes people with accounts on Prosody (connect them yourself); all disconnected after."""
    made: list[Person] = []

    def make(name: str) -> Person:
        person = Person(prosody, name)
        made.append(person)
        return person

    try:
        yield make
    finally:
        for person in made:
            await person.close()
