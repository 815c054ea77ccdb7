"""slixmpp's client with nightcrew's handlers in front, and its input parsed at a bounded pace.

Only :mod:`._connection` uses this. It overrides three of slixmpp's stream methods (pinned in
pyproject; every XMPP test goes through them): ``_spawn_event`` (each top-level element),
``init_parser`` (the parser of each new stream: bounded, see :mod:`._stanza_limits`) and
``data_received`` (what the socket read).
"""

from __future__ import annotations

import asyncio
import logging
import re
import xml.etree.ElementTree as ET
from collections import deque
from collections.abc import Callable
from typing import Any

import slixmpp

from nightcrew.comm.xmpp._stanza_limits import BoundedPullParser, RefusedStanza

__all__ = ["StanzaHandler", "TagMatcher", "XmppClient"]

log = logging.getLogger("nightcrew.comm.xmpp._connection")  # one logger for the session's lines

#: Gets an incoming stanza's element; returns True when it consumed it (slixmpp never sees it).
StanzaHandler = Callable[[ET.Element], bool]
#: ``{ns}stanza`` or ``{ns}stanza/{ns}child`` (namespaces may contain slashes).
_STANZA_PATH = re.compile(r"(?P<root>\{[^}]*\}[^/{}]+)(?:/(?P<child>\{[^}]*\}[^/{}]+))?")
#: Bytes parsed per turn of the event loop: the socket may deliver megabytes at once, and parsing
#: them in one go would hold every other task of the module for as long.
_PARSE_SLICE = 64 * 1024
#: Bytes waiting to be parsed above which the socket is not read (TCP pushes back on the sender).
_BACKLOG_LIMIT = 1024 * 1024


class TagMatcher:
    """Matches ``{ns}stanza[/{ns}child]`` by comparing tags.

    Every incoming stanza is tried against every handler: a tag comparison (plus a C-level
    ``find`` for the child) costs next to nothing, unlike slixmpp's XPath matchers.
    """

    __slots__ = ("_child", "_root")

    def __init__(self, xpath: str) -> None:
        parsed = _STANZA_PATH.fullmatch(xpath)
        if parsed is None:
            raise ValueError(f"unsupported stanza path {xpath!r}")
        self._root: str = parsed["root"]
        self._child: str | None = parsed["child"]

    def match(self, element: ET.Element) -> bool:
        if element.tag != self._root:
            return False
        return self._child is None or element.find(self._child) is not None


class XmppClient(slixmpp.ClientXMPP):
    """slixmpp's client with nightcrew's handlers in front of its stanza machinery.

    slixmpp wraps every stanza in a stanza object, runs its filters and tries its ~17 handlers;
    for a remote call that was about a third of both sides' CPU time. nightcrew's handlers take
    the parsed element directly; what they do not consume (stream negotiation, disco, IQs slixmpp
    waits for) takes slixmpp's way as before. What it overrides of slixmpp is listed in this
    module's docstring.
    """

    def __init__(
        self,
        handlers: list[tuple[str, TagMatcher, StanzaHandler]],
        on_refused: Callable[[RefusedStanza], None],
        *args: Any,
        **kwargs: Any,
    ):
        super().__init__(*args, **kwargs)
        self._nightcrew_handlers = handlers
        self._on_refused = on_refused
        self._backlog: deque[bytes] = deque()  # received, not parsed yet
        self._parsed = 0  # bytes of the backlog's first chunk parsed already
        self._backlog_bytes = 0
        self._paused = False

    def init_parser(self) -> None:
        """slixmpp's parser for each new stream, bounded (see :mod:`._stanza_limits`)."""
        super().init_parser()
        self.parser = BoundedPullParser(self._on_refused)
        self._backlog.clear()  # a new stream: what the old one left unparsed belongs to it
        self._parsed = self._backlog_bytes = 0
        self._paused = False  # a new connection's transport reads

    def data_received(self, data: bytes | str) -> None:
        """Parse ``data`` at most :data:`_PARSE_SLICE` bytes per turn of the event loop."""
        if isinstance(data, str):
            data = data.encode("utf-8")
        if not self._backlog and len(data) <= _PARSE_SLICE:
            super().data_received(data)  # the usual case: a few stanzas, parsed at once
            return
        self._backlog.append(data)
        self._backlog_bytes += len(data)
        if len(self._backlog) == 1:
            asyncio.get_running_loop().call_soon(self._parse_backlog)
        if self._backlog_bytes > _BACKLOG_LIMIT and not self._paused and self.transport is not None:
            self._paused = True
            self.transport.pause_reading()

    def _parse_backlog(self) -> None:
        if not self._backlog:
            return
        first = self._backlog[0]
        data = first[self._parsed : self._parsed + _PARSE_SLICE]
        self._parsed += len(data)
        if self._parsed == len(first):
            self._backlog.popleft()
            self._parsed = 0
        self._backlog_bytes -= len(data)
        if self.parser is None:  # the stream ended meanwhile
            self._backlog.clear()
            self._parsed = self._backlog_bytes = 0
        else:
            super().data_received(data)
        if self._backlog:
            asyncio.get_running_loop().call_soon(self._parse_backlog)
        if self._paused and self._backlog_bytes <= _BACKLOG_LIMIT // 2 and self.transport is not None:
            self._paused = False
            self.transport.resume_reading()

    def _spawn_event(self, xml: ET.Element) -> None:
        consumed = False
        for name, matcher, handler in self._nightcrew_handlers:
            if matcher.match(xml):
                try:
                    consumed = handler(xml) or consumed
                except Exception:
                    log.exception("handler '%s' failed on a stanza", name)
                    consumed = True
        if consumed:
            if log.isEnabledFor(logging.DEBUG):
                log.debug("RECV: %s", ET.tostring(xml, encoding="unicode"))
        else:
            super()._spawn_event(xml)
