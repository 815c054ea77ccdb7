"""Cutting the byte stream from an indiserver into messages, incrementally and with clear errors.

INDI is a sequence of top-level XML elements without a document element; the stream is parsed
with expat (``XMLPullParser``) inside a synthetic root. Each top-level element becomes a
:data:`~nightcrew.bridges.indi.protocol.ServerMessage` as soon as it ends and is then dropped.

Errors name the device and property of the element being read: malformed XML, a stream that ends
inside an element (truncated), and a BLOB whose text grows beyond what its ``size`` (or ``enclen``)
announced — cut off at once, before a lying server can fill the memory.
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


class IndiStreamParser:
    """Feed bytes, get messages; one parser per connection."""

    def __init__(self) -> None:
        self._parser: XMLPullParser[Element] = XMLPullParser(events=("start", "end"))
        self._parser.feed(b"<indi>")
        self._root: Element | None = None
        self._depth = 0
        self._device = ""
        self._name = ""
        self._blob_limit = 0  # bytes the open BLOB's text may still take; 0 when none is open
        self._blob_member = ""
        self._blob_fed = 0
        self._read_events()

    def feed(self, data: bytes) -> list[ServerMessage]:
        """Parse ``data``; return the messages completed by it.

        Raises:
            IndiProtocolError: Malformed XML, bad values, or a BLOB larger than announced.
        """
        if self._blob_limit:
            self._blob_fed += len(data)
            self._check_blob()
        try:
            self._parser.feed(data)
            return self._read_events()
        except ParseError as exc:
            raise IndiProtocolError(
                f"malformed XML from the server: {exc}", device=self._device, name=self._name
            ) from None

    def close(self) -> None:
        """The connection ended: raise if it ended inside an element (a truncated message)."""
        truncated = self._depth > 1
        if not truncated:
            try:  # ends the synthetic root: expat objects if a tag was left open halfway
                self._parser.feed(b"</indi>")
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

    def _check_blob(self) -> None:
        if self._blob_fed > self._blob_limit:
            raise IndiProtocolError(
                f"BLOB {self._blob_member} is larger than announced: more than {self._blob_limit} "
                "bytes of text arrived",
                device=self._device,
                name=self._name,
            )

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
            if element.tag == "oneBLOB":
                self._blob_limit = 0
            if self._depth == 1:
                message = parse_element(element)
                if self._root is not None:
                    self._root.remove(element)
                if message is not None:
                    messages.append(message)
        return messages

    def _start_blob(self, element: Element) -> None:
        self._blob_member = element.get("name", "")
        try:
            size = int(element.get("size", "0"))
            encoded = int(element.get("enclen", "0"))
        except ValueError:
            raise IndiProtocolError(
                f"BLOB {self._blob_member}: size or enclen is not an integer",
                device=self._device,
                name=self._name,
            ) from None
        text = max(encoded, (size + 2) // 3 * 4)
        self._blob_limit = int(text * _BLOB_SLACK_FACTOR) + _BLOB_SLACK_BYTES
        self._blob_fed = 0
