"""The HTTP side of nightcrew's Alpaca server: routes of the device and management APIs (aiohttp).

``/api/v1/{device_type}/{device_number}/{member}`` (GET and PUT) goes to the served device;
``/management/apiversions``, ``/management/v1/description`` and
``/management/v1/configureddevices`` describe the server. This is the one place where exceptions
become replies: :class:`~nightcrew.bridges.alpaca.server_protocol.BadRequest` (and an unknown
device) is HTTP 400 with a plain-text message, every other error an Alpaca error reply through
:func:`nightcrew.bridges.alpaca.errors.reply_from_error`. An unexpected exception is logged with
its traceback and answered as a driver error (0x500): a client can never stop the server.
"""

from __future__ import annotations

import asyncio
import json
import logging
import uuid
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from aiohttp import web

from nightcrew import __version__
from nightcrew.bridges.alpaca.errors import reply_from_error
from nightcrew.bridges.alpaca.imagebytes import ElementType, encode
from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import (
    AlpacaRequest,
    BadRequest,
    ImageArray,
    TransactionCounter,
    reply,
)
from nightcrew.errors import NightcrewError

__all__ = ["ServerDescription", "build_app", "unique_id"]

log = logging.getLogger(__name__)

_IMAGEBYTES = "application/imagebytes"
#: ImageArrayElementType of the JSON ImageArray: integers are sent as Int32, others as Double.
_JSON_INT32, _JSON_DOUBLE = 2, 3
#: A fixed namespace, so a device's UniqueID stays the same across restarts of the server.
_NAMESPACE = uuid.UUID("5d6f1c3e-7a4b-4f0e-9a51-6e2a2c0b7d11")


@dataclass(frozen=True)
class ServerDescription:
    """What ``/management/v1/description`` says about the server."""

    server_name: str
    location: str = ""
    manufacturer: str = "nightcrew"


def unique_id(server_name: str, device: ServedDevice) -> str:
    """A device's UniqueID: stable for the same server name, device type and module."""
    return str(uuid.uuid5(_NAMESPACE, f"{server_name}/{device.device_type}/{device.module}"))


def build_app(description: ServerDescription, devices: Sequence[ServedDevice]) -> web.Application:
    """The aiohttp application serving ``devices`` (numbered per type as given)."""
    server = _AlpacaHttp(description, devices)
    app = web.Application()
    app.router.add_get("/management/apiversions", server.api_versions)
    app.router.add_get("/management/v1/description", server.description)
    app.router.add_get("/management/v1/configureddevices", server.configured_devices)
    app.router.add_route("GET", "/api/v1/{device_type}/{device_number}/{member}", server.device_get)
    app.router.add_route("PUT", "/api/v1/{device_type}/{device_number}/{member}", server.device_put)
    return app


class _AlpacaHttp:
    def __init__(self, description: ServerDescription, devices: Sequence[ServedDevice]) -> None:
        self._description = description
        self._devices = {(d.device_type, d.number): d for d in devices}
        self._ordered = list(devices)
        self._transactions = TransactionCounter()

    # --- management API ------------------------------------------------------------------------

    async def api_versions(self, request: web.Request) -> web.Response:
        return self._json(self._management_request(request), [1])

    async def description(self, request: web.Request) -> web.Response:
        value = {
            "ServerName": self._description.server_name,
            "Manufacturer": self._description.manufacturer,
            "ManufacturerVersion": __version__,
            "Location": self._description.location,
        }
        return self._json(self._management_request(request), value)

    async def configured_devices(self, request: web.Request) -> web.Response:
        value = [
            {
                "DeviceName": device.module,
                "DeviceType": device.type_name,
                "DeviceNumber": device.number,
                "UniqueID": unique_id(self._description.server_name, device),
            }
            for device in self._ordered
        ]
        return self._json(self._management_request(request), value)

    def _management_request(self, request: web.Request) -> AlpacaRequest:
        return AlpacaRequest.from_query(request.path, request.query)

    def _json(self, alpaca: AlpacaRequest, value: Any) -> web.Response:
        return web.json_response(reply(alpaca, self._transactions.next(), value))

    # --- device API ----------------------------------------------------------------------------

    async def device_get(self, request: web.Request) -> web.StreamResponse:
        return await self._device_call(
            "get", request, AlpacaRequest.from_query(_member(request), request.query)
        )

    async def device_put(self, request: web.Request) -> web.StreamResponse:
        try:
            form = await request.post()
        except ValueError as exc:
            return _bad_request(f"PUT {_member(request)}: the body is not form-encoded: {exc}")
        fields = {name: value for name, value in form.items() if isinstance(value, str)}
        return await self._device_call("put", request, AlpacaRequest.from_form(_member(request), fields))

    async def _device_call(
        self, method: str, request: web.Request, alpaca: AlpacaRequest
    ) -> web.StreamResponse:
        transaction = self._transactions.next()
        try:
            device = self._device(request)
            value = await device.handle(method, alpaca.member, alpaca)
        except BadRequest as exc:
            return _bad_request(str(exc))
        except asyncio.CancelledError:
            raise
        except Exception as exc:
            if not isinstance(exc, NightcrewError):
                log.exception("%s %s failed unexpectedly", method.upper(), request.path)
            number, message = reply_from_error(exc)
            return web.json_response(reply(alpaca, transaction, error_number=number, error_message=message))
        if isinstance(value, ImageArray):
            return await _image_response(request, alpaca, transaction, value)
        return web.json_response(reply(alpaca, transaction, value))

    def _device(self, request: web.Request) -> ServedDevice:
        device_type = request.match_info["device_type"]
        member = request.match_info["member"]
        if device_type != device_type.lower() or member != member.lower():
            # The Alpaca API: URLs are case sensitive and entirely lower case.
            raise BadRequest(
                f"/api/v1/{device_type}/.../{member}: Alpaca URLs are lower case "
                f"(/api/v1/{device_type.lower()}/.../{member.lower()})"
            )
        text = request.match_info["device_number"]
        try:
            number = int(text)
        except ValueError:
            raise BadRequest(f"device number {text!r} is not a whole number") from None
        device = self._devices.get((device_type, number))
        if device is None:
            served = ", ".join(f"{t} {n}" for t, n in self._devices) or "none"
            raise BadRequest(f"no device {device_type} {number} on this server (it serves: {served})")
        return device


def _member(request: web.Request) -> str:
    return request.match_info["member"]


def _bad_request(message: str) -> web.Response:
    return web.Response(status=400, text=message)


async def _image_response(
    request: web.Request, alpaca: AlpacaRequest, transaction: int, image: ImageArray
) -> web.Response:
    """ImageBytes when the client accepts them, else the JSON ImageArray (built off the loop)."""
    if _IMAGEBYTES in request.headers.get("Accept", ""):
        native = ElementType.INT32 if image.data.dtype.kind in "iu" else None
        payload = await asyncio.to_thread(
            encode,
            image.data,
            client_transaction_id=alpaca.client_transaction_id,
            server_transaction_id=transaction,
            image_element_type=native,
        )
        return web.Response(body=payload, content_type=_IMAGEBYTES)

    def blocking_json() -> str:
        body = reply(alpaca, transaction, image.data.T.tolist())
        element = _JSON_INT32 if image.data.dtype.kind in "iu" else _JSON_DOUBLE
        return json.dumps({"Type": element, "Rank": 2, **body})

    return web.Response(text=await asyncio.to_thread(blocking_json), content_type="application/json")
