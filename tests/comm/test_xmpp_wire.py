"""docs/protocol.md is enough: a plain XMPP client, knowing nothing of nightcrew's code, takes part.

The client here is bare slixmpp fed with stanzas written as in the protocol document — standing in
for a program in another language.
"""

from __future__ import annotations

import asyncio
import xml.etree.ElementTree as ET
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest
import slixmpp
from slixmpp.xmlstream.handler import Callback
from slixmpp.xmlstream.matcher import MatchXPath

from nightcrew.events import TestEvent
from nightcrew.testing import wait_for

from .conftest import Network
from .sample import Calculator, Listener

pytestmark = pytest.mark.xmpp

RPC = "jabber:iq:rpc"
MUC_USER = "http://jabber.org/protocol/muc#user"


class PlainClient:
    """Logs in, joins the room, and records every message and room presence it gets."""

    def __init__(self, jid: str, password: str, ca_file: str) -> None:
        self.xmpp = slixmpp.ClientXMPP(jid, password)
        self.xmpp.enable_direct_tls = False
        self.xmpp.ca_certs = Path(ca_file)
        self.messages: asyncio.Queue[ET.Element] = asyncio.Queue()
        self.occupants: dict[str, str] = {}  # nick -> real JID
        self.states: dict[str, str] = {}  # nick -> module state last announced in presence
        self.xmpp.register_handler(Callback("m", MatchXPath("{jabber:client}message"), self._message))
        self.xmpp.register_handler(Callback("p", MatchXPath("{jabber:client}presence"), self._presence))

    def _message(self, stanza: Any) -> None:
        self.messages.put_nowait(stanza.xml)

    def _presence(self, stanza: Any) -> None:
        item = stanza.xml.find(f"{{{MUC_USER}}}x/{{{MUC_USER}}}item")
        if item is not None and item.get("jid"):
            self.occupants[stanza["from"].resource] = item.get("jid")
        module = stanza.xml.find("{urn:nightcrew:module}module")
        if module is not None:
            self.states[stanza["from"].resource] = module.get("state", "")

    async def connect(self, host: str, port: int) -> None:
        started: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        self.xmpp.add_event_handler("session_start", lambda _: started.set_result(None))
        self.xmpp.connect(host, port)
        await asyncio.wait_for(started, 10)


@pytest.fixture
async def plain_client(prosody_network: Network) -> AsyncIterator[PlainClient]:
    server = prosody_network.server
    assert server is not None and server.ca_file is not None
    account = server.account("operator")
    client = PlainClient(f"{account.jid}/plain", account.password, server.ca_file)
    host, port = server.address.split(":")
    await client.connect(host, int(port))
    room = f"{prosody_network.room}@conference.{account.domain}"
    client.xmpp.send_raw(
        f"<presence to='{room}/operator'>"
        "<x xmlns='http://jabber.org/protocol/muc'><history maxstanzas='0'/></x></presence>"
    )
    yield client
    await client.xmpp.disconnect(wait=1)


async def test_a_plain_client_calls_a_module_with_the_documented_stanzas(
    prosody_network: Network, plain_client: PlainClient
) -> None:
    await prosody_network.start(Calculator, "calc")
    await wait_for(lambda: "calc" in plain_client.occupants, 5.0)
    calc_jid = plain_client.occupants["calc"]

    disco: Any = plain_client.xmpp.make_iq_get(ito=calc_jid)
    disco.xml.append(ET.fromstring("<query xmlns='http://jabber.org/protocol/disco#info'/>"))
    info = await disco.send(timeout=5)
    features = {f.get("var") for f in info.xml.iter("{http://jabber.org/protocol/disco#info}feature")}
    assert {"jabber:iq:rpc", "urn:nightcrew:interface:ICalculator:1"} <= features

    iq: Any = plain_client.xmpp.make_iq_set(ito=calc_jid)
    iq.xml.append(
        ET.fromstring(
            "<query xmlns='jabber:iq:rpc'><methodCall><methodName>add</methodName><params>"
            "<param><value><int>2</int></value></param><param><value><double>0.5</double></value></param>"
            "</params></methodCall></query>"
        )
    )
    reply = await iq.send(timeout=5)
    value = reply.xml.find(f"{{{RPC}}}query/{{{RPC}}}methodResponse/{{{RPC}}}params/{{{RPC}}}param")
    assert value is not None and ET.tostring(value[0][0]).endswith(b">2.5</ns0:double>")

    # wait(seconds) declares a timeout of 100 x seconds: announced at once, before the result.
    slow: Any = plain_client.xmpp.make_iq_set(ito=calc_jid)
    slow.xml.append(
        ET.fromstring(
            "<query xmlns='jabber:iq:rpc'><methodCall><methodName>wait</methodName><params>"
            "<param><value><double>0.2</double></value></param></params></methodCall></query>"
        )
    )
    pending = asyncio.ensure_future(slow.send(timeout=5))
    announcement = None
    while announcement is None:  # skip the room subject and log events
        message = await asyncio.wait_for(plain_client.messages.get(), 5)
        announcement = message.find("{urn:nightcrew:rpc:timeout}timeout")
    assert not pending.done(), "the announcement comes before the result"
    await pending
    # add() has the default timeout, so it announced nothing: the first announcement is wait()'s.
    assert announcement.get("id") == slow["id"] and float(announcement.get("seconds", "")) == 20.0


async def test_a_plain_client_sends_an_event_a_module_receives(
    prosody_network: Network, plain_client: PlainClient
) -> None:
    listener = await prosody_network.start(Listener, "listener")
    await wait_for(lambda: "listener" in plain_client.occupants, 5.0)
    room = f"{prosody_network.room}@conference.observatory.test"
    plain_client.xmpp.send_raw(
        f"<message type='groupchat' to='{room}'>"
        "<event xmlns='urn:nightcrew:event' name='TestEvent'>{\"message\":\"hello\"}</event></message>"
    )
    await asyncio.wait_for(listener.arrived.wait(), 5)
    assert listener.received == [(TestEvent(message="hello"), "operator")]


async def test_module_state_changes_are_announced_in_presence(
    prosody_network: Network, plain_client: PlainClient
) -> None:
    calc = await prosody_network.start(Calculator, "calc")
    await wait_for(lambda: plain_client.states.get("calc") == "ready", 5.0)
    calc.set_error("lost the filter wheel")
    await wait_for(lambda: plain_client.states.get("calc") == "error", 5.0)
    await calc.reset_error()
    await wait_for(lambda: plain_client.states.get("calc") == "ready", 5.0)
