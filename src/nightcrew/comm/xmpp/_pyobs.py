"""The pyobs dialect of an XmppComm: pyobs-core 2.x modules as peers (docs/pyobs.md).

pyobs finds its peers by roster presence (the server's shared roster makes every account a
contact of every other), reads their interfaces from ``urn:pyobs:interface:<Name>:1`` disco
features, and sends events as PubSub items on ``pubsub.<domain>``, one node per sender and event,
``pyobs:event:<module>:<Event>:1``, holding ``{"type", "timestamp", "uuid", "data"}`` as JSON. A
comm in this dialect does all of that beside the room: it stays a full member of the nightcrew
room, announces itself by presence, answers disco with pyobs' features too, publishes its events
to PubSub as well and subscribes to the nodes of pyobs peers it has handlers for. Calls in pyobs'
value format are :class:`~nightcrew.comm.xmpp._rpc.RpcChannel`'s business.
"""

from __future__ import annotations

import asyncio
import logging
import uuid
import xml.etree.ElementTree as ET
from collections.abc import Callable, Coroutine
from dataclasses import dataclass, field
from typing import Any

from slixmpp.exceptions import IqError, IqTimeout

from nightcrew.comm.xmpp._connection import XmppConnection, split_jid
from nightcrew.comm.xmpp._pyobs_events import NS_PYOBS_EVENT, PYOBS_EVENTS, event_body, translate_event
from nightcrew.comm.xmpp._pyobs_states import STATE_INTERFACES, pyobs_state, state_namespace, state_node
from nightcrew.comm.xmpp._pyobs_values import state_element
from nightcrew.errors import RemoteError

__all__ = ["PyobsPeer", "PyobsPeers"]

log = logging.getLogger(__name__)

_C = "{jabber:client}"
NS_DISCO = "http://jabber.org/protocol/disco#info"
NS_PUBSUB_EVENT = "http://jabber.org/protocol/pubsub#event"
NS_PUBSUB = "http://jabber.org/protocol/pubsub"
INTERFACE_PREFIX = "urn:pyobs:interface:"
EVENT_PREFIX = "urn:pyobs:event:"
_IQ_TIMEOUT = 5.0
_SUBSCRIBE_ATTEMPTS = 6


@dataclass
class PyobsPeer:
    """A pyobs module online: its full JID, interface names and the events it says it sends."""

    jid: str
    interfaces: list[str]
    sent_events: set[str] = field(default_factory=set)


class PyobsPeers:
    """Presence, discovery and events of pyobs peers, on an open :class:`XmppConnection`.

    Args:
        connection: The comm's connection (handlers are added here, before it opens).
        name: This module's name (local part of its JID).
        features: The disco features this module offers the nightcrew way.
        interfaces: Names of the interfaces it serves (offered to pyobs under the same names).
        on_online, on_offline: A pyobs peer came or went (its module name).
        deliver: ``deliver(event_name, wire_fields, sender)`` for an event from a pyobs peer.
        wants: Whether this module has handlers for an event name.
        spawn: Runs a background coroutine owned by the comm.
    """

    def __init__(
        self,
        connection: XmppConnection,
        *,
        name: str,
        domain: str,
        features: list[str],
        interfaces: list[str],
        on_online: Callable[[str], None],
        on_offline: Callable[[str], None],
        deliver: Callable[[str, dict[str, Any], str], None],
        wants: Callable[[str], bool],
        spawn: Callable[[Coroutine[Any, Any, Any], str], None],
    ) -> None:
        self._connection = connection
        self._name = name
        self._service = f"pubsub.{domain}"
        self._features = [*features, *(f"{INTERFACE_PREFIX}{i}:1" for i in interfaces)]
        self._features += [f"{EVENT_PREFIX}{e}:1" for e in sorted(PYOBS_EVENTS)]
        #: pyobs interfaces whose state this module publishes (docs/pyobs.md, "States").
        self._states = sorted({i for i in STATE_INTERFACES.values() if i in interfaces})
        self._features += [state_namespace(i) for i in self._states]
        self._on_online = on_online
        self._on_offline = on_offline
        self._deliver = deliver
        self._wants = wants
        self._spawn = spawn
        self._peers: dict[str, PyobsPeer] = {}
        self._probing: set[str] = set()  # full JIDs whose disco is under way
        self._shows: dict[str, str] = {}  # full JID → its presence <show> ("" when none)
        self._probed = asyncio.Event()  # set whenever no disco is under way
        self._probed.set()
        self._subscribed: set[str] = set()
        self._show = ""
        connection.add_handler("pyobs presence", f"{_C}presence", self._on_presence)
        connection.add_handler("pyobs disco", f"{_C}iq/{{{NS_DISCO}}}query", self._on_disco)
        connection.add_handler("pyobs event", f"{_C}message/{{{NS_PUBSUB_EVENT}}}event", self._on_pubsub)

    @property
    def names(self) -> list[str]:
        return list(self._peers)

    def peer(self, name: str) -> PyobsPeer | None:
        return self._peers.get(name)

    def state(self, name: str) -> str | None:
        """The module state pyobs peer ``name`` shows by presence (as pyobs reads it), or None."""
        peer = self._peers.get(name)
        if peer is None:
            return None
        return {"dnd": "error", "away": "local"}.get(self._shows.get(peer.jid, ""), "ready")

    def is_peer(self, jid: str) -> bool:
        """Whether the full JID ``jid`` is a pyobs module's session."""
        peer = self._peers.get(split_jid(jid)[0].partition("@")[0])
        return peer is not None and peer.jid == jid

    # --- session -------------------------------------------------------------------------------

    async def on_session(self) -> None:
        """After every session start: make our event nodes, then announce ourselves by presence."""
        pubsub: Any = self._connection.client.plugin["xep_0060"]
        # Nodes exist before pyobs peers see us, so their first subscription attempt succeeds.
        nodes = [self._node(self._name, e) for e in sorted(PYOBS_EVENTS)]
        for node in [*nodes, *(state_node(self._name, i) for i in self._states)]:
            try:
                await pubsub.create_node(self._service, node, timeout=_IQ_TIMEOUT)
            except IqError:
                pass  # conflict: made in an earlier session
            except IqTimeout:
                log.warning("the PubSub service %s does not answer; pyobs will not see events", self._service)
                break
        self._send_presence()

    async def settled(self) -> None:
        """Wait until the pyobs modules online when this session began are discovered (bounded).

        The server answers our initial presence with the presence of every contact online before
        it answers anything we send later: one ping's round trip, and every such presence is here.
        Each discovery started for them ends within its own timeout.
        """
        ping: Any = self._connection.client.plugin["xep_0199"]
        try:
            await ping.ping(timeout=_IQ_TIMEOUT)
        except (IqError, IqTimeout):
            log.debug("the server did not answer a ping; pyobs peers may be missing")
        try:  # each discovery ends within _IQ_TIMEOUT; new presences may start more meanwhile
            await asyncio.wait_for(self._probed.wait(), 2 * _IQ_TIMEOUT)
        except TimeoutError:
            log.debug("pyobs discovery still under way: %s", ", ".join(sorted(self._probing)))

    def lost(self) -> None:
        """The session is gone: every pyobs peer is offline for us (presence comes again later)."""
        for name in list(self._peers):
            self._drop(name)
        self._shows.clear()
        self._probing.clear()
        self._probed.set()
        self._subscribed.clear()

    def advertise_state(self, state: str) -> None:
        """pyobs reads a module's state from presence ``<show>``: dnd = error, away = local."""
        self._show = "dnd" if state == "error" else ""
        if self._connection.online:
            self._send_presence()

    def _send_presence(self) -> None:
        children = [ET.Element(f"{_C}show")] if self._show else []
        if children:
            children[0].text = self._show
        stanza = ET.Element(f"{_C}presence")
        stanza.extend(children)
        self._connection.send(stanza)

    # --- presence and discovery ----------------------------------------------------------------

    def _on_presence(self, stanza: ET.Element) -> bool:
        jid = stanza.get("from", "")
        bare, resource = split_jid(jid)
        local, _, domain = bare.partition("@")
        if not resource or not local or local == self._name or domain.startswith("conference."):
            return False  # the room's (its own handler) or our own
        kind = stanza.get("type", "available")
        if kind == "available":
            self._shows[jid] = stanza.findtext(f"{_C}show") or ""
        if kind == "unavailable":
            self._shows.pop(jid, None)
            self._probing.discard(jid)  # gone before it answered: its discovery is moot
            peer = self._peers.get(local)
            if peer is not None and peer.jid == jid:
                self._drop(local)
        elif kind == "available" and local not in self._peers and jid not in self._probing:
            self._probing.add(jid)
            self._probed.clear()
            self._spawn(self._discover(local, jid), f"discover {local}")
        return False  # slixmpp may keep its roster view

    async def _discover(self, name: str, jid: str) -> None:
        disco: Any = self._connection.client.plugin["xep_0030"]
        try:
            info = await disco.get_info(jid=jid, local=False, timeout=_IQ_TIMEOUT)
        except (IqError, IqTimeout) as exc:
            if jid in self._probing:  # else it left meanwhile (a one-shot command): nothing to say
                log.warning("pyobs discovery of %s failed: %s", jid, type(exc).__name__)
            return
        except RemoteError:
            return  # the session ended meanwhile (the comm closed, or reconnects and asks again)
        finally:
            gone = jid not in self._probing
            self._probing.discard(jid)
            if not self._probing:
                self._probed.set()
        if gone:
            return
        query = info.xml.find(f"{{{NS_DISCO}}}query")
        features = (
            [f.get("var", "") for f in query.iter(f"{{{NS_DISCO}}}feature")] if query is not None else []
        )
        if any(f.startswith("urn:nightcrew:") for f in features):
            return  # a nightcrew module: we meet it in the room
        interfaces = [
            f[len(INTERFACE_PREFIX) :].rpartition(":")[0] for f in features if f.startswith(INTERFACE_PREFIX)
        ]
        if "IModule" not in interfaces:
            return  # pyobs ignores such clients (e.g. a GUI); so do we
        peer = PyobsPeer(jid, interfaces, _sent_events(query))
        self._peers[name] = peer
        log.info("pyobs module %s is online (%s)", name, ", ".join(interfaces))
        for event in peer.sent_events:
            if self._wants(event):
                self._spawn(self._subscribe(name, event), f"subscribe {name} {event}")
        self._on_online(name)

    def _drop(self, name: str) -> None:
        del self._peers[name]
        self._subscribed = {node for node in self._subscribed if not node.startswith(f"pyobs:event:{name}:")}
        self._on_offline(name)

    def _on_disco(self, stanza: ET.Element) -> bool:
        query = stanza.find(f"{{{NS_DISCO}}}query")
        if stanza.get("type") != "get" or query is None or query.get("node"):
            return False  # a reply (slixmpp waits for it), or a node we do not serve
        reply = ET.Element(f"{{{NS_DISCO}}}query")
        ET.SubElement(reply, f"{{{NS_DISCO}}}identity", category="client", type="bot")
        for var in [*self._features, NS_DISCO]:
            ET.SubElement(reply, f"{{{NS_DISCO}}}feature", var=var)
        # pyobs subscribes only to events a peer marks as sent (role="send").
        for event in sorted(PYOBS_EVENTS):
            ET.SubElement(reply, f"{{{EVENT_PREFIX}{event}:1}}event", name=event, role="send")
        try:
            answer = self._connection.stanza(
                "iq", stanza.get("from", ""), reply, id=stanza.get("id", ""), type="result"
            )
            self._connection.send(answer)
        except RemoteError:
            log.debug("disco answer to %s lost: not connected", stanza.get("from"))
        return True

    # --- events --------------------------------------------------------------------------------

    def publish(self, name: str, payload: dict[str, Any]) -> None:
        """Publish event ``name`` (if pyobs knows it) on our PubSub node, and the state it tells
        (if any) on the state node of its interface; fire and forget."""
        if name in PYOBS_EVENTS:
            event = ET.Element(f"{{{NS_PYOBS_EVENT}}}event")
            event.text = event_body(name, payload)
            self._publish_item(self._node(self._name, name), event)
        interface = STATE_INTERFACES.get(name)
        state = pyobs_state(name, payload) if interface in self._states else None
        if interface is not None and state is not None:
            namespace = state_namespace(interface)
            self._publish_item(state_node(self._name, interface), state_element(namespace, state, name))

    def _publish_item(self, node: str, payload: ET.Element) -> None:
        pubsub = ET.Element(f"{{{NS_PUBSUB}}}pubsub")
        publish = ET.SubElement(pubsub, f"{{{NS_PUBSUB}}}publish", node=node)
        ET.SubElement(publish, f"{{{NS_PUBSUB}}}item").append(payload)
        iq_id = f"pyobs-publish-{uuid.uuid4().hex[:12]}"
        self._connection.send(self._connection.stanza("iq", self._service, pubsub, id=iq_id, type="set"))

    def subscribe(self, name: str) -> None:
        """Start receiving event ``name`` from every pyobs peer online that sends it."""
        for peer_name, peer in self._peers.items():
            if name in peer.sent_events:
                self._spawn(self._subscribe(peer_name, name), f"subscribe {peer_name} {name}")

    async def _subscribe(self, peer: str, event: str) -> None:
        node = self._node(peer, event)
        if node in self._subscribed:
            return
        self._subscribed.add(node)
        pubsub: Any = self._connection.client.plugin["xep_0060"]
        for attempt in range(_SUBSCRIBE_ATTEMPTS):
            try:
                await pubsub.subscribe(self._service, node, timeout=_IQ_TIMEOUT)
                return
            except (IqError, IqTimeout) as exc:
                # The peer may not have made its node yet; it does on its first publish.
                log.debug("subscribing to %s failed (%s), attempt %d", node, type(exc).__name__, attempt + 1)
                await asyncio.sleep(0.2 * 2**attempt)
        self._subscribed.discard(node)
        log.warning("could not subscribe to %s from pyobs module %s (node %s)", event, peer, node)

    def _on_pubsub(self, stanza: ET.Element) -> bool:
        if stanza.get("from") != self._service:
            return False
        items = stanza.find(f"{{{NS_PUBSUB_EVENT}}}event/{{{NS_PUBSUB_EVENT}}}items")
        if items is None or stanza.find("{urn:xmpp:delay}delay") is not None:
            return True  # a retraction, or a stored item replayed: not news
        node = items.get("node", "")
        parts = node.split(":")
        if len(parts) != 5 or parts[:2] != ["pyobs", "event"] or parts[2] not in self._peers:
            return True
        sender, node_event = parts[2], parts[3]
        for payload in items.iter(f"{{{NS_PYOBS_EVENT}}}event"):
            translated = translate_event(payload.text or "", node_event, sender)
            if translated is not None:
                self._deliver(node_event, translated, sender)
        return True

    @staticmethod
    def _node(module: str, event: str) -> str:
        return f"pyobs:event:{module}:{event}:1"


def _sent_events(query: ET.Element | None) -> set[str]:
    """Events a pyobs peer's disco marks as sent: ``<event xmlns='urn:pyobs:event:X:1' role='send'>``."""
    sent = set()
    for element in query if query is not None else ():
        namespace, _, local = element.tag[1:].partition("}")
        if (
            local == "event"
            and namespace.startswith(EVENT_PREFIX)
            and "send" in element.get("role", "").split()
        ):
            sent.add(element.get("name") or namespace[len(EVENT_PREFIX) :].rpartition(":")[0])
    return sent
