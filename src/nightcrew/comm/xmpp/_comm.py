"""XmppComm: modules in separate processes or machines, talking through an XMPP server.

The protocol is documented in docs/protocol.md; this class only wires the pieces together:
:class:`~nightcrew.comm.xmpp._connection.XmppConnection` (session, reconnects),
:class:`~nightcrew.comm.xmpp._rpc.RpcChannel` (calls) and
:class:`~nightcrew.comm.xmpp._room.Room` (presence, discovery, events).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Literal

from nightcrew.comm.base import Comm, PendingCall
from nightcrew.comm.xmpp._settings import DEFAULT_RESOURCE, XmppSettings
from nightcrew.config import DataPath, InputPath
from nightcrew.errors import ConfigError, RemoteError
from nightcrew.interfaces.base import interface_by_name
from nightcrew.interfaces.quantities import Period, Timeout
from nightcrew.security import Policy

if TYPE_CHECKING:
    from nightcrew.comm.xmpp._connection import XmppConnection
    from nightcrew.comm.xmpp._pyobs import PyobsPeer, PyobsPeers
    from nightcrew.comm.xmpp._room import Room
    from nightcrew.comm.xmpp._rpc import RpcChannel

__all__ = ["INTERFACE_FEATURE", "XmppComm"]

log = logging.getLogger(__name__)

#: disco#info feature per served interface: ``urn:nightcrew:interface:ICamera:1`` (name, version).
INTERFACE_FEATURE = "urn:nightcrew:interface:"
_DISCO_TIMEOUT = 5.0
DIALECTS = ("nightcrew", "pyobs")
#: pyobs addresses a peer as ``name@domain/<its own resource>``, ``pyobs`` unless configured.
PYOBS_RESOURCE = "pyobs"


class XmppComm(Comm):
    """Comm over an XMPP server; the module's name is the JID's local part.

    Args:
        jid: The module's account, ``camera@observatory.local`` (a resource is optional).
        password: Its password (use ``${CAMERA_PASSWORD}`` in YAML).
        server: ``host[:port]`` of the server; the JID's domain and 5222 by default.
        room: The room all modules meet in: a name (on ``conference.<domain>``) or a full JID.
        require_tls: Refuse to log in without TLS; by default required unless the server is on
            loopback.
        verify_tls: Check the server's certificate (turn off only for testing).
        ca_file: A CA or self-signed certificate to trust (``nightcrew server init`` writes one).
        connect_timeout: Seconds to wait for the first session before giving up.
        ping_interval: Wall seconds between pings to the server (XEP-0199); ``null`` for none.
        ping_timeout: Wall seconds a ping may go unanswered: then the link counts as dead and the
            module reconnects (a silent link is noticed within interval + timeout).
        rpc_grace: Wall seconds added to every announced timeout for network latency.
        policy: The access policy file; callers are identified by their authenticated account
            (the JID's local part on this domain, the bare JID otherwise). Without one the module
            refuses every state-changing call; ``open`` lets every account call everything (warned
            at every start).
        audit: The audit trail file.
        dialect: ``pyobs`` makes pyobs-core 2.x modules peers too (docs/pyobs.md): the module
            also announces itself by presence, offers its interfaces and events the pyobs way and
            calls pyobs modules in their value format; its resource defaults to ``pyobs``.
    """

    network = True

    def __init__(
        self,
        jid: str,
        password: str,
        *,
        server: str | None = None,
        room: str = "nightcrew",
        require_tls: bool | None = None,
        verify_tls: bool = True,
        ca_file: InputPath | None = None,
        connect_timeout: Timeout = 10.0,
        ping_interval: Period | None = 10.0,
        ping_timeout: Timeout = 10.0,
        rpc_grace: float = 1.0,
        policy: InputPath | Literal["open"] | Policy | None = None,
        audit: DataPath | None = None,
        dialect: str = "nightcrew",
    ) -> None:
        super().__init__(rpc_grace=rpc_grace, policy=policy, audit=audit)
        if dialect not in DIALECTS:
            raise ConfigError(f"unknown dialect '{dialect}' (known: {', '.join(DIALECTS)})", key="dialect")
        self._dialect = dialect
        self._settings = XmppSettings.from_options(
            jid,
            password,
            resource=PYOBS_RESOURCE if dialect == "pyobs" else DEFAULT_RESOURCE,
            room=room,
            server=server,
            require_tls=require_tls,
            verify_tls=verify_tls,
            ca_file=ca_file,
            connect_timeout=connect_timeout,
            ping_interval=ping_interval,
            ping_timeout=ping_timeout,
        )
        self._connection: XmppConnection | None = None
        self._rpc: RpcChannel | None = None
        self._room: Room | None = None
        self._pyobs: PyobsPeers | None = None

    @property
    def name(self) -> str:
        return self._settings.local

    @property
    def jid(self) -> str:
        """The full JID of this module's session."""
        return self._settings.full_jid

    @property
    def clients(self) -> list[str]:
        room = self._room.occupants if self._room is not None else []
        pyobs = [n for n in self._pyobs.names if n not in room] if self._pyobs is not None else []
        return room + pyobs

    @property
    def connected(self) -> bool:
        """Whether a session with the server is up now (False while reconnecting)."""
        return self._connection is not None and self._connection.online

    def advertise_state(self, state: str) -> None:
        """Publish the module's state in its room presence (``<status>`` and ``<module state=…>``)."""
        if self._room is not None:
            self._room.advertise_state(state)
        if self._pyobs is not None:
            self._pyobs.advertise_state(state)

    def presence_state(self, client: str) -> str | None:
        if self._pyobs is None or self._pyobs_peer(client) is None:
            return None  # a room occupant answers get_state itself
        return self._pyobs.state(client)

    async def settle(self) -> None:
        if self._pyobs is not None:
            await self._pyobs.settled()

    # --- transport hooks -----------------------------------------------------------------------

    async def _open_transport(self) -> None:
        # slixmpp is imported only when a module really goes on the network.
        from nightcrew.comm.xmpp._connection import XmppConnection
        from nightcrew.comm.xmpp._room import Room
        from nightcrew.comm.xmpp._rpc import RpcChannel

        connection = XmppConnection(
            self._settings,
            on_session=self._on_session,
            on_lost=self._on_lost,
            features=self._features(self.served_interfaces),
            features_for=self._features_for if self.policy is not None else None,
            on_fatal=self._report_fatal,
            plugins=("xep_0060",) if self._dialect == "pyobs" else (),
        )
        self._rpc = RpcChannel(
            connection,
            serve=self._serve_remote,
            spawn=self._spawn,
            pyobs_caller=lambda jid: self._pyobs is not None and self._pyobs.is_peer(jid),
        )
        self._room = Room(
            connection,
            self._settings.room_jid,
            self.name,
            on_online=self._client_online,
            on_offline=self._on_client_offline,
            on_event=self._deliver_event,
            domain=self._settings.domain,
            members=self._observatory_accounts(),
        )
        if self._dialect == "pyobs":
            from nightcrew.comm.xmpp._pyobs import PyobsPeers

            self._pyobs = PyobsPeers(
                connection,
                name=self.name,
                domain=self._settings.domain,
                features=self._features(self.served_interfaces),
                interfaces=self.served_interfaces,
                on_online=self._client_online,
                on_offline=self._on_client_offline,
                deliver=self._deliver_event,
                wants=lambda event: bool(self._handlers.get(event)),
                spawn=self._spawn,
            )
        self._connection = connection
        try:
            await connection.open()
        except BaseException:
            await connection.close()
            raise

    async def _close_transport(self) -> None:
        if self._room is not None:
            await self._room.close()
        if self._connection is not None:
            await self._connection.close()
        if self._rpc is not None:
            self._rpc.fail_all("comm closed")

    async def _fetch_interface_names(self, client: str) -> list[str]:
        peer = self._pyobs_peer(client)
        if peer is not None:
            return list(peer.interfaces)
        jid = self._require_room().jid_of(client)
        from slixmpp.exceptions import IqError, IqTimeout

        disco: Any = self._require_connection().client.plugin["xep_0030"]
        try:
            info = await disco.get_info(jid=jid, local=False, timeout=_DISCO_TIMEOUT)
        except (IqError, IqTimeout) as exc:
            raise RemoteError(f"interface discovery failed: {type(exc).__name__}", module=client) from None
        return _interface_names(info["disco_info"]["features"], client)

    async def _send_call(self, client: str, method: str, args: list[Any], call: PendingCall) -> None:
        peer = self._pyobs_peer(client)
        if peer is not None:
            self._require_rpc().call(peer.jid, client, method, args, call, pyobs=True)
            return
        jid = self._require_room().jid_of(client)
        self._require_rpc().call(jid, client, method, args, call)

    async def _publish_event(self, name: str, payload: dict[str, Any], acting: str | None = None) -> None:
        try:
            self._require_room().publish(name, payload, acting)
            if self._pyobs is not None:
                self._pyobs.publish(name, payload)
        except RemoteError:
            # Events are fire and forget; while reconnecting there is nobody to tell.
            log.debug("%s dropped: not connected", name)

    async def _subscribe_events(self, name: str) -> None:
        # Every event reaches every room occupant; Comm._deliver_event keeps the registered ones.
        if self._pyobs is not None:
            self._pyobs.subscribe(name)

    def _observatory_accounts(self) -> list[str]:
        """Bare JIDs of the policy's other accounts (acting identities left out): room members."""
        if self.policy is None:
            return []
        own = self._settings.bare_jid.lower()
        jids = {
            account if "@" in account else f"{account}@{self._settings.domain}"
            for account in self.policy.accounts
            if ":" not in account
        }
        return sorted(jid for jid in jids if jid.lower() != own)

    # --- glue ----------------------------------------------------------------------------------

    def _features_for(self, jid: str) -> list[str]:
        """The disco features this module shows the entity ``jid``: only interfaces it may call."""
        return self._features(self.served_interfaces_for(self._account_of(jid)))

    @staticmethod
    def _features(interfaces: list[str]) -> list[str]:
        features = ["jabber:iq:rpc", "urn:nightcrew:rpc:timeout", "urn:nightcrew:event"]
        for name in interfaces:
            interface = interface_by_name(name)
            features.append(f"{INTERFACE_FEATURE}{name}:{interface.version if interface else 1}")
        return features

    async def _on_session(self) -> None:
        await self._require_room().join()
        if self._pyobs is not None:
            await self._pyobs.on_session()

    async def _serve_remote(
        self, method: str, args: list[Any], announce: Callable[[float], None], jid: str, acting: str | None
    ) -> Any:
        return await self._serve_call(method, args, announce, self._account_of(jid), acting)

    def _sender_account(self, sender: str) -> str:
        # The room nickname is chosen by the occupant; its real JID is what the server authenticated.
        peer = self._pyobs_peer(sender)
        if peer is not None:
            return self._account_of(peer.jid)
        try:
            return self._account_of(self._require_room().jid_of(sender))
        except RemoteError:
            return f"{sender} (unknown)"

    def _account_of(self, jid: str) -> str:
        """The caller's account as the server authenticated it: not its room nickname."""
        bare = jid.partition("/")[0].lower()
        local, _, domain = bare.rpartition("@")
        return local if local and domain == self._settings.domain else bare

    def _on_lost(self) -> None:
        log.warning("%s lost its connection to the XMPP server; reconnecting", self.name)
        self._require_rpc().fail_all("connection to the XMPP server lost during the call")
        self._require_room().lost()
        if self._pyobs is not None:
            self._pyobs.lost()

    def _on_client_offline(self, client: str) -> None:
        self._require_rpc().fail_calls_to(client)
        self._client_offline(client)

    def _pyobs_peer(self, client: str) -> PyobsPeer | None:
        """The pyobs peer called ``client`` (a room occupant of that name takes precedence)."""
        if self._pyobs is None or (self._room is not None and client in self._room.occupants):
            return None
        return self._pyobs.peer(client)

    def _require_connection(self) -> XmppConnection:
        if self._connection is None:
            raise RemoteError("comm is not open")
        return self._connection

    def _require_room(self) -> Room:
        if self._room is None:
            raise RemoteError("comm is not open")
        return self._room

    def _require_rpc(self) -> RpcChannel:
        if self._rpc is None:
            raise RemoteError("comm is not open")
        return self._rpc


def _interface_names(features: list[str], client: str) -> list[str]:
    """Interface names from disco features; a version unlike ours is left out (incompatible)."""
    names = []
    for feature in features:
        if not feature.startswith(INTERFACE_FEATURE):
            continue
        name, _, version = feature[len(INTERFACE_FEATURE) :].partition(":")
        known = interface_by_name(name)
        if known is not None and version and version != str(known.version):
            log.warning("%s offers %s v%s, this process knows v%s", client, name, version, known.version)
            continue
        names.append(name)
    return names
