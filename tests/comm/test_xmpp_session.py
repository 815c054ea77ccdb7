"""What only the XMPP transport has: logins, TLS, reconnects after a server restart."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.comm.xmpp import XmppAuthError, XmppComm
from nightcrew.errors import ConfigError, RemoteError
from nightcrew.events import TestEvent
from nightcrew.modules import Module
from nightcrew.server import Account, init_server, start_server, stop_server
from nightcrew.testing import wait_for

from .conftest import Network
from .sample import Calculator, ICalculator, ISlow, Listener
from .xmpp_servers import DOMAIN, PASSWORD, free_port, require_command

pytestmark = pytest.mark.xmpp


async def test_wrong_password_is_one_clear_error(xmpp_network: Network) -> None:
    server = xmpp_network.server
    assert server is not None
    server.account("calc")
    comm = XmppComm(f"calc@{DOMAIN}", "wrong", server=server.address, ca_file=server.ca_file)
    started = time.monotonic()
    with pytest.raises(XmppAuthError, match=r"calc@observatory.test: login refused \(wrong password"):
        await Module(comm=comm).open()
    assert time.monotonic() - started < 5  # no retry loop


async def test_unknown_account_is_one_clear_error(xmpp_network: Network) -> None:
    server = xmpp_network.server
    assert server is not None
    comm = XmppComm(f"nobody@{DOMAIN}", "whatever", server=server.address, ca_file=server.ca_file)
    with pytest.raises(XmppAuthError, match=r"nobody@observatory\.test: login refused"):
        await Module(comm=comm).open()


async def test_untrusted_certificate_is_refused(xmpp_network: Network) -> None:
    server = xmpp_network.server
    assert server is not None
    account = server.account("calc")
    comm = XmppComm(account.jid, account.password, server=server.address, connect_timeout=3)
    untrusted = r"certificate of 127\.0\.0\.1:\d+ is not trusted .*self-signed.*; see ca_file"
    with pytest.raises(RemoteError, match=untrusted):
        await Module(comm=comm).open()


def test_config_errors_are_found_when_the_comm_is_built() -> None:
    with pytest.raises(ConfigError, match="not a JID"):
        XmppComm("camera", "pw")
    with pytest.raises(ConfigError, match="not host:port"):
        XmppComm("camera@obs.local", "pw", server="a:b:c")
    with pytest.raises(ConfigError, match="TLS cannot be turned off"):
        XmppComm("camera@obs.local", "pw", server="192.0.2.1", require_tls=False)
    comm = XmppComm("camera@obs.local/dome", "pw")
    assert comm.name == "camera" and comm.jid == "camera@obs.local/dome"


async def test_modules_reconnect_after_a_server_restart(prosody_network: Network) -> None:
    # On Prosody only: it restarts in a fraction of a second (ejabberd needs ~7 s).
    xmpp_network = prosody_network
    server = xmpp_network.server
    assert server is not None
    calc = await xmpp_network.start(Calculator, "calc")
    listener = await xmpp_network.start(Listener, "listener")
    proxy = await listener.comm.proxy("calc", ICalculator)
    slow = await listener.comm.proxy("calc", ISlow)
    assert await proxy.add(1, 2) == 3.0
    in_flight = asyncio.ensure_future(slow.wait(30))  # announces 3000 s
    await asyncio.sleep(0.3)

    restarted = time.monotonic()
    await asyncio.to_thread(server.restart)
    with pytest.raises(RemoteError, match=r"went offline during the call|connection to the XMPP server lost"):
        await asyncio.wait_for(in_flight, 3)  # fails fast instead of hanging

    # every module is back within 10 s: in the room, calls through the old proxy, events
    await wait_for(lambda: "calc" in listener.comm.clients and "listener" in calc.comm.clients, 10)
    assert await proxy.add(2, 2) == 4.0
    assert time.monotonic() - restarted < 10
    await calc.comm.send_event(TestEvent(message="after restart"))
    await asyncio.wait_for(listener.arrived.wait(), 5)
    assert listener.received[-1] == (TestEvent(message="after restart"), "calc")


@pytest.fixture
def prosody_without_tls(tmp_path: Path) -> Iterator[str]:
    """A private Prosody on loopback that offers no TLS at all; yields its address."""
    require_command("prosody", "prosody")
    port = free_port()
    init_server(tmp_path, [Account("calc", DOMAIN, PASSWORD)], host="127.0.0.1", port=port, domains=[DOMAIN])
    config = tmp_path / "prosody.cfg.lua"
    text = config.read_text().replace('"tls"; ', "")
    config.write_text(text.replace('{ "s2s"; "offline" }', '{ "s2s"; "offline"; "tls" }'))
    start_server(tmp_path)
    try:
        yield f"127.0.0.1:{port}"
    finally:
        stop_server(tmp_path)


async def test_a_server_without_tls_is_refused_when_tls_is_required(prosody_without_tls: str) -> None:
    # Off loopback TLS is required by default (see the config test above); loopback can ask for it.
    strict = XmppComm(f"calc@{DOMAIN}", PASSWORD, server=prosody_without_tls, require_tls=True)
    with pytest.raises(XmppAuthError, match=r"login refused \(the server at 127\.0\.0\.1:\d+ offers no TLS"):
        await Module(comm=strict).open()
    # The same account logs in when TLS is not required: the refusal above was about TLS alone.
    relaxed = Module(comm=XmppComm(f"calc@{DOMAIN}", PASSWORD, server=prosody_without_tls, require_tls=False))
    await relaxed.open()
    await relaxed.close()
