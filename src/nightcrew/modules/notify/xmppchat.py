"""The XmppChat module: people talk to the observatory from their own XMPP accounts.

Any XMPP app on a phone or desktop will do: a person writes ordinary chat messages to the chat
module's account on the observatory's server (``nightcrew@observatory.local``) and gets replies
and notifications the same way. The session (TLS, SCRAM, reconnects) is the one XmppComm uses,
:class:`~nightcrew.comm.xmpp._connection.XmppConnection`. The person's account is the one the
server authenticated (the sender's bare JID), and each still logs in with ``/login SECRET``.

Example (``examples/notify/xmppchat.yaml``)::

    class: nightcrew.modules.notify.XmppChat
    jid: nightcrew@observatory.local
    password: ${CHAT_PASSWORD}
    users:
      alice@observatory.local: {account: alice, secret_hash: "scrypt$16384$8$1$..."}
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from datetime import UTC, datetime
from typing import TYPE_CHECKING, Any

from nightcrew.comm.xmpp import XmppSettings, parse_jid
from nightcrew.config import InputPath
from nightcrew.errors import ConfigError, RemoteError
from nightcrew.modules.notify._module import ChatModule
from nightcrew.modules.notify._users import users_from_config

if TYPE_CHECKING:
    from nightcrew.comm.xmpp._connection import XmppConnection

__all__ = ["XmppChat"]

log = logging.getLogger(__name__)

_CLIENT_NS = "{jabber:client}"
_DELAY = "{urn:xmpp:delay}delay"


def _bare_jid(key: Any) -> str:
    local, domain, _ = parse_jid(str(key)) if "@" in str(key) else ("", "", None)
    if not local:
        raise ConfigError(f"'{key}' is not a JID like alice@observatory.local", key=f"users.{key}")
    return f"{local.lower()}@{domain}"


class XmppChat(ChatModule):
    """Chat with people's own XMPP accounts.

    Args:
        jid: The chat module's own account (people write to it), e.g. ``nightcrew@observatory.local``.
        password: Its password (use ``${CHAT_PASSWORD}``).
        users: Bare JID → ``{account, secret_hash}`` (see ChatModule).
        server: ``host[:port]`` of the server; the JID's domain and 5222 by default.
        require_tls: Refuse to log in without TLS; required unless the server is on loopback.
        verify_tls: Check the server's certificate.
        ca_file: A CA or self-signed certificate to trust.
        connect_timeout: Seconds to wait for the session when the module opens.
        **kwargs: ChatModule options (log_level, events, rate_limit) and module options.
    """

    channel = "xmpp"

    def __init__(
        self,
        *,
        jid: str,
        password: str,
        users: dict[Any, Any],
        server: str | None = None,
        require_tls: bool | None = None,
        verify_tls: bool = True,
        ca_file: InputPath | None = None,
        connect_timeout: float = 10.0,
        **kwargs: Any,
    ) -> None:
        settings = XmppSettings.from_options(
            jid,
            password,
            resource="chat",
            room=None,  # no room: people are written to one by one
            server=server,
            require_tls=require_tls,
            verify_tls=verify_tls,
            ca_file=ca_file,
            connect_timeout=connect_timeout,
        )
        super().__init__(users=users_from_config(users, normalise=_bare_jid), **kwargs)
        self._settings = settings
        self._connection: XmppConnection | None = None

    @property
    def jid(self) -> str:
        """The chat account people write to."""
        return self._settings.bare_jid

    async def open(self) -> None:
        from nightcrew.comm.xmpp._connection import XmppConnection

        await super().open()
        connection = XmppConnection(
            self._settings, on_session=self._on_session, on_lost=_nothing, features=[]
        )
        connection.add_handler("chat", f"{_CLIENT_NS}message", self._on_message)
        self._connection = connection
        try:
            await connection.open()
        except BaseException:
            await self.close()
            raise

    async def close(self) -> None:
        await super().close()
        connection, self._connection = self._connection, None
        if connection is not None:
            await connection.close()

    async def _on_session(self) -> None:
        # Online for the people who added the account to their contacts (slixmpp answers their
        # subscription requests).
        if self._connection is not None:
            self._connection.client.send_presence()

    def _on_message(self, stanza: ET.Element) -> bool:
        if stanza.get("type", "normal") not in ("chat", "normal"):
            return False  # errors and groupchat: not a person talking to us
        body = stanza.find(f"{_CLIENT_NS}body")
        sender = stanza.get("from", "")
        if body is None or not body.text or not sender:
            return True  # typing notifications and the like
        bare = sender.partition("/")[0].lower()
        if bare == self._settings.bare_jid:
            return True
        self.received(bare, bare, body.text, age=_age(stanza))
        return True

    async def _send(self, address: str, text: str) -> None:
        connection = self._connection
        if connection is None or not connection.online:
            raise RemoteError("not connected to the XMPP server")
        body = ET.Element(f"{_CLIENT_NS}body")
        body.text = text
        connection.send(connection.stanza("message", address, body, type="chat"))


def _age(stanza: ET.Element) -> float:
    """Wall seconds since the message was sent: a server that kept it while we were offline marks
    it with a XEP-0203 delay (0 without one, or with one that cannot be read)."""
    delay = stanza.find(_DELAY)
    try:
        sent = datetime.fromisoformat(delay.get("stamp", "")) if delay is not None else None
    except ValueError:
        return 0.0
    if sent is None or sent.tzinfo is None:
        return 0.0
    return (datetime.now(UTC) - sent).total_seconds()


def _nothing() -> None:
    """Nothing is in flight when the session drops: the outboxes keep what waits."""
