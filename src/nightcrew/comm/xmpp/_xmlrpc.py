"""XML-RPC values on stanza XML: the payload of ``jabber:iq:rpc`` (XEP-0009).

Written here rather than borrowed from :mod:`xmlrpc.client` because nightcrew needs ``<nil/>``,
``<i8>`` for 64-bit integers and aware UTC datetimes with microseconds. Values are written as text
(the payload goes into a stanza's text as is: building elements first and serializing them was
the largest part of a call's CPU time) and read from the elements the stream parser produced.
The mapping (see docs/protocol.md):

============  ==========================================================
wire value    element
============  ==========================================================
None          ``<nil/>``
bool          ``<boolean>0|1</boolean>``
int           ``<int>`` within 32 bits, else ``<i8>`` (64 bits)
float         ``<double>`` (Python ``repr``; ``nan``/``inf`` as such)
str           ``<string>``
bytes         ``<base64>``
datetime      ``<dateTime.iso8601>YYYYMMDDTHH:MM:SS[.ffffff]</…>`` in UTC
list          ``<array><data><value>…</value>…</data></array>``
dict          ``<struct><member><name>k</name><value>…</value></member>…</struct>``
============  ==========================================================
"""

from __future__ import annotations

import base64
import math
import re
import xml.etree.ElementTree as ET
from datetime import UTC, datetime
from typing import Any

from nightcrew.comm.rpc import MAX_ARGUMENT_DEPTH, Fault
from nightcrew.comm.xmpp._xmltext import escape_text
from nightcrew.errors import CodecError

__all__ = [
    "NS_RPC",
    "build_call",
    "build_fault",
    "build_response",
    "decode_value",
    "encode_value",
    "parse_call",
    "parse_response",
]

NS_RPC = "jabber:iq:rpc"
_Q = f"{{{NS_RPC}}}"
_INT32 = 2**31
#: Characters XML 1.0 cannot carry at all; strings with them must travel as bytes.
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")
#: faultCode of every fault nightcrew sends; the error class is in the ``errorClass`` member.
FAULT_CODE = 1


def encode_value(value: Any, out: list[str], path: str = "value") -> None:
    """Append the ``<value>`` text for wire ``value`` to ``out``; CodecError if it cannot travel."""
    kind = type(value)
    if value is None:
        out.append("<value><nil/></value>")
    elif kind is bool:
        out.append("<value><boolean>1</boolean></value>" if value else "<value><boolean>0</boolean></value>")
    elif kind is int:
        tag = "int" if -_INT32 <= value < _INT32 else "i8"
        out.append(f"<value><{tag}>{value}</{tag}></value>")
    elif kind is float:
        out.append(f"<value><double>{repr(value) if math.isfinite(value) else str(value)}</double></value>")
    elif kind is str:
        out.append(f"<value><string>{_xml_string(value, path)}</string></value>")
    elif kind is bytes:
        out.append(f"<value><base64>{base64.b64encode(value).decode('ascii')}</base64></value>")
    elif isinstance(value, datetime):
        out.append(f"<value><dateTime.iso8601>{_format_datetime(value)}</dateTime.iso8601></value>")
    elif kind is list:
        out.append("<value><array><data>")
        for i, item in enumerate(value):
            encode_value(item, out, f"{path}[{i}]")
        out.append("</data></array></value>")
    elif kind is dict:
        out.append("<value><struct>")
        for key, item in value.items():
            if type(key) is not str:
                raise CodecError(f"{path}: struct key {key!r} is not a string")
            out.append(f"<member><name>{_xml_string(key, path)}</name>")
            encode_value(item, out, f"{path}.{key}")
            out.append("</member>")
        out.append("</struct></value>")
    else:
        raise CodecError(f"{path}: {kind.__name__} is not a wire value")


def _xml_string(value: str, path: str) -> str:
    if _NOT_XML.search(value):
        raise CodecError(f"{path}: string holds characters XML cannot carry (send bytes instead)")
    return escape_text(value)


def _format_datetime(value: datetime) -> str:
    utc = value.astimezone(UTC) if value.tzinfo else value
    text = utc.strftime("%Y%m%dT%H:%M:%S")
    return f"{text}.{utc.microsecond:06d}" if utc.microsecond else text


def decode_value(holder: ET.Element, depth: int = 0) -> Any:
    """The wire value of a ``<value>`` element (any namespace); CodecError if malformed or nested
    deeper than :data:`~nightcrew.comm.rpc.MAX_ARGUMENT_DEPTH` (a stanza cannot exhaust the stack)."""
    if depth > MAX_ARGUMENT_DEPTH:
        raise CodecError(f"XML-RPC value nested deeper than {MAX_ARGUMENT_DEPTH} levels")
    typed = next(iter(holder), None)
    if typed is None:
        return holder.text or ""  # a bare <value>text</value> is a string
    tag = typed.tag.rsplit("}", 1)[-1]
    text = (typed.text or "").strip()
    try:
        if tag == "nil":
            return None
        if tag == "boolean":
            if text not in ("0", "1"):
                raise ValueError(text)
            return text == "1"
        if tag in ("int", "i4", "i8"):
            return int(text)
        if tag == "double":
            return float(text)
        if tag == "string":
            return typed.text or ""
        if tag == "base64":
            return base64.b64decode(text, validate=False)
        if tag == "dateTime.iso8601":
            return _parse_datetime(text)
        if tag == "array":
            data = _child(typed, "data")
            return [decode_value(v, depth + 1) for v in data if _local(v) == "value"]
        if tag == "struct":
            return {
                _member_name(m): decode_value(_child(m, "value"), depth + 1)
                for m in typed
                if _local(m) == "member"
            }
    except (ValueError, TypeError) as exc:
        raise CodecError(f"malformed XML-RPC <{tag}>: {text[:40]!r}") from exc
    raise CodecError(f"unknown XML-RPC value type <{tag}>")


def _parse_datetime(text: str) -> datetime:
    # Accepts the classic basic form (19980717T14:08:55) and ISO 8601 extended forms; no zone = UTC.
    match = re.fullmatch(r"(\d{4})-?(\d{2})-?(\d{2})T(\d{2}):?(\d{2}):?(\d{2})(\.\d+)?(.*)", text)
    if match is None:
        raise ValueError(text)
    year, month, day, hour, minute, second, fraction, zone = match.groups()
    iso = f"{year}-{month}-{day}T{hour}:{minute}:{second}{(fraction or '')[:7]}{zone or ''}"
    parsed = datetime.fromisoformat(iso.replace("Z", "+00:00"))
    return parsed.astimezone(UTC) if parsed.tzinfo else parsed.replace(tzinfo=UTC)


def _local(element: ET.Element) -> str:
    return element.tag.rsplit("}", 1)[-1]


def _child(element: ET.Element, name: str) -> ET.Element:
    for child in element:
        if _local(child) == name:
            return child
    raise ValueError(f"<{_local(element)}> lacks <{name}>")


def _member_name(member: ET.Element) -> str:
    return _child(member, "name").text or ""


# --- whole payloads ----------------------------------------------------------------------------


def build_call(method: str, args: list[Any]) -> str:
    """``<query xmlns='jabber:iq:rpc'><methodCall>…</methodCall></query>`` as text."""
    name = _xml_string(method, "method name")
    out = [f'<query xmlns="{NS_RPC}"><methodCall><methodName>{name}</methodName><params>']
    for i, arg in enumerate(args):
        out.append("<param>")
        encode_value(arg, out, f"argument {i + 1}")
        out.append("</param>")
    out.append("</params></methodCall></query>")
    return "".join(out)


def parse_call(query: ET.Element) -> tuple[str, list[Any]]:
    """Method name and wire arguments of a ``jabber:iq:rpc`` query; CodecError if malformed."""
    try:
        call = _child(query, "methodCall")
        method = (_child(call, "methodName").text or "").strip()
        params = next((c for c in call if _local(c) == "params"), None)
        holders = [] if params is None else [_child(p, "value") for p in params if _local(p) == "param"]
    except ValueError as exc:
        raise CodecError(f"malformed methodCall: {exc}") from exc
    return method, [decode_value(h) for h in holders]


def build_response(result: Any) -> str:
    """A methodResponse with one param, the wire ``result``, as text."""
    out = [f'<query xmlns="{NS_RPC}"><methodResponse><params><param>']
    encode_value(result, out, "result")
    out.append("</param></params></methodResponse></query>")
    return "".join(out)


def build_fault(fault: Fault) -> str:
    """A methodResponse fault as text: faultCode, faultString (the message) and errorClass."""
    out = [f'<query xmlns="{NS_RPC}"><methodResponse><fault>']
    value = {"faultCode": FAULT_CODE, "faultString": fault.message, "errorClass": fault.error_class}
    encode_value(value, out)
    out.append("</fault></methodResponse></query>")
    return "".join(out)


def parse_response(query: ET.Element) -> Any | Fault:
    """The wire result of a methodResponse, or the :class:`Fault` it carries."""
    try:
        response = _child(query, "methodResponse")
        first = next(iter(response))
    except (ValueError, StopIteration) as exc:
        raise CodecError("malformed methodResponse") from exc
    if _local(first) == "fault":
        data = decode_value(_child(first, "value"))
        if not isinstance(data, dict):
            raise CodecError("malformed fault")
        message = str(data.get("faultString", ""))
        # Faults from other XML-RPC peers have no errorClass: they arrive as RemoteError.
        return Fault(str(data.get("errorClass", "RemoteError")), message)
    try:
        return decode_value(_child(_child(first, "param"), "value"))
    except ValueError:
        return None  # no params: a void result
