"""A console on a small in-process observatory of simulated devices, and a client of its HTTP API.

The console listens on 127.0.0.1 (a free port) and is reached over real HTTP and WebSockets with
aiohttp's client, as a browser would: session cookie, CSRF header, JSON.
"""

from __future__ import annotations

import asyncio
import json
from collections.abc import AsyncIterator, Callable
from pathlib import Path
from typing import Any

import aiohttp
import pytest

from nightcrew.modules.console import WebConsole, hash_password
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.testing import SITE
from nightcrew.testing import Observatory as ModulesObservatory

__all__ = ["SITE", "ApiClient", "Observatory", "Socket", "eventually", "open_socket"]

OPERATOR, OPERATOR_PASSWORD = "olga", "operator-password-1"
VIEWER, VIEWER_PASSWORD = "vera", "viewer-password-2"
ACCOUNTS = {
    OPERATOR: {"password_hash": hash_password(OPERATOR_PASSWORD), "role": "operator"},
    VIEWER: {"password_hash": hash_password(VIEWER_PASSWORD), "role": "viewer"},
}
#: Wall seconds a test waits for something that takes milliseconds.
PATIENCE = 20.0


class Observatory(ModulesObservatory):
    """The modules' test observatory (one network, one fast clock, one in-memory VFS), plus a console."""

    async def start_console(self, **kwargs: Any) -> WebConsole:
        kwargs.setdefault("port", 0)
        kwargs.setdefault("accounts", ACCOUNTS)
        kwargs.setdefault("status_interval", 0.05)
        return await self.start(WebConsole, "console", **kwargs)


class ApiClient:
    """A browser stand-in: a cookie jar, the CSRF token of its session, JSON in and out."""

    def __init__(self, base: str) -> None:
        self.base = base
        # unsafe=True: keep cookies of an IP-address host (127.0.0.1), as browsers do.
        self.http = aiohttp.ClientSession(cookie_jar=aiohttp.CookieJar(unsafe=True))
        self.csrf = ""

    async def login(self, user: str, password: str) -> tuple[int, dict[str, Any]]:
        status, body = await self.post("/api/login", {"user": user, "password": password})
        if status == 200:
            self.csrf = body["csrf_token"]
        return status, body

    async def get(self, path: str, **params: Any) -> tuple[int, Any]:
        async with self.http.get(self.base + path, params=params) as response:
            return response.status, await response.json()

    async def get_bytes(self, path: str, **params: Any) -> tuple[int, bytes, dict[str, str]]:
        async with self.http.get(self.base + path, params=params) as response:
            return response.status, await response.read(), dict(response.headers)

    async def post(self, path: str, body: Any, *, csrf: str | None = None) -> tuple[int, Any]:
        headers = {"X-CSRF-Token": self.csrf if csrf is None else csrf}
        async with self.http.post(self.base + path, json=body, headers=headers) as response:
            return response.status, await response.json()

    async def call(self, module: str, method: str, *args: Any) -> tuple[int, Any]:
        return await self.post("/api/call", {"module": module, "method": method, "args": list(args)})

    async def close(self) -> None:
        await self.http.close()


class Socket:
    """A WebSocket of the console, with the messages it received so far."""

    def __init__(self, socket: aiohttp.ClientWebSocketResponse) -> None:
        self.socket = socket
        self.messages: list[dict[str, Any]] = []

    async def wait_for(self, match: Callable[[dict[str, Any]], bool], what: str) -> dict[str, Any]:
        """The first message (received before or after now) for which ``match`` holds."""
        for seen in self.messages:
            if match(seen):
                return seen
        async with asyncio.timeout(PATIENCE):
            while True:
                received = await self.socket.receive()
                if received.type is not aiohttp.WSMsgType.TEXT:
                    raise AssertionError(
                        f"socket closed ({received.type}, {received.data}) waiting for {what}"
                    )
                message: dict[str, Any] = json.loads(received.data)
                self.messages.append(message)
                if match(message):
                    return message


async def open_socket(client: ApiClient) -> Socket:
    socket = Socket(await client.http.ws_connect(client.base + "/api/ws"))
    await socket.wait_for(lambda m: m["type"] == "hello", "hello")
    return socket


async def eventually(condition: Callable[[], Any], what: str) -> None:
    """Wait (polling, bounded) until ``condition()`` is true."""
    async with asyncio.timeout(PATIENCE):
        while not await _value(condition()):  # noqa: ASYNC110 - polling a state from outside
            await asyncio.sleep(0.01)
    assert await _value(condition()), what


async def _value(value: Any) -> Any:
    return await value if asyncio.iscoroutine(value) else value


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    obs = Observatory(speed=100.0)
    try:
        yield obs
    finally:
        await obs.close()


@pytest.fixture
async def archive(tmp_path: Path, observatory: Observatory) -> AsyncIterator[SqliteTaskArchive]:
    """An opened SQLite task archive in ``tmp_path/tasks.sqlite`` on the observatory's clock, closed
    after the observatory's modules (which may use it)."""
    opened = SqliteTaskArchive(tmp_path / "tasks.sqlite", clock=observatory.clock, poll_interval=0)
    await opened.open()
    try:
        yield opened
    finally:
        await observatory.close()
        await opened.close()


@pytest.fixture
async def clients() -> AsyncIterator[Callable[[str], ApiClient]]:
    """Makes API clients for a console URL; all closed after the test."""
    made: list[ApiClient] = []

    def make(base: str) -> ApiClient:
        client = ApiClient(base.rstrip("/"))
        made.append(client)
        return client

    try:
        yield make
    finally:
        for client in made:
            await client.close()
