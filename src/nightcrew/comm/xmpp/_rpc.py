"""Remote calls over XEP-0009 IQs, with nightcrew's timeout announcement.

Caller → callee: ``<iq type='set' id=ID>`` with ``<query xmlns='jabber:iq:rpc'><methodCall>``.
Callee → caller, at once, when the method's timeout is not the default: ``<message type='headline'>``
with ``<timeout xmlns='urn:nightcrew:rpc:timeout' id=ID seconds=S/>``. Callee → caller, when done:
``<iq type='result' id=ID>`` with a methodResponse (result or fault). An ``<iq type='error'>``
(e.g. the callee's session is gone) fails the call with RemoteError.
"""

from __future__ import annotations

import logging
import uuid
import xml.etree.ElementTree as ET
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any

from slixmpp.xmlstream.stanzabase import StanzaBase

from nightcrew.comm.base import PendingCall
from nightcrew.comm.rpc import Fault, fault_from_exception
from nightcrew.comm.xmpp._connection import XmppConnection
from nightcrew.comm.xmpp._xmlrpc import (
    NS_RPC,
    build_call,
    build_fault,
    build_response,
    parse_call,
    parse_response,
)
from nightcrew.errors import CodecError, InvalidArgumentError, NightcrewError, RemoteError

__all__ = ["NS_HINTS", "NS_TIMEOUT", "RpcChannel"]

log = logging.getLogger(__name__)

NS_TIMEOUT = "urn:nightcrew:rpc:timeout"
NS_HINTS = "urn:xmpp:hints"
_C = "{jabber:client}"

Serve = Callable[[str, list[Any], Callable[[float], None]], Awaitable[Any]]
Spawn = Callable[[Coroutine[Any, Any, Any], str], None]


class _Outgoing:
    __slots__ = ("call", "jid", "module")

    def __init__(self, jid: str, module: str, call: PendingCall) -> None:
        self.jid = jid
        self.module = module
        self.call = call


class RpcChannel:
    """Sends calls and serves incoming ones on one connection."""

    def __init__(self, connection: XmppConnection, *, serve: Serve, spawn: Spawn) -> None:
        self._connection = connection
        self._serve = serve
        self._spawn = spawn
        self._pending: dict[str, _Outgoing] = {}
        connection.add_handler("nightcrew rpc", f"{_C}iq/{{{NS_RPC}}}query", self._on_rpc_iq)
        connection.add_handler("nightcrew rpc error", f"{_C}iq/{_C}error", self._on_error_iq)
        timeouts = f"{_C}message/{{{NS_TIMEOUT}}}timeout"
        connection.add_handler("nightcrew rpc timeout", timeouts, self._on_timeout)

    # --- calling -------------------------------------------------------------------------------

    def call(self, jid: str, module: str, method: str, args: list[Any], call: PendingCall) -> None:
        """Send ``method(*args)`` to ``jid`` (module ``module``); ``call`` hears what comes back."""
        iq_id = f"nc-{uuid.uuid4().hex[:16]}"
        stanza = self._connection.stanza("iq", jid, build_call(method, args), id=iq_id, type="set")
        self._pending[iq_id] = _Outgoing(jid, module, call)
        # When the caller gives up (timeout, cancellation), forget the call.
        call.future.add_done_callback(lambda _: self._pending.pop(iq_id, None))
        try:
            self._connection.send(stanza)
        except NightcrewError:
            self._pending.pop(iq_id, None)
            raise

    def fail_all(self, message: str) -> None:
        """Fail every call in flight (the connection is gone)."""
        for outgoing in list(self._pending.values()):
            outgoing.call.set_error(RemoteError(message, module=outgoing.module))
        self._pending.clear()

    def fail_calls_to(self, module: str) -> None:
        """Fail the calls in flight to ``module``, which went offline."""
        for iq_id, outgoing in list(self._pending.items()):
            if outgoing.module == module:
                del self._pending[iq_id]
                outgoing.call.set_error(RemoteError("went offline during the call", module=module))

    def _take(self, stanza: StanzaBase) -> _Outgoing | None:
        outgoing = self._pending.get(stanza["id"])
        if outgoing is None or str(stanza["from"]) != outgoing.jid:
            return None  # not ours, or a forged reply from someone else
        return outgoing

    def _on_reply(self, stanza: StanzaBase, query: ET.Element) -> None:
        outgoing = self._take(stanza)
        if outgoing is None:
            return
        del self._pending[stanza["id"]]
        try:
            response = parse_response(query)
        except CodecError as exc:
            outgoing.call.set_error(RemoteError(f"unreadable reply: {exc.message}", module=outgoing.module))
            return
        if isinstance(response, Fault):
            outgoing.call.set_fault(response)
        else:
            outgoing.call.set_result(response)

    def _on_error_iq(self, stanza: StanzaBase) -> None:
        if stanza["type"] != "error":
            return
        outgoing = self._take(stanza)
        if outgoing is None:
            return
        del self._pending[stanza["id"]]
        condition = stanza["error"]["condition"] or "unknown error"
        outgoing.call.set_error(RemoteError(f"call not delivered ({condition})", module=outgoing.module))

    def _on_timeout(self, stanza: StanzaBase) -> None:
        element = stanza.xml.find(f"{{{NS_TIMEOUT}}}timeout")
        outgoing = self._take_by_id(element.get("id", "") if element is not None else "", stanza)
        if outgoing is None or element is None:
            return
        try:
            seconds = float(element.get("seconds", ""))
        except ValueError:
            log.debug("ignored malformed timeout announcement from %s", stanza["from"])
            return
        outgoing.call.announce(seconds)

    def _take_by_id(self, iq_id: str, stanza: StanzaBase) -> _Outgoing | None:
        outgoing = self._pending.get(iq_id)
        return outgoing if outgoing is not None and str(stanza["from"]) == outgoing.jid else None

    # --- serving -------------------------------------------------------------------------------

    def _on_rpc_iq(self, stanza: StanzaBase) -> None:
        query = stanza.xml.find(f"{{{NS_RPC}}}query")
        if query is None:
            return
        kind = stanza["type"]
        if kind in ("result",):
            self._on_reply(stanza, query)
        elif kind == "set":
            self._on_call(stanza, query)

    def _on_call(self, stanza: StanzaBase, query: ET.Element) -> None:
        caller, iq_id = str(stanza["from"]), stanza["id"]
        try:
            method, args = parse_call(query)
        except CodecError as exc:
            self._reply(caller, iq_id, build_fault(fault_from_exception(InvalidArgumentError(exc.message))))
            return
        self._spawn(self._serve_call(caller, iq_id, method, args), f"serve {method}()")

    async def _serve_call(self, caller: str, iq_id: str, method: str, args: list[Any]) -> None:
        def announce(seconds: float) -> None:
            element = ET.Element(f"{{{NS_TIMEOUT}}}timeout", id=iq_id, seconds=repr(float(seconds)))
            try:
                self._connection.send(
                    self._connection.stanza("message", caller, element, _no_store(), type="headline")
                )
            except NightcrewError:
                log.debug("could not announce the timeout of %s() to %s", method, caller)

        try:
            result = await self._serve(method, args, announce)
            payload = build_response(result)
        except Exception as exc:
            # Every failure becomes a fault: the one place (nightcrew.comm.rpc) decides its content.
            payload = build_fault(fault_from_exception(exc))
        self._reply(caller, iq_id, payload)

    def _reply(self, caller: str, iq_id: str, payload: ET.Element) -> None:
        try:
            self._connection.send(self._connection.stanza("iq", caller, payload, id=iq_id, type="result"))
        except NightcrewError:
            log.debug("result of call %s to %s lost: not connected", iq_id, caller)


def _no_store() -> ET.Element:
    """XEP-0334 hint: servers must not archive or store this message for later."""
    return ET.Element(f"{{{NS_HINTS}}}no-store")
