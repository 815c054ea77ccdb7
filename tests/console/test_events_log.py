"""Events and log records: relayed live, kept for a fresh page, sent from the browser; slow browsers."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Callable
from typing import Any

from nightcrew.events import TestEvent
from nightcrew.modules import Module
from nightcrew.modules.console._relay import Client, Relay
from nightcrew.modules.test import StandAlone

from .conftest import (
    OPERATOR,
    OPERATOR_PASSWORD,
    VIEWER,
    VIEWER_PASSWORD,
    ApiClient,
    Observatory,
    eventually,
    open_socket,
)


class Listener(Module):
    """Keeps the TestEvents it hears."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.heard: list[tuple[str, str]] = []

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(TestEvent, self.on_test_event)

    async def on_test_event(self, event: TestEvent, sender: str) -> None:
        self.heard.append((event.message, sender))


async def test_an_event_reaches_the_page_and_stays_for_the_next_one(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    sender = await observatory.start(Listener, "sender")
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(VIEWER, VIEWER_PASSWORD)
    socket = await open_socket(client)
    await sender.comm.send_event(TestEvent(message="clear skies"))
    message = await socket.wait_for(lambda m: m["type"] == "event", "the event")
    assert message["sender"] == "sender" and message["event"] == "TestEvent"
    assert message["fields"] == {"message": "clear skies"} and message["time"].startswith("2024-01-15")
    status, body = await client.get("/api/events/recent", type="TestEvent", sender="sender")
    assert status == 200 and [e["fields"]["message"] for e in body["events"]] == ["clear skies"]
    assert (await client.get("/api/events/recent", type="NewImageEvent"))[1]["events"] == []


async def test_the_operator_sends_an_event_with_its_fields(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    listener = await observatory.start(Listener, "listener")
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    types = (await client.get("/api/events/types"))[1]["types"]
    assert types["TestEvent"]["fields"] == [
        {"name": "message", "type": "str", "required": False, "default": "", "choices": None}
    ]
    assert [f["name"] for f in types["BadWeatherEvent"]["fields"]] == ["reason"]
    assert await client.post("/api/events", {"type": "TestEvent", "fields": {"message": "hi"}}) == (
        200,
        {"ok": True},
    )
    await eventually(lambda: listener.heard == [("hi", "console")], "the listener hearing it")
    recent = (await client.get("/api/events/recent", sender="console"))[1]["events"]
    assert [(e["event"], e["fields"]) for e in recent] == [("TestEvent", {"message": "hi"})]
    status, body = await client.post("/api/events", {"type": "NoSuchEvent", "fields": {}})
    assert status == 404 and "unknown event type 'NoSuchEvent'" in body["error"]["message"]
    status, body = await client.post("/api/events", {"type": "TestEvent", "fields": {"message": 3}})
    assert status == 400 and body["error"]["class"] == "CodecError"
    status, body = await client.post("/api/events", {"type": "MoveRaDecEvent", "fields": {"ra": 1.0}})
    assert status == 400 and "dec" in body["error"]["message"]


async def test_log_records_arrive_with_their_module_and_level(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(VIEWER, VIEWER_PASSWORD)
    socket = await open_socket(client)
    await observatory.start(StandAlone, "hello", message="all is well", interval=10.0)
    record = await socket.wait_for(lambda m: m["type"] == "log" and m["module"] == "hello", "its log")
    assert record["level"] == "INFO" and record["message"] in ("all is well", "hello is ready")
    await eventually(
        lambda: any(r["message"] == "all is well" for r in console.log_records), "the message in the log"
    )
    status, body = await client.get("/api/log", module="hello")
    assert status == 200 and {r["module"] for r in body["records"]} == {"hello"}
    assert (await client.get("/api/log", level="ERROR"))[1]["records"] == []
    await client.login(VIEWER, "wrong")
    own = (await client.get("/api/log", module="console", level="WARNING"))[1]["records"]
    assert [r["message"] for r in own] == ["console: failed login from 127.0.0.1"]
    status, body = await client.get("/api/log", level="LOUD")
    assert status == 400 and "unknown log level 'LOUD'" in body["error"]["message"]


async def test_a_slow_browser_loses_messages_not_the_console() -> None:
    relay = Relay()
    slow, quick = Client("a", size=4), Client("b", size=100)
    relay.add(slow)
    relay.add(quick)
    for number in range(10):
        relay.send({"type": "event", "n": number})  # never waits, whoever is behind
    assert slow.dropped == 6 and quick.dropped == 0 and relay.dropped_total == 6
    received: list[dict[str, Any]] = []

    async def send(text: str) -> None:
        received.append(json.loads(text))

    pump = asyncio.create_task(slow.pump(send))
    await eventually(lambda: len(received) == 5, "the four kept messages and the notice")
    pump.cancel()
    assert [m["n"] for m in received if m["type"] == "event"] == [0, 1, 2, 3]
    assert {"type": "dropped", "count": 6} in received  # once the queue has room again
    relay.remove(slow)
    assert relay.dropped_total == 6 and relay.clients == {quick}


async def test_a_browser_that_stops_reading_holds_up_neither_the_console_nor_the_others(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    sender = await observatory.start(Listener, "sender")
    console = await observatory.start_console()
    stalled, reader = clients(console.url), clients(console.url)
    for client in (stalled, reader):
        await client.login(VIEWER, VIEWER_PASSWORD)
    unread = await open_socket(stalled)  # and never read again (kept: a lost reference closes it)
    live = await open_socket(reader)
    received = 0

    async def read_all() -> None:
        nonlocal received
        async for message in live.socket:
            if json.loads(message.data)["type"] == "event":
                received += 1

    reading = asyncio.create_task(read_all())
    count, text = 3000, "x" * 10_000  # 30 MB: more than the sockets' buffers hold
    for number in range(count):
        await sender.comm.send_event(TestEvent(message=f"{number} {text}"))
        if number % 20 == 19:  # a reader that keeps up: it must get every one
            await eventually(lambda: received == number + 1, "the reader keeping up")  # noqa: B023
    drops = sorted(c.dropped for c in console.relay.clients)
    reading.cancel()
    assert drops[0] == 0 and drops[1] > 0, drops  # only the stalled browser lost messages
    assert (await reader.get("/api/modules"))[0] == 200
    assert not unread.socket.closed
