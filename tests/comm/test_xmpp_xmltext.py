"""The outgoing stanza writer: what it writes parses back to the same element tree."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from nightcrew.comm.xmpp._xmltext import stanza_text

CLIENT = "jabber:client"
RPC = "jabber:iq:rpc"


def _parsed(text: str) -> ET.Element:
    # The stream declares jabber:client; wrap the stanza the way the stream does.
    return ET.fromstring(f'<stream xmlns="{CLIENT}">{text}</stream>')[0]


def _same(a: ET.Element, b: ET.Element) -> bool:
    return (
        a.tag == b.tag
        and a.attrib == b.attrib
        and (a.text or "") == (b.text or "")
        and (a.tail or "") == (b.tail or "")
        and len(a) == len(b)
        and all(_same(x, y) for x, y in zip(a, b, strict=True))
    )


@pytest.mark.parametrize(
    "value",
    ["plain", "<&>\"'", "line\nbreak\ttab", "carriage\rreturn", "ümlaut ✓", "]]>", ""],
)
def test_text_and_attributes_round_trip(value: str) -> None:
    iq = ET.Element(f"{{{CLIENT}}}iq", {"type": "set", "id": value or "x", "to": "a@b/c"})
    query = ET.SubElement(iq, f"{{{RPC}}}query")
    name = ET.SubElement(query, f"{{{RPC}}}methodName")
    name.text = value
    name.tail = value
    text = stanza_text(iq)
    assert text.startswith("<iq ") and f'xmlns="{CLIENT}"' not in text  # the stream's namespace
    assert _same(_parsed(text), iq)


def test_namespace_is_declared_only_where_it_changes() -> None:
    message = ET.Element(f"{{{CLIENT}}}message", {"type": "headline"})
    ET.SubElement(message, "{urn:nightcrew:rpc:timeout}timeout", {"id": "1", "seconds": "10"})
    body = ET.SubElement(message, f"{{{CLIENT}}}body")
    body.text = "x"
    text = stanza_text(message)
    # Only the timeout element declares one; <body>'s parent is already in jabber:client.
    assert text.count("xmlns=") == 1 and '<timeout xmlns="urn:nightcrew:rpc:timeout"' in text
    assert _same(_parsed(text), message)


def test_xml_lang_is_kept_and_other_prefixed_attributes_are_refused() -> None:
    message = ET.Element(f"{{{CLIENT}}}message", {"{http://www.w3.org/XML/1998/namespace}lang": "de"})
    assert _same(_parsed(stanza_text(message)), message)
    with pytest.raises(ValueError, match="namespaced attribute"):
        stanza_text(ET.Element(f"{{{CLIENT}}}message", {"{urn:other}x": "1"}))
    with pytest.raises(ValueError, match="has no namespace"):
        stanza_text(ET.Element("message"))
