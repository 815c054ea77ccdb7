"""Sends the checks of :mod:`tests.alpaca.conformance` to a server and judges each answer."""

from __future__ import annotations

import asyncio
import json
import time
from typing import Any

import aiohttp

from nightcrew.bridges.alpaca.imagebytes import ImageBytesError, decode_header

from .conformance import (
    CLIENT_ID,
    INVALID_VALUE,
    NOT_IMPLEMENTED,
    TRANSACTION_ID,
    Check,
    Current,
    Outcome,
    common_checks,
)
from .conformance_devices import device_checks

__all__ = ["judge", "run_device_checks"]

_IMAGEBYTES = "application/imagebytes"
_REPLY_KEYS = ("ClientTransactionID", "ServerTransactionID", "ErrorNumber", "ErrorMessage")
#: Wall seconds a check may wait for a motion it started (a filter or focuser moving nowhere).
_MOTION_WAIT = 10.0


async def run_device_checks(
    session: aiohttp.ClientSession, url: str, device_type: str, number: int
) -> list[Outcome]:
    """Connect, run every check for the device in ConformU's order, disconnect; the outcomes."""
    base = f"/api/v1/{device_type}/{number}"
    connect = Check("PUT Connected=True", "PUT", f"{base}/connected", _ids_and(("Connected", "True")))
    outcomes = [await run_check(session, url, connect)]
    version = await _read(session, url, f"{base}/interfaceversion")
    checks = common_checks(device_type, number, version if isinstance(version, int) else 1)
    checks += device_checks(device_type, number)
    for check in checks:
        outcomes.append(await run_check(session, url, check))
    disconnect = Check("PUT Connected=False", "PUT", f"{base}/connected", _ids_and(("Connected", "False")))
    outcomes.append(await run_check(session, url, disconnect))
    return outcomes


def _ids_and(*params: tuple[str, str]) -> tuple[tuple[str, str | Current], ...]:
    return (("ClientID", CLIENT_ID), ("ClientTransactionID", TRANSACTION_ID), *params)


async def run_check(session: aiohttp.ClientSession, url: str, check: Check) -> Outcome:
    base = check.path.rsplit("/", 1)[0]
    params = [(name, await _resolve(session, url, base, value)) for name, value in check.params]
    # As ConformU asks for images: ImageBytes preferred, JSON accepted.
    headers = {"Accept": f"{_IMAGEBYTES}, application/json"} if check.image_array else {}
    try:
        if check.method == "GET":
            request = session.get(url + check.path, params=params, headers=headers)
        else:
            request = session.request(check.method, url + check.path, data=params, params=check.query)
        async with request as response:
            status, content_type, payload = response.status, response.content_type, await response.read()
    except aiohttp.ClientError as exc:
        return Outcome(check, f"no answer: {exc!r}")
    if status == 200 and content_type == _IMAGEBYTES:
        problem, text = _judge_imagebytes(check, payload, params), f"<{len(payload)} bytes of ImageBytes>"
    else:
        text = payload.decode("utf-8", errors="replace")
        problem = judge(check, status, content_type, text, params)
    if check.wait_while is not None:
        await _wait_while(session, url, base, *check.wait_while)
    return Outcome(check, problem, {"status": status, "body": text[:300]})


def judge(check: Check, status: int, content_type: str, text: str, params: list[tuple[str, str]]) -> str:
    """What is wrong with an answer, empty when it conforms (ConformU's tolerant rules)."""
    if not check.statuses:
        return ""
    body: dict[str, Any] | None = None
    if status == 200:
        try:
            loaded = json.loads(text)
        except ValueError:
            return f"HTTP 200 but the body is not JSON ({content_type})"
        if not isinstance(loaded, dict):
            return "HTTP 200 but the JSON is not an object"
        body = loaded
    if status not in check.statuses:
        number = body.get("ErrorNumber") if body is not None else None
        tolerated = body is not None and (
            (check.invalid_value_ok and number == INVALID_VALUE)
            or (number == NOT_IMPLEMENTED and check.statuses == frozenset({400}))
        )
        if not tolerated:
            return f"HTTP {status}, expected {sorted(check.statuses)}"
    return "" if body is None else _judge_reply(check, body, params)


def _judge_imagebytes(check: Check, payload: bytes, params: list[tuple[str, str]]) -> str:
    """An ImageBytes answer: judged on its header, as ConformU does (metadata version 1)."""
    try:
        header = decode_header(payload)
    except ImageBytesError as exc:
        return f"broken ImageBytes: {exc}"
    if header.metadata_version != 1:
        return f"ImageBytes metadata version {header.metadata_version}, expected 1"
    body = {
        "ClientTransactionID": header.client_transaction_id,
        "ServerTransactionID": header.server_transaction_id,
        "ErrorNumber": header.error_number,
        "ErrorMessage": "",
        "Value": None,
        "Type": header.image_element_type,
        "Rank": header.rank,
    }
    return _judge_reply(check, body, params)


def _judge_reply(check: Check, body: dict[str, Any], params: list[tuple[str, str]]) -> str:
    for key in _REPLY_KEYS:
        miscased = [given for given in body if given.lower() == key.lower() and given != key]
        if miscased:
            return f"reply key {miscased[0]} should be spelled {key}"
    number = body.get("ErrorNumber", 0)
    if check.method == "GET" and number == 0 and "Value" not in body:
        return "a GET without error has no Value"
    sent = [value for name, value in params if name.lower() == "clienttransactionid"]
    if sent:
        expected = _uint32(sent[0])
        returned = body.get("ClientTransactionID")
        allowed = {0, expected} if check.miscased_transaction else {expected}
        if sent[0].strip().startswith("-") and sent[0].strip()[1:].isdigit():
            allowed.add(int(sent[0]))  # tolerated: a negative ID sent back as it came
        if returned not in allowed:
            return f"ClientTransactionID {returned!r} returned, expected {expected}"
    server_id = body.get("ServerTransactionID", 0)
    if not isinstance(server_id, int) or server_id < 0:
        return f"ServerTransactionID {server_id!r} is not an unsigned number"
    if check.errors is not None and number not in check.errors:
        wanted = " or ".join(f"0x{n:X}" for n in sorted(check.errors))
        return f"ErrorNumber 0x{number:X} ({body.get('ErrorMessage', '')!r}), expected {wanted}"
    if check.image_array and number == 0 and not {"Type", "Rank"} <= set(body):
        return "an ImageArray reply without Type and Rank"
    if check.device_state and number == 0:
        value = body.get("Value")
        if not isinstance(value, list) or not all(
            isinstance(item, dict) and "Name" in item and "Value" in item for item in value
        ):
            return f"DeviceState is not a list of Name/Value objects: {value!r}"
    return ""


def _uint32(text: str) -> int:
    try:
        value = int(text.strip())
    except ValueError:
        return 0
    return value if 0 <= value < 2**32 else 0


async def _read(
    session: aiohttp.ClientSession, url: str, path: str, params: tuple[tuple[str, str], ...] = ()
) -> Any:
    """A member's Value, None on any error."""
    try:
        async with session.get(url + path, params=[("ClientID", CLIENT_ID), *params]) as response:
            body = await response.json(content_type=None)
    except (aiohttp.ClientError, ValueError):
        return None
    if not isinstance(body, dict) or body.get("ErrorNumber", 0) != 0:
        return None
    return body.get("Value")


async def _resolve(session: aiohttp.ClientSession, url: str, base: str, value: str | Current) -> str:
    if isinstance(value, str):
        return value
    current = await _read(session, url, f"{base}/{value.member.lower()}", value.params)
    if current is None:
        return value.fallback
    return str(current) if not isinstance(current, bool) else ("True" if current else "False")


async def _wait_while(session: aiohttp.ClientSession, url: str, base: str, member: str, value: Any) -> None:
    deadline = time.monotonic() + _MOTION_WAIT
    while time.monotonic() < deadline:
        if await _read(session, url, f"{base}/{member.lower()}") != value:
            return
        await asyncio.sleep(0.05)
