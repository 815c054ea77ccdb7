"""A small Alpaca server on 127.0.0.1 that misbehaves on purpose (fault tests of the client side).

alpaca-simulators behaves well; a device that answers with garbage, hangs or sends a broken image
has to be made. Each device member can be given a reply; unknown members answer like a connected
device with Value true.
"""

from __future__ import annotations

import asyncio
import json
from collections.abc import Awaitable, Callable
from typing import Any

from aiohttp import web

Reply = Callable[[web.Request], Awaitable[web.StreamResponse]]


def value(v: Any) -> Reply:
    async def reply(request: web.Request) -> web.StreamResponse:
        return web.json_response({"Value": v, "ErrorNumber": 0, "ErrorMessage": ""})

    return reply


def alpaca_error(number: int, message: str) -> Reply:
    async def reply(request: web.Request) -> web.StreamResponse:
        return web.json_response({"ErrorNumber": number, "ErrorMessage": message})

    return reply


def raw(body: bytes, content_type: str = "application/json", status: int = 200) -> Reply:
    async def reply(request: web.Request) -> web.StreamResponse:
        return web.Response(body=body, content_type=content_type, status=status)

    return reply


def image_bytes(payload: bytes) -> Reply:
    return raw(payload, "application/imagebytes")


def json_image(array: list[list[int]], element_type: int = 2) -> Reply:
    body = json.dumps({"Value": array, "Type": element_type, "Rank": 2, "ErrorNumber": 0, "ErrorMessage": ""})
    return raw(body.encode())


class FaultyServer:
    """Serves ``/api/v1/{type}/{number}/{member}`` from :attr:`replies` (member -> reply)."""

    def __init__(self) -> None:
        self.replies: dict[str, Reply] = {}
        self.requests: list[tuple[str, str, dict[str, str]]] = []
        self.release = asyncio.Event()  # set to free hanging replies
        self._runner: web.AppRunner | None = None
        self.url = ""

    def hang(self) -> Reply:
        async def reply(request: web.Request) -> web.StreamResponse:
            await self.release.wait()
            return web.json_response({"Value": True, "ErrorNumber": 0, "ErrorMessage": ""})

        return reply

    async def _handle(self, request: web.Request) -> web.StreamResponse:
        member = request.match_info["member"]
        fields = (
            dict(request.query)
            if request.method == "GET"
            else {k: str(v) for k, v in (await request.post()).items()}
        )
        self.requests.append((request.method, member, fields))
        reply = self.replies.get(member, value(True))
        return await reply(request)

    async def start(self) -> None:
        app = web.Application()
        app.router.add_route("*", "/api/v1/{device_type}/{number}/{member}", self._handle)
        self._runner = web.AppRunner(app)
        await self._runner.setup()
        site = web.TCPSite(self._runner, "127.0.0.1", 0)
        await site.start()
        port = self._runner.addresses[0][1]
        self.url = f"http://127.0.0.1:{port}"

    async def stop(self) -> None:
        self.release.set()
        if self._runner is not None:
            await self._runner.cleanup()
