"""Cutting the byte stream from an indiserver into messages, incrementally and with clear errors.

INDI is a sequence of top-level XML elements without a document element; the stream is parsed
with expat (``XMLPullParser``) inside a synthetic root. Each top-level element becomes a
:data:`~nightcrew.bridges.indi.protocol.ServerMessage` as soon as it ends and is then dropped.

BLOBs take a short cut: expat sees a ``oneBLOB``'s tags but not its megabytes of base64 text,
which are collected as raw chunks up to ``</oneBLOB>`` (base64 holds no ``<``) and handed to
:func:`~nightcrew.bridges.indi.protocol.parse_element` beside the tree. Pushing the text through
expat's character handlers cost ten times the reading itself (bench/indi.py).

Errors name the device and property of the element being read: malformed XML, a stream that ends
inside an element (truncated), and a BLOB whose text grows beyond what its ``size`` (or
``enclen``) announced — cut off at once, before a lying server can fill the memory.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import cast
from xml.etree.ElementTree import Element, ParseError, XMLPullParser

from nightcrew.bridges.indi.protocol import IndiProtocolError, ServerMessage, parse_element

__all__ = ["IndiStreamParser"]

#: Base64 text is 4/3 of the data plus line breaks; compressed data may exceed its original a bit.
_BLOB_SLACK_FACTOR = 1.5
_BLOB_SLACK_BYTES = 4096
_BLOB_START = b"<oneBLOB"
_BLOB_END = b"</oneBLOB>"


def _partial_tail(data: bytes, marker: bytes) -> int:
    """Length of the longest end of ``data`` that is a beginning of ``marker`` (a split marker)."""
    for size in range(min(len(marker) - 1, len(data)), 0, -1):
        if data.endswith(marker[:size]):
            return size
    return 0


class IndiStreamParser:
    """Feed bytes, get messages; one parser per connection."""

    def __init__(self) -> None:
        self._parser: XMLPullParser[Element] = XMLPullParser(events=("start", "end"))
        self._parser.feed(b"<indi>")
        self._root: Element | None = None
        self._depth = 0
        self._device = ""
        self._name = ""
        self._held = b""  # bytes kept back: a marker may continue in the next chunk
        self._blob: Element | None = None  # the oneBLOB whose text is being collected
        self._blob_parts: list[memoryview] = []
        self._blob_size = 0
        self._blob_limit = 0
        self._payloads: dict[Element, bytes] = {}
        self._messages: list[ServerMessage] = []
        self._read_events()

    def feed(self, data: bytes) -> list[ServerMessage]:
        """Parse ``data``; return the messages completed by it.

        Raises:
            IndiProtocolError: Malformed XML, bad values, or a BLOB larger than announced.
        """
        data, self._held = (self._held + data if self._held else data), b""
        position = 0
        try:
            while position < len(data):
                if self._blob is not None:
                    position = self._blob_text(data, position)
                else:
                    position = self._markup(data, position)
        except ParseError as exc:
            raise IndiProtocolError(
                f"malformed XML from the server: {exc}", device=self._device, name=self._name
            ) from None
        messages, self._messages = self._messages, []
        return messages

    def _markup(self, data: bytes, position: int) -> int:
        """Feed expat up to the next oneBLOB start tag; return where the rest begins."""
        start = data.find(_BLOB_START, position)
        if start < 0:
            keep = _partial_tail(data, _BLOB_START)
            self._expat(data[position : len(data) - keep])
            self._held = data[len(data) - keep :]
            return len(data)
        end = data.find(b">", start)
        if end < 0:
            self._expat(data[position:start])
            self._held = data[start:]
            return len(data)
        self._expat(data[position : end + 1])
        if data[end - 1 : end] != b"/" and self._blob is None:
            raise IndiProtocolError("<oneBLOB> outside a BLOB vector", device=self._device, name=self._name)
        return end + 1

    def _blob_text(self, data: bytes, position: int) -> int:
        """Collect base64 text up to ``</oneBLOB>``; return where what follows it begins."""
        end = data.find(_BLOB_END, position)
        stop = end
        if end < 0:
            stop = len(data) - _partial_tail(data, _BLOB_END)
            self._held = data[stop:]
        # Views, not copies: the text is copied once, when it is complete.
        self._blob_parts.append(memoryview(data)[position:stop])
        self._blob_size += stop - position
        if self._blob_size > self._blob_limit:
            member = self._blob.get("name", "") if self._blob is not None else ""
            raise IndiProtocolError(
                f"BLOB {member} is larger than announced: more than {self._blob_limit} bytes of text arrived",
                device=self._device,
                name=self._name,
            )
        if end < 0:
            return len(data)
        assert self._blob is not None
        self._payloads[self._blob] = b"".join(self._blob_parts)
        self._blob, self._blob_parts = None, []
        self._expat(_BLOB_END)
        return end + len(_BLOB_END)

    def close(self) -> None:
        """The connection ended: raise if it ended inside an element (a truncated message)."""
        truncated = self._depth > 1 or self._blob is not None
        if not truncated:
            try:  # ends the synthetic root: expat objects if a tag was left open halfway
                self._parser.feed(self._held + b"</indi>")
                self._parser.close()
            except ParseError:
                truncated = True
        if truncated:
            raise IndiProtocolError(
                "the stream ended inside a message (truncated XML)", device=self._device, name=self._name
            )

    @property
    def inside_message(self) -> bool:
        return self._depth > 1

    def _expat(self, data: bytes) -> None:
        if data:
            self._parser.feed(data)
            self._messages += self._read_events()

    def _read_events(self) -> list[ServerMessage]:
        messages: list[ServerMessage] = []
        # Only start and end events were asked for: each carries an element.
        for event, element in cast(Iterator[tuple[str, Element]], self._parser.read_events()):
            if event == "start":
                self._depth += 1
                if self._depth == 1:
                    self._root = element
                elif self._depth == 2:
                    self._device, self._name = element.get("device", ""), element.get("name", "")
                elif element.tag == "oneBLOB":
                    self._start_blob(element)
                continue
            self._depth -= 1
            if element.tag == "oneBLOB" and self._blob is element:
                self._blob = None  # <oneBLOB .../>: no text
            if self._depth == 1:
                payloads, self._payloads = self._payloads, {}
                message = parse_element(element, payloads)
                if self._root is not None:
                    self._root.remove(element)
                if message is not None:
                    messages.append(message)
        return messages

    def _start_blob(self, element: Element) -> None:
        member = element.get("name", "")
        try:
            size = int(element.get("size", "0"))
            encoded = int(element.get("enclen", "0"))
        except ValueError:
            raise IndiProtocolError(
                f"BLOB {member}: size or enclen is not an integer", device=self._device, name=self._name
            ) from None
        text = max(encoded, (size + 2) // 3 * 4)
        self._blob = element
        self._blob_parts, self._blob_size = [], 0
        self._blob_limit = int(text * _BLOB_SLACK_FACTOR) + _BLOB_SLACK_BYTES
