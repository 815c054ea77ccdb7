"""A person on the observatory's XMPP server: a real second client (slixmpp), as a chat app would be."""

from __future__ import annotations

import asyncio
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable
from pathlib import Path
from typing import Any

import slixmpp

from tests.comm.xmpp_servers import XmppServer

__all__ = ["Heard", "Person"]

Heard = tuple[str, str, float]  # (sender's bare JID, text, time.monotonic() on arrival)


class Person:
    """Logs in as ``name`` on ``server``, says things, and keeps every chat message heard."""

    def __init__(self, server: XmppServer, name: str) -> None:
        account = server.account(name)
        self.jid = account.jid
        self._server = server
        self.client = slixmpp.ClientXMPP(account.jid, account.password)
        if server.ca_file:
            self.client.ca_certs = Path(server.ca_file)
        self.heard: list[Heard] = []
        self._changed = asyncio.Condition()
        self.client.add_event_handler("message", self._on_message)

    async def connect(self) -> None:
        session: asyncio.Future[None] = asyncio.get_running_loop().create_future()

        def started(_: Any) -> None:
            self.client.send_presence()  # available: messages to the bare JID reach this client
            if not session.done():
                session.set_result(None)

        self.client.add_event_handler("session_start", started)
        self.client.connect("127.0.0.1", self._server.port)
        await asyncio.wait_for(session, 20.0)

    async def close(self) -> None:
        await asyncio.wait_for(self.client.disconnect(wait=1.0), 5.0)

    async def _on_message(self, message: Any) -> None:
        if message["type"] not in ("chat", "normal") or not message["body"]:
            return
        async with self._changed:
            self.heard.append((message["from"].bare, message["body"], time.monotonic()))
            self._changed.notify_all()

    async def wait_for(self, match: Callable[[str], bool], what: str, *, since: int = 0) -> Heard:
        """The first message heard (the ``since``-th or later) whose text ``match``es."""
        try:
            async with asyncio.timeout(20.0), self._changed:
                while True:
                    for heard in self.heard[since:]:
                        if match(heard[1]):
                            return heard
                    await self._changed.wait()
        except TimeoutError:
            texts = [text for _, text, _ in self.heard]
            raise AssertionError(f"{self.jid} heard no {what}; heard {texts}") from None

    async def say(self, to: str, text: str, expect: str, *, delayed_since: str | None = None) -> str:
        """What ``to`` answers to ``text`` (the first new message containing ``expect``); with
        ``delayed_since`` (an ISO time) the message carries a XEP-0203 delay, as one kept by a
        server while its receiver was offline."""
        before = len(self.heard)
        message = self.client.make_message(mto=slixmpp.JID(to), mbody=text, mtype="chat")
        if delayed_since is not None:
            delay = ET.Element("{urn:xmpp:delay}delay", {"stamp": delayed_since, "from": self.jid})
            message.xml.append(delay)
        message.send()
        return (await self.wait_for(lambda t: expect in t, f"reply to {text!r}", since=before))[1]
