"""Modules own the room, people are members: the documented set-up on a real Prosody.

``nightcrew server init`` with module files and the people's comm files (operator.yaml,
observer.yaml) writes the starting policy, which every module's comm names. The observer enters
the members-only room but may not destroy or configure it, grant membership or ban; when the room
disappears anyway (destroyed by an owner), the modules enter it again and log it at WARNING; a
module whose name another account holds waits and says so, instead of exiting.
"""

from __future__ import annotations

import asyncio
import xml.etree.ElementTree as ET
from collections.abc import AsyncIterator, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.comm.xmpp import XmppComm
from nightcrew.config import build_object, load_config
from nightcrew.errors import ForbiddenError
from nightcrew.modules import Module
from nightcrew.security import load_policy
from nightcrew.server import start_server, stop_server
from nightcrew.testing.waiting import wait_for

from ..comm.xmpp_servers import free_port, require_command
from .muc import NS_OWNER, room_iq, ruling_attempts

pytestmark = pytest.mark.xmpp

DOMAIN = "roles.test"
ROOM = "nightcrew"
MODULES = ("camera", "roof", "weather", "dome")
PEOPLE = ("operator", "observer")
ROOM_JID = f"{ROOM}@conference.{DOMAIN}"


@dataclass
class _Observatory:
    directory: Path
    files: dict[str, Path]

    def module(self, name: str) -> Module:
        """The module (or, for a person, a client) a file describes, built as `nightcrew run` does."""
        built = build_object(load_config(self.files[name]))
        module = Module(comm=built) if isinstance(built, XmppComm) else built
        assert isinstance(module, Module)
        return module


@pytest.fixture(scope="module")
def observatory(tmp_path_factory: pytest.TempPathFactory) -> Iterator[_Observatory]:
    require_command("prosody", "prosody")
    top = tmp_path_factory.mktemp("roles")
    server, port = top / "xmpp", free_port()
    comm = (
        f"  class: nightcrew.comm.xmpp.XmppComm\n  server: 127.0.0.1:{port}\n"
        f"  ca_file: xmpp/certs/{DOMAIN}.crt\n  policy: xmpp/access.policy\n"
    )
    files = {}
    for name in MODULES:
        files[name] = top / f"{name}.yaml"
        files[name].write_text(
            f"class: nightcrew.modules.Module\ncomm:\n{comm}  jid: {name}@{DOMAIN}\n  password: pw-{name}\n"
        )
    files["holder"] = top / "holder.yaml"  # the dome's account entering under the name 'weather'
    holder_comm = comm.replace("nightcrew.comm.xmpp.XmppComm", f"{__name__}._HolderComm")
    holder = f"class: nightcrew.modules.Module\ncomm:\n{holder_comm}  jid: dome@{DOMAIN}\n"
    files["holder"].write_text(f"{holder}  password: pw-dome\n")
    for name in PEOPLE:  # the people's comm files, as the operator commands take them
        files[name] = top / f"{name}.yaml"
        files[name].write_text(comm.replace("  ", "") + f"jid: {name}@{DOMAIN}\npassword: pw-{name}\n")
    given = [str(path) for name, path in files.items() if name != "holder"]
    assert main(["server", "init", str(server), "--port", str(port), *given]) == 0
    start_server(server)
    try:
        yield _Observatory(top, files)
    finally:
        stop_server(server)


@pytest.fixture
async def modules(observatory: _Observatory) -> AsyncIterator[dict[str, Module]]:
    started: dict[str, Module] = {}
    try:
        for name in ("camera", "roof"):
            started[name] = observatory.module(name)
            await asyncio.wait_for(started[name].open(), 20)
        yield started
    finally:
        for module in started.values():
            await module.close()


def test_server_init_writes_the_starting_policy(observatory: _Observatory) -> None:
    policy = load_policy(observatory.directory / "xmpp" / "access.policy")
    assert policy.roles_of("camera") == ("modules",) and policy.roles_of("weather") == ("modules", "safety")
    assert policy.roles_of("operator") == ("operator",) and policy.roles_of("observer") == ("observer",)
    assert policy.allows("observer", "roof", "get_motion_status", None)
    assert not policy.allows("observer", "roof", "open_roof", None)
    config = (observatory.directory / "xmpp" / "prosody.cfg.lua").read_text()
    room_section = config.split(f'Component "conference.{DOMAIN}"', 1)[1]
    owners = next(line for line in room_section.splitlines() if "admins" in line)
    assert "observer" not in owners and "operator" not in owners  # people own no room


async def test_people_are_members_and_cannot_rule_the_room(
    observatory: _Observatory, modules: dict[str, Module]
) -> None:
    from slixmpp.exceptions import IqError

    observer = observatory.module("observer")
    await asyncio.wait_for(observer.open(), 20)  # a member: the modules admitted it from the policy
    try:
        await wait_for(lambda: {"camera", "roof"} <= set(observer.comm.clients), 20)
        for what, (kind, namespace, children) in ruling_attempts(DOMAIN, "observer").items():
            with pytest.raises(IqError) as refused:
                await room_iq(observer.comm, ROOM_JID, kind, namespace, *children)
            assert refused.value.iq["error"]["condition"] in ("forbidden", "not-allowed"), what
        with pytest.raises(ForbiddenError, match=r"observer may not call roof\.open_roof"):
            await observer.comm.execute("roof", "open_roof", [])
        assert set(observer.comm.clients) >= {"camera", "roof"}  # nothing changed
    finally:
        await observer.close()


async def test_a_held_name_is_waited_out_not_fatal(
    observatory: _Observatory, modules: dict[str, Module], caplog: pytest.LogCaptureFixture
) -> None:
    # Another module's account (an owner: it cannot be banned) took and registered the name
    # 'weather' before the weather module ever started.
    holder = observatory.module("holder")
    await asyncio.wait_for(holder.open(), 20)
    weather = observatory.module("weather")
    opening = asyncio.create_task(weather.open())
    try:
        await wait_for(lambda: "holds the name of module 'weather'" in caplog.text, 20)
        assert "cannot be removed" in caplog.text and "trying again in 1 s" in caplog.text
        await holder.close()  # gone, but the name stays registered to it: still waited out
        room = f"{ROOM}@conference.{DOMAIN}"
        message = f"the name 'weather' is reserved in room {room} for another account; trying again in"
        await wait_for(lambda: message in caplog.text, 20)
        assert not opening.done()  # no exit 2, no "broken": the module keeps trying
    finally:
        opening.cancel()
        await asyncio.gather(opening, return_exceptions=True)
        await weather.close()
        await holder.close()


async def test_modules_enter_a_destroyed_room_again(
    observatory: _Observatory, modules: dict[str, Module], caplog: pytest.LogCaptureFixture
) -> None:
    dome = observatory.module("dome")  # an owner destroys the room
    await asyncio.wait_for(dome.open(), 20)
    try:
        await wait_for(lambda: "dome" in modules["camera"].comm.clients, 20)
        await room_iq(dome.comm, ROOM_JID, "set", NS_OWNER, ET.Element(f"{{{NS_OWNER}}}destroy"))
        await wait_for(
            lambda: f"room {ROOM}@conference.{DOMAIN} was destroyed; entering it again" in caplog.text, 20
        )
        await wait_for(lambda: "roof" in modules["camera"].comm.clients, 20)
        await wait_for(lambda: "camera" in modules["roof"].comm.clients, 20)
        await wait_for(lambda: caplog.text.count(f"entered room {ROOM}@conference.{DOMAIN} again") == 3, 20)
    finally:
        await dome.close()


class _HolderComm(XmppComm):
    """An observatory account entering under another module's name."""

    @property
    def name(self) -> str:
        return "weather"
