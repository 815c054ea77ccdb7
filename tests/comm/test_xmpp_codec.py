"""XML-RPC values on stanza XML (no server needed)."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from datetime import UTC, datetime, timedelta, timezone
from typing import Any

import pytest

from nightcrew.comm.rpc import Fault
from nightcrew.comm.xmpp._xmlrpc import (
    build_call,
    build_fault,
    build_response,
    decode_value,
    encode_value,
    parse_call,
    parse_response,
)
from nightcrew.errors import CodecError


def encoded(*values: Any) -> ET.Element:
    """``<param>`` holding the ``<value>`` of each of ``values``, parsed from the text written."""
    out: list[str] = []
    for value in values:
        encode_value(value, out)
    return ET.fromstring("<param>" + "".join(out) + "</param>")


def round_trip(value: Any) -> Any:
    return decode_value(next(iter(encoded(value))))


@pytest.mark.parametrize(
    "value",
    [
        None,
        True,
        False,
        0,
        -(2**31),
        2**31 - 1,
        2**31,
        -(2**63),
        2**63 - 1,
        1.5,
        -0.0,
        1e300,
        "",
        "ä <&> ünïcode 🔭",
        "line\r\nbreaks\tand ]]> \"quotes'",
        b"\x00\xff",
        b"",
        datetime(2026, 11, 22, 21, 30, tzinfo=UTC),
        datetime(2026, 11, 22, 21, 30, 5, 123456, tzinfo=UTC),
        [1, [2, [None]], {"a": []}],
        {"n": [1, 2.5, None, True], "s": "x", "nested": {"deep": {}}, "<&>": "key escaped"},
    ],
)
def test_wire_values_round_trip(value: Any) -> None:
    back = round_trip(value)
    assert back == value and type(back) is type(value)


def test_integer_width_picks_int_or_i8() -> None:
    parent = encoded(2**31 - 1, 2**31)
    assert [v[0].tag.rsplit("}")[-1] for v in parent] == ["int", "i8"]


def test_datetimes_travel_as_utc_and_classic_forms_are_read() -> None:
    local = datetime(2026, 11, 22, 22, 30, tzinfo=timezone(timedelta(hours=1)))
    assert round_trip(local) == datetime(2026, 11, 22, 21, 30, tzinfo=UTC)
    for text in ("20261122T21:30:00", "2026-11-22T21:30:00Z", "20261122T213000", "2026-11-22T22:30:00+01:00"):
        holder = ET.fromstring(f"<value><dateTime.iso8601>{text}</dateTime.iso8601></value>")
        assert decode_value(holder) == datetime(2026, 11, 22, 21, 30, tzinfo=UTC)


def test_values_of_other_peers_are_read() -> None:
    assert decode_value(ET.fromstring("<value>untyped</value>")) == "untyped"
    assert decode_value(ET.fromstring("<value><i4>7</i4></value>")) == 7
    assert decode_value(ET.fromstring("<value><string/></value>")) == ""


def test_unwritable_and_unreadable_values_are_codec_errors() -> None:
    with pytest.raises(CodecError, match="characters XML cannot carry"):
        encode_value("bell\x07", [])
    with pytest.raises(CodecError, match="set is not a wire value"):
        encode_value({1, 2}, [])
    with pytest.raises(CodecError, match=r"value\.a: struct key 1 is not a string"):
        encode_value({"a": {1: 2}}, [])
    with pytest.raises(CodecError, match="malformed XML-RPC <int>"):
        decode_value(ET.fromstring("<value><int>x</int></value>"))
    with pytest.raises(CodecError, match="unknown XML-RPC value type <float>"):
        decode_value(ET.fromstring("<value><float>1</float></value>"))


def test_call_response_and_fault_payloads() -> None:
    method, args = parse_call(ET.fromstring(build_call("move", [1.5, None])))
    assert (method, args) == ("move", [1.5, None])
    assert parse_response(ET.fromstring(build_response({"ok": True}))) == {"ok": True}
    fault = parse_response(ET.fromstring(build_fault(Fault("MoveError", "limit <reached> & more"))))
    assert isinstance(fault, Fault)
    assert (fault.error_class, fault.message) == ("MoveError", "limit <reached> & more")


def test_a_plain_xml_rpc_fault_becomes_remote_error() -> None:
    plain = (
        "<query xmlns='jabber:iq:rpc'><methodResponse><fault><value><struct>"
        "<member><name>faultCode</name><value><int>4</int></value></member>"
        "<member><name>faultString</name><value><string>Too many parameters.</string></value></member>"
        "</struct></value></fault></methodResponse></query>"
    )
    fault = parse_response(ET.fromstring(plain))
    assert isinstance(fault, Fault) and fault.error_class == "RemoteError"
