"""Incoming stanzas bounded while they stream in: size and nesting checked as the XML is parsed.

slixmpp feeds every chunk it receives to one ElementTree pull parser and hands on each stanza only
once it is whole, so a check on the finished tree comes after the whole cost of building it (a
2.7-MB call of small values held a module's event loop for seconds). :class:`BoundedPullParser`
is that parser with limits: it parses the data in slices, counts each top-level stanza's bytes and
nesting as its elements start, and once a stanza passes :data:`MAX_STANZA_BYTES` or
:data:`MAX_STANZA_DEPTH` it keeps none of its elements (each is dropped as it closes) and slixmpp
never sees the stanza. ``on_refused`` hears of it at once with what the opening tags said (who
sent it, its id and type, what it carries), so the refusal can be answered and logged.
"""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

from nightcrew.comm.rpc import MAX_ARGUMENT_DEPTH
from nightcrew.errors import CodecError

__all__ = [
    "MAX_EVENT_CHARS",
    "MAX_PAYLOAD_BYTES",
    "MAX_STANZA_BYTES",
    "MAX_STANZA_DEPTH",
    "BoundedPullParser",
    "RefusedStanza",
    "load_json_bounded",
    "too_large",
]

#: Largest stanza a module accepts (bytes of XML). Calls, results and events carry values, never
#: images (only VFS paths travel); parsing and decoding a stanza of this size of the smallest
#: values takes some tens of milliseconds, so no accepted stanza holds the event loop for long.
MAX_STANZA_BYTES = 1024 * 1024
#: Largest call, result or event payload a module sends: the stanza around it, and the stanza's size
#: being counted in slices, fit well within MAX_STANZA_BYTES.
MAX_PAYLOAD_BYTES = MAX_STANZA_BYTES - 64 * 1024
#: Deepest nesting of elements in a stanza: an XML-RPC value adds three per level (array, data,
#: value), so any value within MAX_ARGUMENT_DEPTH fits, with room for the envelope.
MAX_STANZA_DEPTH = 4 * MAX_ARGUMENT_DEPTH + 16
#: Longest event payload (characters of JSON): events say what happened in a few fields, and the
#: depth check before parsing costs up to ~20 ms at this size.
MAX_EVENT_CHARS = 64 * 1024
#: Bytes parsed between two checks: the size of a stanza is known to within one slice.
_SLICE = 16 * 1024


@dataclass(frozen=True)
class RefusedStanza:
    """A stanza refused while it streamed in, as far as its opening tags told."""

    tag: str  #: the stanza's tag, ``{jabber:client}iq``
    attrib: dict[str, str]  #: its attributes (``from``, ``id``, ``type``)
    reason: str  #: what was refused, e.g. "larger than 1048576 bytes"
    payload: str | None = None  #: tag of its first child, when that had arrived
    payload_attrib: dict[str, str] = field(default_factory=dict)  #: that child's attributes

    @property
    def kind(self) -> str:
        """``iq``, ``message`` or ``presence``."""
        return self.tag.rpartition("}")[2]

    @property
    def sender(self) -> str:
        return self.attrib.get("from", "")

    def describe(self) -> str:
        """The stanza in a few words for a log line: ``<iq type='set'> (jabber:iq:rpc query)``."""
        kind = f"<{self.kind} type='{self.attrib.get('type', '')}'>"
        if self.payload is None:
            return kind
        ns, _, local = (
            self.payload[1:].partition("}") if self.payload.startswith("{") else ("", "", self.payload)
        )
        what = self.payload_attrib.get("name")  # an event says its name
        return f"{kind} ({ns} {local}{' ' + what if what else ''})"


def too_large(text: str, limit: int = MAX_PAYLOAD_BYTES) -> bool:
    """Whether ``text`` takes more than ``limit`` bytes as UTF-8 (encoded only when it might)."""
    return len(text) > limit or (4 * len(text) > limit and len(text.encode("utf-8")) > limit)


class BoundedPullParser(ET.XMLPullParser):  # type: ignore[type-arg]
    """slixmpp's stream parser, refusing stanzas beyond the limits while they stream in.

    Only the events slixmpp acts on pass: the stream's opening and closing, and each accepted
    stanza as a start and an end at once when it is complete (slixmpp counts depth by them and
    ignores the elements inside).
    """

    def __init__(
        self,
        on_refused: Callable[[RefusedStanza], None],
        *,
        max_bytes: int = MAX_STANZA_BYTES,
        max_depth: int = MAX_STANZA_DEPTH,
    ) -> None:
        super().__init__(("start", "end"))
        self._on_refused = on_refused
        self._max_bytes = max_bytes
        self._max_depth = max_depth
        self._passed: list[tuple[str, ET.Element]] = []
        self._error: ET.ParseError | None = None
        self._root: ET.Element | None = None
        self._open: list[ET.Element] = []  # the current stanza and its open descendants
        self._bytes = 0  # of the current stanza, counted in slices
        self._refusal: str | None = None  # why the current stanza is refused

    def feed(self, data: bytes | str) -> None:  # type: ignore[override]  # slixmpp passes bytes
        for start in range(0, len(data), _SLICE):
            if self._error is not None:
                return  # the stream is broken: slixmpp ends it when it reads the error
            chunk = data[start : start + _SLICE]
            if self._open:
                self._bytes += len(chunk)
                if self._refusal is None and self._bytes > self._max_bytes:
                    self._refuse(f"larger than {self._max_bytes} bytes")
            super().feed(chunk)
            try:
                for item in super().read_events():
                    event, element = item  # type: ignore[misc]  # ("start" | "end", element)
                    self._on_event(event, element, len(chunk))  # type: ignore[arg-type]
            except ET.ParseError as exc:
                self._error = exc

    def read_events(self) -> Iterator[tuple[str, ET.Element]]:  # type: ignore[override]
        events, self._passed = self._passed, []
        yield from events
        if self._error is not None:
            raise self._error

    def _on_event(self, event: str, element: ET.Element, chunk: int) -> None:
        if event == "start":
            if self._root is None:
                self._root = element
                self._passed.append((event, element))
            elif not self._open:
                self._open.append(element)
                self._bytes, self._refusal = chunk, None
            else:
                self._open.append(element)
                if self._refusal is None and len(self._open) > self._max_depth:
                    self._refuse(f"nested deeper than {self._max_depth} elements")
            return
        if not self._open:  # the stream's root closed
            self._passed.append((event, element))
            return
        self._open.pop()
        if self._refusal is not None:
            if self._open:
                del self._open[-1][:]  # keep nothing of a refused stanza
            elif self._root is not None:
                del self._root[:]
            return
        if not self._open:
            self._passed += (("start", element), ("end", element))

    def _refuse(self, reason: str) -> None:
        self._refusal = reason
        stanza = self._open[0]
        payload = stanza[0] if len(stanza) else (self._open[1] if len(self._open) > 1 else None)
        self._on_refused(
            RefusedStanza(
                tag=stanza.tag,
                attrib=dict(stanza.attrib),
                reason=reason,
                payload=None if payload is None else payload.tag,
                payload_attrib={} if payload is None else dict(payload.attrib),
            )
        )
        del stanza[:]  # what was built so far goes at once


#: A JSON string (with its escapes), to blank out before brackets are counted.
_JSON_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')
_NOT_BRACKET = re.compile(r"[^\[\]{}]+")


def load_json_bounded(
    text: str, max_chars: int = MAX_EVENT_CHARS, max_depth: int = MAX_ARGUMENT_DEPTH
) -> Any:
    """``json.loads(text)``, refusing text longer than ``max_chars`` or nested deeper than
    ``max_depth`` before anything is built.

    Raises CodecError for too long, too deep or malformed text (the json module would recurse into
    a deep one until Python's recursion limit and raise RecursionError). Cost: a few passes of
    C-speed string operations over ``text``.
    """
    if len(text) > max_chars:
        raise CodecError(f"larger than {max_chars} characters")
    brackets = _NOT_BRACKET.sub("", _JSON_STRING.sub("", text))
    # Each pass removes the innermost (empty) pairs: the depth falls by one. A run of openers left
    # after k passes proves a depth of at least run + k, found at C speed.
    for done in range(max_depth + 1):
        if not brackets:
            break
        if _too_deep(brackets, max_depth + 1 - done):
            raise CodecError(f"nested deeper than {max_depth} levels")
        shorter = brackets.replace("[]", "").replace("{}", "")
        if len(shorter) == len(brackets):
            raise CodecError("not JSON: its brackets do not match")
        brackets = shorter
    try:
        return json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise CodecError(f"not JSON: {exc}") from None


def _too_deep(brackets: str, run: int) -> bool:
    """Whether ``brackets`` holds ``run`` openers in a row."""
    return re.search(f"[\\[{{]{{{run}}}", brackets) is not None
