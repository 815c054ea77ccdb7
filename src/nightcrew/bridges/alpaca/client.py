"""The async Alpaca client: one HTTP session per server, one :class:`AlpacaDevice` per device.

aiohttp (a dependency already) carries the calls; alpyca is synchronous (requests), so it does not
fit an event loop. Facts from the ASCOM Alpaca API specification:

* ``GET|PUT {server}/api/v1/{device_type}/{device_number}/{member}``; GET parameters in the query,
  PUT parameters form-encoded (``application/x-www-form-urlencoded``), booleans as ``True``/``False``.
* Every request carries ``ClientID`` (one number per client) and ``ClientTransactionID`` (counts up).
* A reply is JSON ``{Value, ErrorNumber, ErrorMessage, ClientTransactionID, ServerTransactionID}``;
  ErrorNumber != 0 is a device error (mapped in :mod:`nightcrew.bridges.alpaca.errors`).
* Platform 7 devices connect with ``PUT connect`` and report ``Connecting`` until done; older
  devices only know ``PUT connected``.
* ``GET imagearray`` with ``Accept: application/imagebytes`` may answer in the binary ImageBytes
  format (:mod:`nightcrew.bridges.alpaca.imagebytes`); otherwise JSON with ``Type`` and ``Rank``.

Every error names the device and the call: ``camera 0 at http://127.0.0.1:11111: GET imagearray: ...``.
"""

from __future__ import annotations

import asyncio
import itertools
import json
import random
from typing import Any

import aiohttp
import numpy as np
import numpy.typing as npt
from yarl import URL

from nightcrew.bridges.alpaca import imagebytes
from nightcrew.bridges.alpaca.errors import (
    AlpacaConnectionError,
    AlpacaReplyError,
    error_from_reply,
)
from nightcrew.errors import NotSupportedError, RemoteTimeoutError

__all__ = ["DEVICE_TYPES", "AlpacaClient", "AlpacaDevice", "check_server_url"]

#: Device types of the Alpaca API (lower case, as in the URL).
DEVICE_TYPES = frozenset(
    {
        "camera",
        "covercalibrator",
        "dome",
        "filterwheel",
        "focuser",
        "observingconditions",
        "rotator",
        "safetymonitor",
        "switch",
        "telescope",
    }
)
_READ_BUFFER = 16 * 1024 * 1024
_IMAGE_ACCEPT = "application/imagebytes, application/json;q=0.9"
# A dropped keep-alive connection (typically: the server restarted) fails the first reuse; an
# idempotent GET is then worth one retry on a fresh connection.
_STALE_CONNECTION = (aiohttp.ServerDisconnectedError, aiohttp.ClientOSError)


def check_server_url(server: str) -> URL:
    """The base URL of an Alpaca server (``http://host:port``); ValueError saying what is wrong."""
    try:
        url = URL(server)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"not a URL: {server!r} ({exc})") from None
    if url.scheme not in ("http", "https"):
        raise ValueError(f"an Alpaca server URL starts with http:// or https://, got {server!r}")
    if not url.host:
        raise ValueError(f"the Alpaca server URL {server!r} names no host")
    try:
        url.port  # noqa: B018 - yarl checks the port only when asked
    except ValueError as exc:
        raise ValueError(f"the Alpaca server URL {server!r} has a bad port ({exc})") from None
    if url.path not in ("", "/") or url.query_string or url.fragment:
        raise ValueError(f"an Alpaca server URL is only scheme://host:port, got {server!r}")
    return url.with_path("")


def _form_value(value: Any) -> str:
    if isinstance(value, bool):
        return "True" if value else "False"
    if isinstance(value, float):
        return repr(value)
    return str(value)


class AlpacaClient:
    """An HTTP session to one Alpaca server; constructed without I/O, opened by :meth:`open`.

    Args:
        server: Base URL, ``http://host:port``.
        timeout: Seconds an HTTP call may take before it fails with RemoteTimeoutError.
        client_id: The ClientID sent with every call; a random one by default.
    """

    def __init__(self, server: str, *, timeout: float = 10.0, client_id: int | None = None) -> None:
        self._base = check_server_url(server)
        if not timeout > 0:
            raise ValueError(f"timeout must be > 0 seconds, got {timeout}")
        self.timeout = float(timeout)
        self.client_id = random.randint(1, 65535) if client_id is None else int(client_id)
        self._transactions = itertools.count(1)
        self._session: aiohttp.ClientSession | None = None

    @property
    def server(self) -> str:
        return str(self._base)

    async def open(self) -> None:
        if self._session is None:
            # A large read buffer: with aiohttp's 64 KiB the transport pauses and resumes hundreds of
            # times per image download (~17 % slower for a 32 MB ImageBytes reply, measured).
            self._session = aiohttp.ClientSession(read_bufsize=_READ_BUFFER)

    async def close(self) -> None:
        session, self._session = self._session, None
        if session is not None:
            await session.close()

    async def __aenter__(self) -> AlpacaClient:
        await self.open()
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.close()

    def device(self, device_type: str, device_number: int = 0) -> AlpacaDevice:
        """The device ``device_type``/``device_number`` on this server."""
        return AlpacaDevice(self, device_type, device_number)

    def _url(self, device_type: str, device_number: int, member: str) -> URL:
        return self._base / "api" / "v1" / device_type / str(device_number) / member

    def _ids(self) -> dict[str, str]:
        return {
            "ClientID": str(self.client_id),
            "ClientTransactionID": str(next(self._transactions) & 0xFFFFFFFF),
        }

    async def request(
        self,
        method: str,
        url: URL,
        where: str,
        params: dict[str, Any],
        *,
        time_limit: float | None = None,
        accept: str = "application/json",
    ) -> tuple[str, bytes]:
        """Send one call; return the reply's content type and body (HTTP 200 only).

        Raises:
            AlpacaConnectionError: The server cannot be reached or dropped the connection.
            RemoteTimeoutError: No complete reply within the timeout.
            AlpacaReplyError: An HTTP status other than 200.
        """
        if self._session is None:
            raise AlpacaConnectionError(f"{where}: the client is not open")
        seconds = self.timeout if time_limit is None else time_limit
        fields = {**{k: _form_value(v) for k, v in params.items()}, **self._ids()}
        attempts = 2 if method == "GET" else 1
        for attempt in range(attempts):
            try:
                async with asyncio.timeout(seconds):
                    if method == "GET":
                        response = await self._session.get(url, params=fields, headers={"Accept": accept})
                    else:
                        response = await self._session.put(url, data=fields, headers={"Accept": accept})
                    async with response:
                        body = await response.read()
                        if response.status != 200:
                            text = body[:300].decode("utf-8", errors="replace").strip()
                            raise AlpacaReplyError(
                                f"{where}: HTTP {response.status}: {text or response.reason}"
                            )
                        return response.content_type, body
            except TimeoutError:
                raise RemoteTimeoutError(f"{where}: no reply within {seconds:g} s") from None
            except _STALE_CONNECTION as exc:
                if attempt + 1 < attempts:
                    continue
                raise AlpacaConnectionError(f"{where}: {type(exc).__name__}: {exc}") from exc
            except aiohttp.ClientPayloadError as exc:
                raise AlpacaReplyError(f"{where}: broken reply: {exc}") from exc
            except aiohttp.ClientError as exc:
                raise AlpacaConnectionError(f"{where}: {type(exc).__name__}: {exc}") from exc
        raise AssertionError("unreachable")  # pragma: no cover


class AlpacaDevice:
    """One device on an Alpaca server: typed calls with errors naming the device and the call."""

    def __init__(self, client: AlpacaClient, device_type: str, device_number: int) -> None:
        if device_type not in DEVICE_TYPES:
            raise ValueError(
                f"unknown Alpaca device type {device_type!r}; known: {', '.join(sorted(DEVICE_TYPES))}"
            )
        if device_number < 0:
            raise ValueError(f"device_number must be >= 0, got {device_number}")
        self.client = client
        self.device_type = device_type
        self.device_number = int(device_number)

    @property
    def name(self) -> str:
        """``camera 0 at http://host:port``, for messages."""
        return f"{self.device_type} {self.device_number} at {self.client.server}"

    def _where(self, method: str, member: str) -> str:
        return f"{self.name}: {method} {member}"

    async def get(self, member: str, *, time_limit: float | None = None, **params: Any) -> Any:
        """The Value of ``GET member``."""
        return await self._call("GET", member, params, time_limit, needs_value=True)

    async def put(self, member: str, *, time_limit: float | None = None, **params: Any) -> Any:
        """``PUT member`` with form parameters; the Value if the reply has one."""
        return await self._call("PUT", member, params, time_limit, needs_value=False)

    async def _call(
        self, method: str, member: str, params: dict[str, Any], time_limit: float | None, *, needs_value: bool
    ) -> Any:
        where = self._where(method, member)
        url = self.client._url(self.device_type, self.device_number, member)
        _, body = await self.client.request(method, url, where, params, time_limit=time_limit)
        reply = _json_reply(body, where)
        if needs_value and "Value" not in reply:
            raise AlpacaReplyError(f"{where}: malformed reply: no 'Value' in {_excerpt(body)}")
        return reply.get("Value")

    async def connect(self, time_limit: float = 30.0, poll_interval: float = 0.1) -> None:
        """Connect: Platform 7 ``Connect`` polled via ``Connecting``, else ``Connected = True``.

        Raises:
            RemoteTimeoutError: Still connecting after ``time_limit`` seconds.
        """
        try:
            await self.put("connect")
        except (NotSupportedError, AlpacaReplyError):
            # A device before Platform 7 has no Connect method (0x400, or HTTP 400 for an unknown path).
            await self.put("connected", Connected=True)
        else:
            try:
                async with asyncio.timeout(time_limit):
                    while True:
                        if not await self.get("connecting"):
                            break
                        await asyncio.sleep(poll_interval)
            except TimeoutError:
                raise RemoteTimeoutError(f"{self.name}: still connecting after {time_limit:g} s") from None
        if not await self.get("connected"):
            raise AlpacaConnectionError(f"{self.name}: the device did not connect")

    async def disconnect(self) -> None:
        """Disconnect (Platform 7 ``Disconnect``, else ``Connected = False``)."""
        try:
            await self.put("disconnect")
        except (NotSupportedError, AlpacaReplyError):
            await self.put("connected", Connected=False)

    async def image_array(self, *, time_limit: float | None = None) -> npt.NDArray[Any]:
        """The camera's last image as ``[y, x]`` (or ``[y, x, plane]``), ImageBytes if offered.

        Raises:
            AlpacaReplyError: A malformed image (wrong size, bad header, bad JSON).
        """
        where = self._where("GET", "imagearray")
        url = self.client._url(self.device_type, self.device_number, "imagearray")
        content_type, body = await self.client.request(
            "GET", url, where, {}, time_limit=time_limit, accept=_IMAGE_ACCEPT
        )
        if content_type == "application/imagebytes":
            return _imagebytes_reply(body, where)
        reply = await asyncio.to_thread(_json_reply, body, where)
        return await asyncio.to_thread(_json_image, reply, where)


def _excerpt(body: bytes) -> str:
    text = body[:120].decode("utf-8", errors="replace")
    return repr(text + ("..." if len(body) > 120 else ""))


def _json_reply(body: bytes, where: str) -> dict[str, Any]:
    try:
        reply = json.loads(body)
    except ValueError:
        raise AlpacaReplyError(f"{where}: malformed reply (not JSON): {_excerpt(body)}") from None
    if not isinstance(reply, dict):
        raise AlpacaReplyError(f"{where}: malformed reply (not a JSON object): {_excerpt(body)}")
    number = reply.get("ErrorNumber", 0)
    if not isinstance(number, int) or isinstance(number, bool):
        raise AlpacaReplyError(f"{where}: malformed reply: ErrorNumber is {number!r}")
    if number != 0:
        raise error_from_reply(number, str(reply.get("ErrorMessage", "")), where)
    return reply


def _imagebytes_reply(body: bytes, where: str) -> npt.NDArray[Any]:
    try:
        header, image = imagebytes.decode(body)
    except imagebytes.ImageBytesError as exc:
        raise AlpacaReplyError(f"{where}: malformed image: {exc}") from None
    if header.error_number != 0:
        raise error_from_reply(header.error_number, imagebytes.error_message(body, header), where)
    return image


_JSON_TYPES: dict[int, type[np.generic]] = {
    imagebytes.ElementType.INT16: np.int16,
    imagebytes.ElementType.INT32: np.int32,
    imagebytes.ElementType.DOUBLE: np.float64,
}


def _json_image(reply: dict[str, Any], where: str) -> npt.NDArray[Any]:
    value, rank = reply.get("Value"), reply.get("Rank")
    if rank not in (2, 3) or not isinstance(value, list):
        raise AlpacaReplyError(f"{where}: malformed image: Rank {rank!r} with a {type(value).__name__} Value")
    element = reply.get("Type")
    dtype = _JSON_TYPES.get(element, np.int32) if isinstance(element, int) else np.int32
    try:
        array = np.asarray(value, dtype=dtype)
    except (ValueError, TypeError, OverflowError) as exc:
        raise AlpacaReplyError(f"{where}: malformed image: {exc}") from None
    if array.ndim != rank or 0 in array.shape:
        raise AlpacaReplyError(f"{where}: malformed image: rank {rank} but an array of shape {array.shape}")
    return array.transpose((1, 0) if rank == 2 else (1, 0, 2))
