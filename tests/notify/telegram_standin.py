"""A stand-in for Telegram's Bot API servers, which tests cannot reach: on 127.0.0.1, in this process.

It answers the documented Bot API methods the Telegram module uses — ``getMe``, ``getUpdates``
(long polling with ``offset`` and ``timeout``), ``sendMessage``, ``deleteMessage`` — at
``/bot<token>/<method>``, with the API's envelope (``{"ok": true, "result": ...}``, errors with
``error_code`` and ``description``, 429 with ``retry_after``). Parameters come as the API allows:
query string, form or JSON. A test plays the people (:meth:`BotApiStandIn.person_says`), reads
what the bot sent (:meth:`BotApiStandIn.wait_for`), and can make a chat refuse messages (a person
who blocked the bot) or throttle the next ones (Telegram's flood control).
"""

from __future__ import annotations

import asyncio
import json
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from aiohttp import web

__all__ = ["BotApiStandIn", "Sent"]

BOT_ID = 4242


@dataclass(frozen=True)
class Sent:
    chat_id: int
    text: str
    wall: float  # time.monotonic() when it arrived


class BotApiStandIn:
    """The Bot API for one bot ``token``; :meth:`start` listens on a free loopback port."""

    def __init__(self, token: str) -> None:
        self.token = token
        self.sent: list[Sent] = []
        self.blocked: set[int] = set()
        #: sendMessage calls still to answer with 429 (Telegram's flood control), and how long to wait.
        self.throttle = 0
        self.retry_after = 1
        self.calls: list[str] = []
        #: (chat id, message id) of the messages the bot deleted.
        self.deleted: list[tuple[int, int]] = []
        self._updates: list[dict[str, Any]] = []
        self._next_update = 1
        self._next_message = 1
        self._changed = asyncio.Condition()
        self._runner: web.AppRunner | None = None
        self._closing = False
        self.base_url = ""

    async def start(self) -> None:
        app = web.Application()
        app.router.add_route("*", "/bot{token}/{method}", self._handle)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, "127.0.0.1", 0)
        await site.start()
        port = self._runner.addresses[0][1]
        self.base_url = f"http://127.0.0.1:{port}/bot"

    async def close(self) -> None:
        async with self._changed:  # long polls waiting end now, not at their timeout
            self._closing = True
            self._changed.notify_all()
        if self._runner is not None:
            await self._runner.cleanup()

    async def person_says(
        self, user_id: int, text: str, *, group: int | None = None, sent: float | None = None
    ) -> None:
        """A private message from Telegram user ``user_id`` to the bot (or one in ``group``),
        sent at Unix time ``sent`` (now by default)."""
        chat = {"id": user_id, "type": "private", "first_name": f"user{user_id}"}
        if group is not None:
            chat = {"id": group, "type": "group", "title": "observers"}
        async with self._changed:
            self._updates.append(
                {
                    "update_id": self._next_update,
                    "message": {
                        "message_id": self._new_message_id(),
                        "date": int(time.time() if sent is None else sent),
                        "chat": chat,
                        "from": {"id": user_id, "is_bot": False, "first_name": f"user{user_id}"},
                        "text": text,
                    },
                }
            )
            self._next_update += 1
            self._changed.notify_all()

    async def wait_for(
        self, chat_id: int, match: Callable[[str], bool], what: str, *, since: int = 0, patience: float = 20.0
    ) -> Sent:
        """The first message to ``chat_id`` (the ``since``-th sent or later) whose text ``match``es."""
        try:
            async with asyncio.timeout(patience), self._changed:
                while True:
                    for sent in self.sent[since:]:
                        if sent.chat_id == chat_id and match(sent.text):
                            return sent
                    await self._changed.wait()
        except TimeoutError:
            raise AssertionError(f"no message to {chat_id}: {what}; got {self.texts(chat_id)}") from None

    async def wait_for_deletions(self, count: int) -> list[tuple[int, int]]:
        """The deleted messages, once there are ``count``."""
        async with asyncio.timeout(20.0), self._changed:
            await self._changed.wait_for(lambda: len(self.deleted) >= count)
        return list(self.deleted)

    def texts(self, chat_id: int) -> list[str]:
        return [s.text for s in self.sent if s.chat_id == chat_id]

    def _new_message_id(self) -> int:
        self._next_message += 1
        return self._next_message

    async def _handle(self, request: web.Request) -> web.Response:
        if request.match_info["token"] != self.token:
            return _error(401, "Unauthorized")
        method = request.match_info["method"]
        params: dict[str, Any] = dict(request.query)
        if request.content_type == "application/json":
            params.update(await request.json())
        elif request.can_read_body:
            params.update(await request.post())
        self.calls.append(method)
        if method == "getMe":
            return _ok(
                {"id": BOT_ID, "is_bot": True, "first_name": "Observatory", "username": "observatory_bot"}
            )
        if method == "getUpdates":
            return _ok(
                await self._get_updates(int(params.get("offset") or 0), float(params.get("timeout") or 0))
            )
        if method == "sendMessage":
            return await self._send_message(int(params["chat_id"]), str(params["text"]))
        if method == "deleteMessage":
            async with self._changed:
                self.deleted.append((int(params["chat_id"]), int(params["message_id"])))
                self._changed.notify_all()
            return _ok(True)
        return _error(404, "Not Found: method not found")

    async def _get_updates(self, offset: int, wait: float) -> list[dict[str, Any]]:
        async with self._changed:
            self._updates = [u for u in self._updates if u["update_id"] >= offset]
            if not self._updates and wait > 0:
                try:
                    async with asyncio.timeout(wait):
                        await self._changed.wait_for(lambda: bool(self._updates) or self._closing)
                except TimeoutError:
                    pass
            return list(self._updates)

    async def _send_message(self, chat_id: int, text: str) -> web.Response:
        if self.throttle > 0:
            self.throttle -= 1
            body = {
                "ok": False,
                "error_code": 429,
                "description": f"Too Many Requests: retry after {self.retry_after}",
                "parameters": {"retry_after": self.retry_after},
            }
            return web.Response(status=429, text=json.dumps(body), content_type="application/json")
        if chat_id in self.blocked:
            return _error(403, "Forbidden: bot was blocked by the user")
        if not text or len(text) > 4096:
            return _error(400, "Bad Request: message text is empty or too long")
        async with self._changed:
            self.sent.append(Sent(chat_id, text, time.monotonic()))
            self._changed.notify_all()
        return _ok(
            {
                "message_id": self._new_message_id(),
                "date": int(time.time()),
                "chat": {"id": chat_id, "type": "private"},
                "from": {"id": BOT_ID, "is_bot": True, "first_name": "Observatory"},
                "text": text,
            }
        )


def _ok(result: Any) -> web.Response:
    return web.Response(text=json.dumps({"ok": True, "result": result}), content_type="application/json")


def _error(code: int, description: str) -> web.Response:
    body = {"ok": False, "error_code": code, "description": description}
    return web.Response(status=code, text=json.dumps(body), content_type="application/json")
