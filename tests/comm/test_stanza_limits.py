"""Stanzas refused by size and nesting while they stream in, and event JSON bounded before parsing."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from nightcrew.comm.xmpp._stanza_limits import (
    MAX_EVENT_CHARS,
    MAX_STANZA_DEPTH,
    BoundedPullParser,
    RefusedStanza,
    load_json_bounded,
    too_large,
)
from nightcrew.comm.xmpp._xmlrpc import build_call, parse_call
from nightcrew.errors import CodecError

STREAM = b'<stream:stream xmlns="jabber:client" xmlns:stream="http://etherx.jabber.org/streams">'


def _iq(payload: str, iq_id: str = "1") -> bytes:
    return f'<iq type="set" id="{iq_id}" from="attacker@x.test/a">{payload}</iq>'.encode()


class _Stream:
    """A bounded parser fed as slixmpp feeds it, recording what passes and what is refused."""

    def __init__(self, **limits: int) -> None:
        self.refused: list[RefusedStanza] = []
        self.parser = BoundedPullParser(self.refused.append, **limits)
        self.passed: list[tuple[str, ET.Element]] = []
        self.feed(STREAM)

    def feed(self, data: bytes, piece: int = 100_000) -> None:
        for start in range(0, len(data), piece):
            self.parser.feed(data[start : start + piece])
            self.passed += self.parser.read_events()

    def stanzas(self) -> list[ET.Element]:
        return [element for event, element in self.passed if event == "end"]


def test_stanzas_within_the_limits_pass_whole() -> None:
    stream = _Stream()
    call = build_call("echo", [[{"a": [1, 2.5, "x"]}] * 100])
    stream.feed(_iq(call, "1") + _iq(call, "2"), piece=7)
    stanzas = stream.stanzas()
    assert [s.get("id") for s in stanzas] == ["1", "2"]
    assert parse_call(stanzas[0][0]) == ("echo", [[{"a": [1, 2.5, "x"]}] * 100])
    # slixmpp sees the stream open, then each stanza as a start and an end (it counts depth by them).
    assert [event for event, _ in stream.passed] == ["start", "start", "end", "start", "end"]
    assert stream.refused == []


def test_an_oversized_stanza_is_refused_while_it_streams_and_the_next_one_passes() -> None:
    stream = _Stream(max_bytes=100_000)
    oversized = _iq(build_call("echo", [[0] * 20_000]), "big")  # ~500 kB of small values
    stream.feed(oversized[:200_000])
    # Refused before its end arrived: nothing built beyond the limit is kept.
    assert [(r.kind, r.sender, r.attrib["id"], r.reason) for r in stream.refused] == [
        ("iq", "attacker@x.test/a", "big", "larger than 100000 bytes")
    ]
    assert stream.refused[0].describe() == "<iq type='set'> (jabber:iq:rpc query)"
    stream.feed(oversized[200_000:] + _iq(build_call("add", [1, 2]), "next"))
    assert [s.get("id") for s in stream.stanzas()] == ["next"]
    assert len(stream.refused) == 1


def test_a_deep_stanza_is_refused_at_the_depth_limit() -> None:
    stream = _Stream()
    deep = "<value><array><data>" * 5000 + "<value><int>1</int></value>" + "</data></array></value>" * 5000
    call = build_call("echo", [0]).replace("<value><int>0</int></value>", deep)
    stream.feed(_iq(call))
    assert [r.reason for r in stream.refused] == [f"nested deeper than {MAX_STANZA_DEPTH} elements"]
    assert stream.stanzas() == []


def test_the_deepest_value_the_codec_accepts_fits_the_depth_limit() -> None:
    from nightcrew.comm.rpc import MAX_ARGUMENT_DEPTH

    value: object = 1
    for level in range(MAX_ARGUMENT_DEPTH - 1):
        value = [value] if level % 2 else {"k": value}
    stream = _Stream()
    stream.feed(_iq(build_call("echo", [value])))
    assert stream.refused == []
    assert parse_call(stream.stanzas()[0][0])[1] == [value]


def test_a_broken_stream_raises_when_read_as_slixmpp_expects() -> None:
    stream = _Stream()
    with pytest.raises(ET.ParseError):
        stream.feed(b"<iq><unclosed></iq>")


def test_too_large_counts_utf8_bytes() -> None:
    assert not too_large("a" * 100, limit=100)
    assert too_large("é" * 60, limit=100)  # 120 bytes


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ("[" * 5000 + "]" * 5000, "nested deeper than 32 levels"),
        ("[" * 33 + "]" * 33, "nested deeper than 32 levels"),
        ("[[]," * 40 + "[]" + "]" * 40, "nested deeper than 32 levels"),  # interleaved
        ('{"a": [1, 2}', "not JSON: its brackets do not match"),
        ("[1, 2", "not JSON"),
        ("[" + "0," * MAX_EVENT_CHARS + "0]", f"larger than {MAX_EVENT_CHARS} characters"),
    ],
)
def test_event_json_refused_before_it_is_parsed(text: str, error: str) -> None:
    with pytest.raises(CodecError, match=error):
        load_json_bounded(text)


def test_event_json_within_the_limits_loads() -> None:
    nested: list[object] = []
    for _ in range(31):
        nested = [nested]
    assert load_json_bounded("[" * 32 + "]" * 32) == nested
    assert load_json_bounded('{"a": "[[[{{", "b": "\\"]"}') == {"a": "[[[{{", "b": '"]'}
