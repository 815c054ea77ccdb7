"""Remote calls over XEP-0009 IQs, with nightcrew's timeout announcement.

Caller → callee: ``<iq type='set' id=ID>`` with ``<query xmlns='jabber:iq:rpc'><methodCall>``.
Callee → caller, at once, when the method's timeout is not the default: ``<message type='headline'>``
with ``<timeout xmlns='urn:nightcrew:rpc:timeout' id=ID seconds=S/>``. Callee → caller, when done:
``<iq type='result' id=ID>`` with a methodResponse (result or fault). An ``<iq type='error'>``
(e.g. the callee's session is gone) fails the call with RemoteError.

Calls to and from pyobs-core peers (the comm's pyobs dialect) carry their values in pyobs' format
(:mod:`~nightcrew.comm.xmpp._pyobs_values`) and announce timeouts pyobs' way: an early
``<iq type='result'>`` with the same id holding ``<methodTimeout><timeout>S</timeout>``.
"""

from __future__ import annotations

import itertools
import logging
import math
import secrets
import xml.etree.ElementTree as ET
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any

from nightcrew.comm.base import PendingCall
from nightcrew.comm.rpc import Fault, fault_from_exception
from nightcrew.comm.xmpp._connection import XmppConnection, error_condition
from nightcrew.comm.xmpp._pyobs_values import (
    build_pyobs_fault,
    build_pyobs_params,
    is_pyobs_call,
    parse_pyobs_fault,
    parse_pyobs_params,
    result_from_pyobs,
    result_to_pyobs,
)
from nightcrew.comm.xmpp._stanza_limits import MAX_PAYLOAD_BYTES, RefusedStanza, too_large
from nightcrew.comm.xmpp._xmlrpc import (
    NS_RPC,
    build_call,
    build_fault,
    build_response,
    parse_call,
    parse_response,
)
from nightcrew.comm.xmpp._xmltext import escape_attribute
from nightcrew.errors import CodecError, InterfaceError, InvalidArgumentError, NightcrewError, RemoteError

__all__ = ["NS_HINTS", "NS_TIMEOUT", "RpcChannel"]

log = logging.getLogger(__name__)

NS_TIMEOUT = "urn:nightcrew:rpc:timeout"
#: ``<acting xmlns=NS_ACTING identity='viewer'/>`` in a call's query: made as ``account:viewer``.
NS_ACTING = "urn:nightcrew:rpc:acting"
NS_HINTS = "urn:xmpp:hints"
_C = "{jabber:client}"

#: Serves ``method(args)``; then the caller's full JID and the identity it acts in (access check).
Serve = Callable[[str, list[Any], Callable[[float], None], str, str | None], Awaitable[Any]]
Spawn = Callable[[Coroutine[Any, Any, Any], str], None]


_Q = f"{{{NS_RPC}}}"


class _Outgoing:
    __slots__ = ("call", "jid", "method", "module", "pyobs")

    def __init__(
        self, jid: str, module: str, call: PendingCall, method: str = "", pyobs: bool = False
    ) -> None:
        self.jid = jid
        self.module = module
        self.call = call
        self.method = method
        self.pyobs = pyobs  # the callee speaks pyobs' value format


class RpcChannel:
    """Sends calls and serves incoming ones on one connection."""

    def __init__(
        self,
        connection: XmppConnection,
        *,
        serve: Serve,
        spawn: Spawn,
        pyobs_caller: Callable[[str], bool] = lambda jid: False,
    ) -> None:
        self._connection = connection
        # pyobs sends a call without arguments as a bare <params/>: only the caller tells its format.
        self._pyobs_caller = pyobs_caller
        self._serve = serve
        self._spawn = spawn
        self._pending: dict[str, _Outgoing] = {}
        # Call ids: unique per session and unguessable across sessions, without a uuid per call.
        self._id_prefix = f"nc-{secrets.token_hex(4)}-"
        self._ids = itertools.count(1)
        connection.add_handler("nightcrew rpc", f"{_C}iq/{{{NS_RPC}}}query", self._on_rpc_iq)
        connection.add_handler("nightcrew rpc error", f"{_C}iq/{_C}error", self._on_error_iq)
        timeouts = f"{_C}message/{{{NS_TIMEOUT}}}timeout"
        connection.add_handler("nightcrew rpc timeout", timeouts, self._on_timeout)
        connection.add_refusal_handler(self._on_refused)

    # --- calling -------------------------------------------------------------------------------

    def call(
        self, jid: str, module: str, method: str, args: list[Any], call: PendingCall, *, pyobs: bool = False
    ) -> None:
        """Send ``method(*args)`` to ``jid`` (module ``module``); ``call`` hears what comes back."""
        iq_id = f"{self._id_prefix}{next(self._ids):x}"
        if pyobs:  # pyobs peers know no acting identity: they are not under nightcrew's policy
            query = ET.Element(f"{_Q}query")
            method_call = ET.SubElement(query, f"{_Q}methodCall")
            ET.SubElement(method_call, f"{_Q}methodName").text = method
            method_call.append(build_pyobs_params(args, f"{method}(): argument"))
        else:
            payload = build_call(method, args)
            if call.acting_as is not None:
                # Inside the query: an IQ carries exactly one payload element (RFC 6120 §8.2.3).
                acting = f'<acting xmlns="{NS_ACTING}" identity="{escape_attribute(call.acting_as)}"/>'
                payload = f"{payload[: -len('</query>')]}{acting}</query>"
            if too_large(payload):  # the callee would refuse it: say so here, without sending
                raise InvalidArgumentError(f"{method}(): the call is larger than {MAX_PAYLOAD_BYTES} bytes")
        self._pending[iq_id] = _Outgoing(jid, module, call, method, pyobs)
        # When the caller gives up (timeout, cancellation), forget the call.
        call.future.add_done_callback(lambda _: self._pending.pop(iq_id, None))
        try:
            if pyobs:
                self._connection.send(self._connection.stanza("iq", jid, query, id=iq_id, type="set"))
            else:
                self._connection.send_text("iq", jid, payload, id=iq_id, type="set")
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

    def _take(self, iq_id: str, stanza: ET.Element) -> _Outgoing | None:
        """The call ``iq_id`` if ``stanza`` comes from its callee (else it is not ours, or forged)."""
        return self._take_from(iq_id, stanza.get("from", ""))

    def _take_from(self, iq_id: str, sender: str) -> _Outgoing | None:
        outgoing = self._pending.get(iq_id)
        return outgoing if outgoing is not None and sender == outgoing.jid else None

    def _on_refused(self, refused: RefusedStanza) -> bool:
        """Answer a call refused for its size or nesting; fail a call whose reply was refused."""
        if refused.kind != "iq" or refused.payload != f"{_Q}query":
            return False
        caller, iq_id = refused.sender, refused.attrib.get("id", "")
        kind = refused.attrib.get("type")
        if kind == "set":
            error = InvalidArgumentError(f"call refused: {refused.reason}")
            if self._pyobs_caller(caller):
                self._reply_pyobs(caller, iq_id, _pyobs_fault(error))
            else:
                self._reply(caller, iq_id, build_fault(fault_from_exception(error)))
            return True
        outgoing = self._take_from(iq_id, caller) if kind == "result" else None
        if outgoing is not None:
            del self._pending[iq_id]
            outgoing.call.set_error(RemoteError(f"reply refused: {refused.reason}", module=outgoing.module))
        return kind == "result"

    def _on_reply(self, stanza: ET.Element, query: ET.Element) -> None:
        iq_id = stanza.get("id", "")
        outgoing = self._take(iq_id, stanza)
        if outgoing is None:
            return
        if outgoing.pyobs:
            self._on_pyobs_reply(iq_id, outgoing, query)
            return
        del self._pending[iq_id]
        try:
            response = parse_response(query)
        except CodecError as exc:
            outgoing.call.set_error(RemoteError(f"unreadable reply: {exc.message}", module=outgoing.module))
            return
        if isinstance(response, Fault):
            outgoing.call.set_fault(response)
        else:
            outgoing.call.set_result(response)

    def _on_pyobs_reply(self, iq_id: str, outgoing: _Outgoing, query: ET.Element) -> None:
        timeout = query.findtext(f"{_Q}methodTimeout/{_Q}timeout")
        if timeout is not None:
            try:
                outgoing.call.announce(float(timeout))
            except ValueError:
                log.debug("ignored malformed pyobs timeout %r from %s", timeout, outgoing.module)
            return  # the result follows under the same id
        del self._pending[iq_id]
        response = query.find(f"{_Q}methodResponse")
        fault = response.find(f"{_Q}fault") if response is not None else None
        if fault is not None:
            outgoing.call.set_fault(parse_pyobs_fault(fault))
            return
        try:
            values = parse_pyobs_params(
                response.find(f"{_Q}params") if response is not None else None, "result"
            )
        except CodecError as exc:
            outgoing.call.set_error(
                RemoteError(f"unreadable pyobs reply: {exc.message}", module=outgoing.module)
            )
            return
        outgoing.call.set_result(result_from_pyobs(outgoing.method, values[0] if values else None))

    def _on_error_iq(self, stanza: ET.Element) -> bool:
        iq_id = stanza.get("id", "")
        outgoing = self._take(iq_id, stanza) if stanza.get("type") == "error" else None
        if outgoing is None:
            return False  # maybe an IQ slixmpp waits for (disco)
        del self._pending[iq_id]
        condition = error_condition(stanza) or "unknown error"
        if outgoing.pyobs and condition == "item-not-found":  # pyobs' answer to an unknown method
            message = f"pyobs module '{outgoing.module}' has no method '{outgoing.method}'"
            outgoing.call.set_error(InterfaceError(message, module=outgoing.module))
            return True
        outgoing.call.set_error(RemoteError(f"call not delivered ({condition})", module=outgoing.module))
        return True

    def _on_timeout(self, stanza: ET.Element) -> bool:
        element = stanza.find(f"{{{NS_TIMEOUT}}}timeout")
        outgoing = self._take(element.get("id", ""), stanza) if element is not None else None
        if outgoing is None or element is None:
            return True
        try:
            seconds = float(element.get("seconds", ""))
        except ValueError:
            log.debug("ignored malformed timeout announcement from %s", stanza.get("from"))
            return True
        outgoing.call.announce(seconds)
        return True

    # --- serving -------------------------------------------------------------------------------

    def _on_rpc_iq(self, stanza: ET.Element) -> bool:
        query = stanza.find(f"{{{NS_RPC}}}query")
        kind = stanza.get("type")
        if query is None or kind not in ("result", "set"):
            return False  # an error reply: _on_error_iq's
        if kind == "result":
            self._on_reply(stanza, query)
        else:
            self._on_call(stanza, query)
        return True

    def _on_call(self, stanza: ET.Element, query: ET.Element) -> None:
        caller, iq_id = stanza.get("from", ""), stanza.get("id", "")
        if is_pyobs_call(query) or self._pyobs_caller(caller):
            self._on_pyobs_call(caller, iq_id, query)
            return
        try:
            method, args = parse_call(query)
        except CodecError as exc:
            self._reply(caller, iq_id, build_fault(fault_from_exception(InvalidArgumentError(exc.message))))
            return
        acting = query.find(f"{{{NS_ACTING}}}acting")
        identity = None if acting is None else acting.get("identity", "")
        self._spawn(self._serve_call(caller, iq_id, method, args, identity), f"serve {method}()")

    async def _serve_call(
        self, caller: str, iq_id: str, method: str, args: list[Any], identity: str | None
    ) -> None:
        def announce(seconds: float) -> None:
            element = ET.Element(f"{{{NS_TIMEOUT}}}timeout", id=iq_id, seconds=repr(float(seconds)))
            try:
                self._connection.send(
                    self._connection.stanza("message", caller, element, _no_store(), type="headline")
                )
            except NightcrewError:
                log.debug("could not announce the timeout of %s() to %s", method, caller)

        try:
            result = await self._serve(method, args, announce, caller, identity)
            payload = build_response(result)
            if too_large(payload):
                raise RemoteError(f"the result of {method}() is larger than {MAX_PAYLOAD_BYTES} bytes")
        except Exception as exc:
            # Every failure becomes a fault: the one place (nightcrew.comm.rpc) decides its content.
            payload = build_fault(fault_from_exception(exc))
        self._reply(caller, iq_id, payload)

    def _on_pyobs_call(self, caller: str, iq_id: str, query: ET.Element) -> None:
        method = query.findtext(f"{_Q}methodCall/{_Q}methodName") or ""
        try:
            args = parse_pyobs_params(query.find(f"{_Q}methodCall/{_Q}params"), f"{method}(): argument")
        except CodecError as exc:
            log.warning("refused pyobs call %s() from %s: %s", method, caller, exc.message)
            self._reply_pyobs(caller, iq_id, _pyobs_fault(InvalidArgumentError(exc.message)))
            return
        self._spawn(self._serve_pyobs_call(caller, iq_id, method, args), f"serve pyobs {method}()")

    async def _serve_pyobs_call(self, caller: str, iq_id: str, method: str, args: list[Any]) -> None:
        def announce(seconds: float) -> None:
            body = ET.Element(f"{_Q}methodTimeout")
            ET.SubElement(body, f"{_Q}timeout").text = str(math.ceil(seconds))  # pyobs reads an int
            self._reply_pyobs(caller, iq_id, body)

        try:
            result = await self._serve(method, args, announce, caller, None)
            body = ET.Element(f"{_Q}methodResponse")
            result = result_to_pyobs(method, result)
            body.append(build_pyobs_params([] if result is None else [result], "result"))
        except Exception as exc:
            body = _pyobs_fault(exc)
        self._reply_pyobs(caller, iq_id, body)

    def _reply_pyobs(self, caller: str, iq_id: str, body: ET.Element) -> None:
        query = ET.Element(f"{_Q}query")
        query.append(body)
        try:
            self._connection.send(self._connection.stanza("iq", caller, query, id=iq_id, type="result"))
        except NightcrewError:
            log.debug("reply to pyobs call %s from %s lost: not connected", iq_id, caller)

    def _reply(self, caller: str, iq_id: str, payload: str) -> None:
        try:
            self._connection.send_text("iq", caller, payload, id=iq_id, type="result")
        except NightcrewError:
            log.debug("result of call %s to %s lost: not connected", iq_id, caller)


def _pyobs_fault(exc: BaseException) -> ET.Element:
    response = ET.Element(f"{_Q}methodResponse")
    response.append(build_pyobs_fault(fault_from_exception(exc)))
    return response


def _no_store() -> ET.Element:
    """XEP-0334 hint: servers must not archive or store this message for later."""
    return ET.Element(f"{{{NS_HINTS}}}no-store")
