"""Cutting the byte stream from an indiserver into messages, incrementally and with clear errors.

INDI is a sequence of top-level XML elements without a document element; the stream is parsed
with expat (``XMLPullParser``) inside a synthetic root. Each top-level element becomes a
:data:`~nightcrew.bridges.indi.protocol.ServerMessage` as soon as it ends and is then dropped.

BLOBs take a short cut: expat sees a ``oneBLOB``'s tags but not its megabytes of base64 text,
which are decoded chunk by chunk as they arrive, up to ``</oneBLOB>`` (base64 holds no ``<``), and
handed to :func:`~nightcrew.bridges.indi.protocol.parse_element` beside the tree. Pushing the text
through expat's character handlers cost ten times the reading itself, and decoding while the rest
is still on the wire hides the decoding behind the transfer (bench/indi.py).

Errors name the device and property of the element being read: malformed XML, a stream that ends
inside an element (truncated), and a BLOB whose text grows beyond what its ``size`` (or
``enclen``) announced — cut off at once, before a lying server can fill the memory.
"""

from __future__ import annotations

import binascii
from collections.abc import Iterator
from typing import cast
from xml.etree.ElementTree import Element, ParseError, XMLPullParser

import pybase64

from nightcrew.bridges.indi.protocol import IndiProtocolError, ServerMessage, parse_element

__all__ = ["IndiStreamParser"]

#: Base64 text is 4/3 of the data plus line breaks; compressed data may exceed its original a bit.
_BLOB_SLACK_FACTOR = 1.5
_BLOB_SLACK_BYTES = 4096
_BLOB_START = b"<oneBLOB"
_BLOB_END = b"</oneBLOB>"
_WHITESPACE = b" \t\r\n"  # libindi breaks base64 lines; nothing else may sit between the quads


def _partial_tail(data: bytes, marker: bytes) -> int:
    """Length of the longest end of ``data`` that is a beginning of ``marker`` (a split marker)."""
    for size in range(min(len(marker) - 1, len(data)), 0, -1):
        if data.endswith(marker[:size]):
            return size
    return 0


class Base64Chunks:
    """Base64 text decoded as it arrives: whole 4-character quads now, the rest with the next chunk.

    indiserver sends a BLOB's text as one line: the fast path trims the ends and decodes the middle
    in place, strictly. Text broken into lines (other servers) takes the slow path, which removes
    the whitespace first. Raises ValueError (binascii.Error) when the text does not decode.
    """

    def __init__(self) -> None:
        self._parts: list[bytes] = []
        self._carry = b""  # the characters of a quad begun in the last chunk

    def feed(self, data: bytes, start: int, stop: int) -> None:
        while start < stop and (self._carry or data[start] in _WHITESPACE):
            if data[start] not in _WHITESPACE:  # completing the quad begun in the last chunk
                self._carry += data[start : start + 1]
                if len(self._carry) == 4:
                    self._parts.append(pybase64.b64decode(self._carry, validate=True))
                    self._carry = b""
            start += 1
        if start == stop:
            return
        while stop > start and data[stop - 1] in _WHITESPACE:
            stop -= 1
        cut = stop - (stop - start) % 4
        tail = data[cut:stop]
        if tail.translate(None, _WHITESPACE) == tail:
            try:
                self._parts.append(pybase64.b64decode(memoryview(data)[start:cut], validate=True))
                self._carry = tail
                return
            except ValueError:
                pass  # whitespace inside (or a bad character, which the slow path names)
        quads = data[start:stop].translate(None, _WHITESPACE)
        whole = len(quads) - len(quads) % 4
        self._parts.append(pybase64.b64decode(quads[:whole], validate=True))
        self._carry = quads[whole:]

    def finish(self) -> bytes:
        if self._carry:
            raise binascii.Error(f"the text ends with {len(self._carry)} characters of an incomplete quad")
        return b"".join(self._parts)


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
        self._blob_text_chunks = Base64Chunks()
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
        assert self._blob is not None
        member = self._blob.get("name", "")
        self._blob_size += stop - position
        if self._blob_size > self._blob_limit:
            raise IndiProtocolError(
                f"BLOB {member} is larger than announced: more than {self._blob_limit} bytes of text arrived",
                device=self._device,
                name=self._name,
            )
        try:
            self._blob_text_chunks.feed(data, position, stop)
            if end < 0:
                return len(data)
            self._payloads[self._blob] = self._blob_text_chunks.finish()
        except ValueError as exc:  # binascii.Error is a ValueError
            raise IndiProtocolError(
                f"BLOB {member} cannot be decoded: {exc}", device=self._device, name=self._name
            ) from None
        self._blob, self._blob_text_chunks = None, Base64Chunks()
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
        self._blob_text_chunks, self._blob_size = Base64Chunks(), 0
        self._blob_limit = int(text * _BLOB_SLACK_FACTOR) + _BLOB_SLACK_BYTES
