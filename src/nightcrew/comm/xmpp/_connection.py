"""One XMPP session on slixmpp: connect, authenticate, keep reconnecting, send and receive XML.

This is the only file that knows slixmpp's life cycle. Its failures become nightcrew errors here:
a refused login is :class:`XmppAuthError` (no retry: a wrong password does not get better), an
unreachable server :class:`~nightcrew.errors.RemoteError`. After the first session, a lost
connection is retried every second or so until :meth:`close`; ``on_session`` runs after every
session start (join the room again), ``on_lost`` after every loss (fail calls in flight),
``on_fatal`` when the connection is lost for good (another session took over the account, or the
login is refused on a reconnect): the process should then end, not stay alive and offline.
A :class:`~nightcrew.comm.xmpp._keepalive.Keepalive` pings the server during every session, so a
link that went silent ends the session within seconds and the reconnect loop starts.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import socket
import ssl
import xml.etree.ElementTree as ET
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import slixmpp

from nightcrew.comm.xmpp._client import StanzaHandler, TagMatcher, XmppClient
from nightcrew.comm.xmpp._errors import XmppAuthError
from nightcrew.comm.xmpp._keepalive import Keepalive
from nightcrew.comm.xmpp._settings import XmppSettings
from nightcrew.comm.xmpp._stanza_limits import RefusedStanza
from nightcrew.comm.xmpp._xmltext import escape_attribute, stanza_text
from nightcrew.errors import NightcrewError, RemoteError
from nightcrew.log import current_module

__all__ = ["RefusalHandler", "StanzaHandler", "XmppConnection", "error_condition", "split_jid"]

log = logging.getLogger(__name__)

#: SCRAM only: the password never travels, not even inside TLS.
_MECHANISMS = {"SCRAM-SHA-1", "SCRAM-SHA-256", "SCRAM-SHA-512"}
_RECONNECT_DELAYS = (0.2, 0.5, 1.0, 1.0, 2.0)
_STANZA_KINDS = frozenset({"iq", "message", "presence"})
_NS_STANZAS = "{urn:ietf:params:xml:ns:xmpp-stanzas}"

#: Hears of a stanza refused while it streamed in; returns True when it answered it.
RefusalHandler = Callable[[RefusedStanza], bool]


class XmppConnection:
    """A client session for one JID; nothing happens before :meth:`open`."""

    def __init__(
        self,
        settings: XmppSettings,
        *,
        on_session: Callable[[], Awaitable[None]],
        on_lost: Callable[[], None],
        features: list[str],
        features_for: Callable[[str], list[str]] | None = None,
        on_fatal: Callable[[NightcrewError], None] | None = None,
        plugins: tuple[str, ...] = (),
    ) -> None:
        self._settings = settings
        self._features_for = features_for
        self._on_session = on_session
        self._on_lost = on_lost
        self._on_fatal = on_fatal
        self._features = features
        self._plugins = plugins  # slixmpp plugins beyond disco (PubSub for the pyobs dialect)
        self._handlers: list[tuple[str, TagMatcher, StanzaHandler]] = []
        self._refusal_handlers: list[RefusalHandler] = []
        self._client: slixmpp.ClientXMPP | None = None
        self._session: asyncio.Future[None] | None = None
        self._tls_done = False
        self._online = False
        self._closing = False
        self._reconnect_task: asyncio.Task[None] | None = None
        self._outbox: list[str] = []  # serialized stanzas waiting for the next flush
        self._keepalive = (
            Keepalive(settings.ping_interval, settings.ping_timeout, self._on_silent_link)
            if settings.ping_interval is not None
            else None
        )

    @property
    def online(self) -> bool:
        """Whether a session is established (stanzas can be sent)."""
        return self._online

    @property
    def client(self) -> slixmpp.ClientXMPP:
        if self._client is None:
            raise RemoteError("not connected to the XMPP server")
        return self._client

    def add_handler(self, name: str, xpath: str, handler: StanzaHandler) -> None:
        """Call ``handler(element)`` for incoming stanzas matching ``xpath`` (before :meth:`open`).

        ``xpath`` is ``{ns}stanza`` or ``{ns}stanza/{ns}child``: a top-level stanza, optionally with
        a direct child element. Handlers see stanzas before slixmpp does; a stanza some handler
        consumed (returned True for) goes no further.
        """
        self._handlers.append((name, TagMatcher(xpath), handler))

    def add_refusal_handler(self, handler: RefusalHandler) -> None:
        """Call ``handler`` for every stanza refused by its size or nesting (before :meth:`open`).

        The refusal is logged here, once; a handler answers it (a fault to a refused call).
        """
        self._refusal_handlers.append(handler)

    # --- life cycle ----------------------------------------------------------------------------

    async def open(self) -> None:
        """Connect and log in; raises XmppAuthError or RemoteError (one attempt, no retry loop)."""
        # slixmpp's tasks copy this context: keep them out of the module's log forwarding.
        token = current_module.set(None)
        _quiet_slixmpp()
        try:
            self._client = self._make_client()
            await self._connect_once()
        finally:
            current_module.reset(token)

    async def close(self) -> None:
        """Leave the server; safe to call twice."""
        self._closing = True
        self._flush()  # what was sent before close() still goes out
        self._online = False  # a disconnect we asked for is not a loss
        if self._keepalive is not None:
            self._keepalive.stop()
        if self._reconnect_task is not None:
            self._reconnect_task.cancel()
            await asyncio.gather(self._reconnect_task, return_exceptions=True)
            self._reconnect_task = None
        client, self._client = self._client, None
        if client is not None:
            client.cancel_connection_attempt()
            if client.transport is not None:
                try:
                    await asyncio.wait_for(client.disconnect(wait=1.0), 3)
                except (TimeoutError, ConnectionError):
                    client.abort()
            # slixmpp leaves its outgoing-stanza task running after a disconnect; end it with us.
            filters = client._run_out_filters
            if filters is not None and not filters.done():
                filters.cancel()
                await asyncio.gather(filters, return_exceptions=True)
        self._online = False

    def send(self, stanza: ET.Element) -> None:
        """Queue ``stanza``; RemoteError when there is no session (no silent queueing for later).

        Stanzas sent in one turn of the event loop leave in one write at the start of the next
        (slixmpp's send queue writes each on its own): a callee's timeout announcement and a fast
        result share a TCP segment, and a burst of calls costs one system call, not fifty. This
        bypasses slixmpp's outgoing filters, which only its plugins we do not load use.
        """
        self._queue(stanza_text(stanza, self.client.default_ns))

    def send_text(self, kind: str, to: str, payload: str, **attrs: str) -> None:
        """Like :meth:`send` for a stanza made of ``payload``, XML text in a namespace of its own.

        The fast path for remote calls: their payloads are written as text (see ``_xmlrpc``).
        """
        if kind not in _STANZA_KINDS:
            raise ValueError(f"not a stanza: {kind}")
        head = "".join(f' {name}="{escape_attribute(value)}"' for name, value in attrs.items())
        self._queue(f'<{kind} to="{escape_attribute(to)}"{head}>{payload}</{kind}>')

    def _queue(self, text: str) -> None:
        if not self._online or self._client is None:
            raise RemoteError("not connected to the XMPP server")
        self._outbox.append(text)
        if len(self._outbox) == 1:
            asyncio.get_running_loop().call_soon(self._flush)

    def stanza(self, kind: str, to: str, *payload: ET.Element, **attrs: str) -> ET.Element:
        """A ``<message>``, ``<presence>`` or ``<iq>`` to ``to`` carrying ``payload`` elements.

        ``attrs`` are the stanza's other attributes (``type``, ``id``); see :meth:`send`.
        """
        if kind not in _STANZA_KINDS:
            raise ValueError(f"not a stanza: {kind}")
        made = ET.Element(f"{{{self.client.default_ns}}}{kind}", {"to": to, **attrs})
        made.extend(payload)
        return made

    # --- internals -----------------------------------------------------------------------------

    def _flush(self) -> None:
        if not self._outbox:
            return
        data, self._outbox = "".join(self._outbox), []
        client = self._client
        if self._online and client is not None and client.transport is not None:
            client.send_raw(data)
        # else the connection was lost meanwhile: its calls have failed already (on_lost)

    def _make_client(self) -> slixmpp.ClientXMPP:
        s = self._settings
        client = XmppClient(
            self._handlers,  # all registered before open()
            self._on_refused,
            s.full_jid,
            s.password,
            plugin_config={
                "feature_mechanisms": {"use_mechs": set(_MECHANISMS), "unencrypted_scram": not s.require_tls}
            },
        )
        client.enable_direct_tls = False  # STARTTLS on the one c2s port
        client.enable_starttls = True
        client.enable_plaintext = False
        if s.ca_file:
            client.ca_certs = Path(s.ca_file)
        if not s.verify_tls:
            client.ssl_context.check_hostname = False
            client.ssl_context.verify_mode = ssl.CERT_NONE
        client.register_plugin("xep_0030")  # disco#info: answers interface discovery
        client.register_plugin("xep_0199")  # pings: ours (Keepalive) and answers to the server's
        disco: Any = client.plugin["xep_0030"]
        for feature in self._features:
            disco.add_feature(feature)
        for plugin in self._plugins:
            client.register_plugin(plugin)
        if self._features_for is not None:
            disco.api.register(self._disco_info_for, "get_info")
        client.add_event_handler("session_start", self._on_session_start)
        client.add_event_handler("tls_success", self._on_tls)
        client.add_event_handler("ssl_invalid_chain", self._on_untrusted_certificate)
        client.add_event_handler("failed_all_auth", self._on_auth_failed)
        client.add_event_handler("connection_failed", self._on_connection_failed)
        client.add_event_handler("disconnected", self._on_disconnected)
        client.add_event_handler("stream_error", self._on_stream_error)
        return client

    def _disco_info_for(self, jid: Any, node: str | None, ifrom: Any, data: Any) -> Any:
        """disco#info answered per asking entity (XEP-0030 answers are per entity): the features
        ``features_for`` gives for it, so a caller is not told of interfaces it may not call."""
        from slixmpp.plugins.xep_0030.stanza.info import DiscoInfo

        disco: Any = self.client.plugin["xep_0030"]
        info = disco.static.get_info(jid, node, ifrom, data)
        if node or self._features_for is None:
            return info
        answer = DiscoInfo()
        for category, kind, _, name in info["identities"]:
            answer.add_identity(category, kind, name)
        for feature in self._features_for(str(ifrom) if ifrom else ""):
            answer.add_feature(feature)
        return answer

    def _on_refused(self, refused: RefusedStanza) -> None:
        log.warning("refused %s from %s: %s", refused.describe(), refused.sender or "?", refused.reason)
        answered = False
        for handler in self._refusal_handlers:
            answered = handler(refused) or answered
        if not answered and refused.kind == "iq" and refused.attrib.get("type") in ("get", "set"):
            # Every request gets an answer (RFC 6120 8.2.3): a policy violation, said in words.
            error = ET.Element(f"{{{self.client.default_ns}}}error", type="modify")
            ET.SubElement(error, f"{_NS_STANZAS}policy-violation")
            ET.SubElement(error, f"{_NS_STANZAS}text").text = f"stanza {refused.reason}"
            with contextlib.suppress(NightcrewError):
                to, iq_id = refused.sender, refused.attrib.get("id", "")
                self.send(self.stanza("iq", to, error, id=iq_id, type="error"))

    async def _connect_once(self) -> None:
        s = self._settings
        client = self.client
        self._session = asyncio.get_running_loop().create_future()
        self._tls_done = False
        client.connect(s.host, s.port)
        try:
            await asyncio.wait_for(self._session, s.connect_timeout)
        except TimeoutError:
            client.cancel_connection_attempt()
            client.abort()
            raise RemoteError(
                f"no XMPP session with {s.host}:{s.port} within {s.connect_timeout:g} s"
            ) from None
        finally:
            self._session = None
        await self._on_session()

    def _fail_session(self, error: NightcrewError) -> None:
        if self._session is not None and not self._session.done():
            self._session.set_exception(error)

    def _on_session_start(self, _: Any) -> None:
        transport = self.client.transport
        raw = transport.get_extra_info("socket") if transport is not None else None
        if raw is not None:
            # A call's reply follows its timeout announcement at once: do not let Nagle hold it.
            raw.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._online = True
        if self._keepalive is not None:
            self._keepalive.start(self.client.plugin["xep_0199"])
        if self._session is not None and not self._session.done():
            self._session.set_result(None)

    def _on_tls(self, _: Any) -> None:
        self._tls_done = True

    def _on_untrusted_certificate(self, error: Any) -> None:
        self._fail_session(self._loss_error(error))
        self.client.abort()

    def _loss_error(self, reason: Any) -> RemoteError:
        s = self._settings
        if isinstance(reason, ssl.SSLCertVerificationError):
            why = reason.verify_message or str(reason)
            return RemoteError(f"the certificate of {s.host}:{s.port} is not trusted ({why}); see ca_file")
        return RemoteError(f"XMPP server closed the connection ({reason})")

    def _on_auth_failed(self, _: Any) -> None:
        s = self._settings
        if s.require_tls and not self._tls_done:
            reason = f"the server at {s.host}:{s.port} offers no TLS, which is required off loopback"
        else:
            reason = "wrong password or unknown account"
        error = XmppAuthError(f"{s.bare_jid}: login refused ({reason})")
        if self._session is not None:
            self._fail_session(error)
        else:
            self._give_up(error)  # a refused login does not get better by retrying

    def _on_connection_failed(self, error: Any) -> None:
        s = self._settings
        self.client.cancel_connection_attempt()  # we retry ourselves, at our own pace
        self._fail_session(RemoteError(f"cannot connect to the XMPP server at {s.host}:{s.port}: {error}"))

    def _on_stream_error(self, error: Any) -> None:
        condition = error["condition"] if error is not None else "?"
        if condition == "conflict":
            self._give_up(
                RemoteError(
                    f"{self._settings.bare_jid}: another session took over this account "
                    "(a second process with the same account?); not reconnecting"
                )
            )

    def _give_up(self, error: NightcrewError) -> None:
        """The connection is lost for good: no more reconnects; the owner hears of it (on_fatal)."""
        log.error("%s", error)
        self._closing = True
        if self._on_fatal is not None:
            self._on_fatal(error)

    def _on_silent_link(self, why: str) -> None:
        log.warning("%s: the XMPP server is silent (%s); reconnecting", self._settings.bare_jid, why)
        if self._client is not None:
            self._client.abort()  # -> "disconnected" -> the reconnect loop

    def _on_disconnected(self, reason: Any) -> None:
        was_online, self._online = self._online, False
        if self._keepalive is not None:
            self._keepalive.stop()
        self._fail_session(self._loss_error(reason))
        if was_online:
            self._on_lost()
            if not self._closing and self._reconnect_task is None:
                self._reconnect_task = asyncio.get_running_loop().create_task(self._reconnect_loop())

    async def _reconnect_loop(self) -> None:
        attempt = 0
        try:
            while not self._closing:
                await asyncio.sleep(_RECONNECT_DELAYS[min(attempt, len(_RECONNECT_DELAYS) - 1)])
                attempt += 1
                try:
                    await self._connect_once()
                except XmppAuthError as exc:
                    self._give_up(exc)
                    return
                except RemoteError as exc:
                    log.debug("reconnect attempt %d failed: %s", attempt, exc)
                    continue
                log.info("%s reconnected to the XMPP server", self._settings.bare_jid)
                return
        finally:
            self._reconnect_task = None


def split_jid(jid: str) -> tuple[str, str]:
    """``(bare, resource)`` of a JID as the server wrote it (servers send them normalised)."""
    bare, _, resource = jid.partition("/")
    return bare, resource


def error_condition(stanza: ET.Element) -> str:
    """The defined condition of an error stanza (``conflict``, ``item-not-found`` …) or ``""``."""
    error = stanza.find("{jabber:client}error")
    for child in error if error is not None else ():
        if child.tag.startswith(_NS_STANZAS) and child.tag != _NS_STANZAS + "text":
            return child.tag[len(_NS_STANZAS) :]
    return ""


def _quiet_slixmpp() -> None:
    """Keep slixmpp's routine INFO lines and its own report of a refused login off the console.

    nightcrew reports connection losses and refused logins itself, once. Under debug logging
    (and when an application set these loggers' levels) nothing is changed.
    """
    if logging.getLogger().getEffectiveLevel() <= logging.DEBUG:
        return
    for name, level in (
        ("slixmpp", logging.WARNING),
        ("slixmpp.features.feature_mechanisms", logging.CRITICAL),
    ):
        logger = logging.getLogger(name)
        if logger.level == logging.NOTSET:
            logger.setLevel(level)
