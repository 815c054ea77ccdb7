"""The XMPP side hardened, on real Prosody servers set up by ``init_server`` as ``nightcrew server`` does.

* A squatter process holding a module's name is banned and the real module takes its name back.
* A members-only room: an account of the server that is not the observatory's cannot enter.
* TLS required (also on loopback), in-band registration refused, passwords in no output.
"""

from __future__ import annotations

import asyncio
import logging
import os
import re
import ssl
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from nightcrew.comm.xmpp import XmppComm
from nightcrew.errors import NightcrewError, RemoteError
from nightcrew.events import TestEvent
from nightcrew.modules import Module
from nightcrew.server import Account, init_server, start_server, stop_server
from nightcrew.testing.waiting import wait_for

from ..comm.xmpp_servers import free_port, require_command

DOMAIN = "observatory.test"
PASSWORD = "hardening-pass"
#: A password no other text contains, so that finding it anywhere means it leaked.
DISTINCTIVE = "Qx7-distinctive-Pa55-90210"
WRONG = "Wz3-wrong-Pa55-55190"
SQUATTER = Path(__file__).with_name("squatter.py")


class _Server:
    def __init__(self, directory: Path, port: int) -> None:
        self.directory, self.port = directory, port
        self.ca_file = str(directory / "certs" / f"{DOMAIN}.crt")

    def comm(self, name: str, room: str, password: str = PASSWORD) -> XmppComm:
        return XmppComm(
            f"{name}@{DOMAIN}", password, server=f"127.0.0.1:{self.port}", room=room, ca_file=self.ca_file,
            require_tls=True,
        )  # fmt: skip


def _server(directory: Path, *, members_only: bool, require_tls: bool | None) -> Iterator[_Server]:
    require_command("prosody", "prosody")
    port = free_port()
    accounts = [Account(n, DOMAIN, PASSWORD) for n in ("weather", "listener", "intruder")]
    accounts.append(Account("operator", DOMAIN, DISTINCTIVE))
    owners = [f"{n}@{DOMAIN}" for n in ("weather", "listener", "operator")]
    init_server(
        directory, accounts, host="127.0.0.1", port=port, domains=[DOMAIN], room_owners=owners,
        members_only=members_only, require_tls=require_tls,
    )  # fmt: skip
    start_server(directory)
    try:
        yield _Server(directory, port)
    finally:
        stop_server(directory)


@pytest.fixture(scope="module")
def open_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[_Server]:
    """Rooms any account may enter, owned by the observatory's accounts."""
    yield from _server(tmp_path_factory.mktemp("open"), members_only=False, require_tls=None)


@pytest.fixture(scope="module")
def hardened_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[_Server]:
    """The production set-up: members-only rooms, TLS required, registration off."""
    yield from _server(tmp_path_factory.mktemp("hardened"), members_only=True, require_tls=True)


async def _open(comm: XmppComm) -> Module:
    module = Module(comm=comm)
    await module.open()
    return module


@pytest.mark.xmpp
async def test_squatted_name_is_taken_back(open_server: _Server, caplog: pytest.LogCaptureFixture) -> None:
    room = f"squat@conference.{DOMAIN}"
    listener = await _open(open_server.comm("listener", room))
    squatter = await asyncio.create_subprocess_exec(
        sys.executable, str(SQUATTER), f"intruder@{DOMAIN}", PASSWORD, "127.0.0.1", str(open_server.port),
        room, "weather", open_server.ca_file, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )  # fmt: skip
    weather = None
    try:
        assert squatter.stdout is not None
        assert await asyncio.wait_for(squatter.stdout.readline(), 60) == b"joined\n"
        await wait_for(lambda: "took the name of module 'weather'" in caplog.text, 20)
        assert "weather" not in listener.comm.clients

        weather = await _open(open_server.comm("weather", room))  # no nickname conflict: taken back
        await wait_for(lambda: "weather" in listener.comm.clients, 20)
        assert listener.comm._sender_account("weather") == "weather"
        assert f"took back the name 'weather' in room {room} from intruder@{DOMAIN}" in caplog.text
        assert await asyncio.wait_for(squatter.stdout.readline(), 60) == b"removed 110 301\n"
        await asyncio.wait_for(squatter.wait(), 60)
        assert squatter.returncode == 0
        comeback = open_server.comm("intruder", room)  # the banned account cannot come back at all
        with pytest.raises(RemoteError, match="forbidden"):
            await comeback.open()
        await comeback.close()
    finally:
        if squatter.returncode is None:
            squatter.kill()
            await squatter.wait()
        for module in (weather, listener):
            if module is not None:
                await module.close()


@pytest.mark.xmpp
async def test_account_outside_the_member_list_cannot_enter(hardened_server: _Server) -> None:
    room = f"members@conference.{DOMAIN}"
    listener = await _open(hardened_server.comm("listener", room))
    weather = await _open(hardened_server.comm("weather", room))
    heard: list[str] = []

    async def on_event(event: TestEvent, sender: str) -> None:
        heard.append(sender)

    try:
        await listener.comm.register_event(TestEvent, on_event)
        for where in (room, f"elsewhere@conference.{DOMAIN}"):  # its own room cannot be made either
            intruder = hardened_server.comm("intruder", where)
            with pytest.raises(RemoteError, match=f"cannot enter room {where}") as refused:
                await intruder.open()
            await intruder.close()
            assert "registration-required" in str(refused.value) or "not-allowed" in str(refused.value)
        assert "intruder" not in listener.comm.clients
        await weather.comm.send_event(TestEvent(message="members only"))
        await wait_for(lambda: heard == ["weather"], 20)
    finally:
        await weather.close()
        await listener.close()


class _Impostor(XmppComm):
    """An observatory account (a room owner) entering under another module's name."""

    def __init__(self, *args: Any, squatted: str, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._squatted = squatted

    @property
    def name(self) -> str:
        return self._squatted


@pytest.mark.xmpp
async def test_a_reserved_name_is_refused_to_any_other_account(
    hardened_server: _Server, caplog: pytest.LogCaptureFixture
) -> None:
    room = f"reserved@conference.{DOMAIN}"
    weather = await _open(hardened_server.comm("weather", room))  # enters and reserves its name
    await weather.close()
    impostor = _Impostor(
        f"operator@{DOMAIN}", DISTINCTIVE, server=f"127.0.0.1:{hardened_server.port}", room=room,
        ca_file=hardened_server.ca_file, squatted="weather",
    )  # fmt: skip
    opening = asyncio.create_task(impostor.open())  # waits, saying why, as a held name is waited out
    message = f"the name 'weather' is reserved in room {room} for another account; trying again in"
    await wait_for(lambda: message in caplog.text, 20)
    opening.cancel()
    await asyncio.gather(opening, return_exceptions=True)
    await impostor.close()
    weather = await _open(hardened_server.comm("weather", room))  # while the real module still enters
    listener = await _open(hardened_server.comm("listener", room))
    try:
        assert listener.comm.clients == ["weather"]  # the impostor left no passing name behind
    finally:
        await listener.close()
        await weather.close()


async def _read_until(reader: asyncio.StreamReader, pattern: str) -> str:
    text = ""
    async with asyncio.timeout(20):
        while not re.search(pattern, text):
            chunk = await reader.read(4096)
            assert chunk, f"connection closed; got {text!r}"
            text += chunk.decode()
    return text


def _stream_header() -> bytes:
    return (
        f"<?xml version='1.0'?><stream:stream to='{DOMAIN}' version='1.0' xmlns='jabber:client' "
        "xmlns:stream='http://etherx.jabber.org/streams'>"
    ).encode()


@pytest.mark.xmpp
async def test_tls_is_required_and_registration_refused(hardened_server: _Server) -> None:
    reader, writer = await asyncio.open_connection("127.0.0.1", hardened_server.port)
    try:
        writer.write(_stream_header())
        features = await _read_until(reader, "</stream:features>")
        assert re.search(r"<starttls[^>]*>\s*<required\s*/>", features), features
        assert "<mechanisms" not in features  # no login before TLS
        writer.write(b"<starttls xmlns='urn:ietf:params:xml:ns:xmpp-tls'/>")
        await _read_until(reader, "<proceed")
        context = ssl.create_default_context(cafile=hardened_server.ca_file)
        await writer.start_tls(context, server_hostname=DOMAIN)
        writer.write(_stream_header())
        features = await _read_until(reader, "</stream:features>")
        assert "SCRAM-SHA-1" in features and "iq-register" not in features
        writer.write(
            b"<iq type='set' id='reg1'><query xmlns='jabber:iq:register'>"
            b"<username>newcomer</username><password>x-newcomer-1</password></query></iq>"
        )
        reply = await _read_until(reader, r"id=.reg1.[^>]*>.*?</iq>|</stream:stream>")
        assert "type='error'" in reply or 'type="error"' in reply or "</stream:stream>" in reply, reply
    finally:
        writer.close()
    newcomer = XmppComm(
        f"newcomer@{DOMAIN}", "x-newcomer-1", server=f"127.0.0.1:{hardened_server.port}",
        ca_file=hardened_server.ca_file,
    )  # fmt: skip
    with pytest.raises(NightcrewError, match="login refused"):
        await newcomer.open()
    await newcomer.close()


@pytest.mark.xmpp
async def test_passwords_appear_in_no_output(
    hardened_server: _Server,
    tmp_path: Path,
    caplog: pytest.LogCaptureFixture,
    capfd: pytest.CaptureFixture[str],
) -> None:
    caplog.set_level(logging.DEBUG)
    shown: list[str] = []
    for password in (DISTINCTIVE, WRONG):  # a succeeding and a failing login, in this process
        comm = hardened_server.comm("operator", f"pw@conference.{DOMAIN}", password)
        try:
            await comm.open()
        except NightcrewError as exc:
            shown += [str(exc), repr(exc)]
        await comm.close()
    assert "login refused" in " ".join(shown)
    # ... and through the command line, with --debug, as separate processes
    comm_file = tmp_path / "operator.yaml"
    comm_file.write_text(
        f"class: nightcrew.comm.xmpp.XmppComm\njid: operator@{DOMAIN}\npassword: ${{OPERATOR_PASSWORD}}\n"
        f"server: 127.0.0.1:{hardened_server.port}\nca_file: {hardened_server.ca_file}\nrequire_tls: true\n"
        f"room: pw@conference.{DOMAIN}\n"
    )
    codes = []
    for password in (DISTINCTIVE, WRONG):
        command = [str(Path(sys.executable).with_name("nightcrew")), "--debug", "modules"]
        process = await asyncio.create_subprocess_exec(
            *command, "--comm", str(comm_file), env={**os.environ, "OPERATOR_PASSWORD": password},
            stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        )  # fmt: skip
        out, err = await asyncio.wait_for(process.communicate(), 120)
        codes.append(process.returncode)
        shown += [out.decode(), err.decode()]
    assert codes == [0, 1], shown[-4:]
    assert "login refused" in shown[-1]
    captured = capfd.readouterr()
    server_log = (hardened_server.directory / "prosody.log").read_text()
    everything = "\n".join([*shown, caplog.text, captured.out, captured.err, server_log])
    assert "DEBUG" in caplog.text or "SEND" in everything  # the debug output was there to be searched
    assert DISTINCTIVE not in everything and WRONG not in everything
