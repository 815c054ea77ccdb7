"""Bad requests to AlpacaServer get one clear answer each, and the server keeps serving.

Malformed requests (unknown device, a parameter that is missing, not a number or NaN, the wrong
HTTP method) are HTTP 400 with a plain-text message; well-formed requests the device refuses get
the Alpaca error number nightcrew's error maps to, with the nightcrew message.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import aiohttp
import pytest

from nightcrew.bridges.alpaca.errors import (
    ACTION_NOT_IMPLEMENTED,
    DRIVER_ERROR,
    INVALID_OPERATION,
    INVALID_VALUE,
    NOT_CONNECTED,
    NOT_IMPLEMENTED,
)
from nightcrew.errors import ConfigError
from nightcrew.modules.alpaca.server import AlpacaServer
from nightcrew.testing import Observatory, wait_for

from .served import Served, served_observatory


@pytest.fixture
async def served() -> AsyncIterator[Served]:
    async with served_observatory() as served:
        yield served


class Client:
    """Raw HTTP calls, so a test sees status codes and bodies as they are."""

    def __init__(self, session: aiohttp.ClientSession, url: str) -> None:
        self._session, self._url = session, url

    async def call(self, method: str, path: str, **params: str) -> tuple[int, Any]:
        url = f"{self._url}/api/v1/{path}"
        if method == "GET":
            request = self._session.get(url, params=params)
        else:
            request = self._session.put(url, data=params)
        async with request as response:
            if response.content_type == "application/json":
                return response.status, await response.json()
            return response.status, await response.text()

    async def connect(self, device: str) -> None:
        status, body = await self.call("PUT", f"{device}/connected", Connected="True")
        assert (status, body["ErrorNumber"]) == (200, 0), body


@pytest.fixture
async def client(served: Served) -> AsyncIterator[Client]:
    async with aiohttp.ClientSession() as session:
        yield Client(session, served.url)


async def test_unknown_devices_are_bad_requests_naming_what_is_served(client: Client) -> None:
    for path, expected in (
        ("toaster/0/connected", "no device toaster 0"),
        ("telescope/1/connected", "no device telescope 1"),
        ("telescope/x/connected", "device number 'x' is not a whole number"),
    ):
        status, text = await client.call("GET", path)
        assert status == 400
        assert expected in text
    status, text = await client.call("GET", "toaster/0/connected")
    assert "it serves: telescope 0, camera 0, dome 0, focuser 0, filterwheel 0, safetymonitor 0" in text


@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"RightAscension": "abc", "Declination": "10"}, "parameter RightAscension='abc' is not a number"),
        (
            {"RightAscension": "NaN", "Declination": "10"},
            "parameter RightAscension='NaN' is not a finite number",
        ),
        (
            {"RightAscension": "12", "Declination": "inf"},
            "parameter Declination='inf' is not a finite number",
        ),
        ({"RightAscension": "12"}, "slewtocoordinatesasync: missing parameter Declination"),
        ({"RightAscension": "١٢", "Declination": "10"}, "parameter RightAscension='١٢' is not a number"),
    ],
)
async def test_malformed_parameters_are_bad_requests(
    client: Client, params: dict[str, str], message: str
) -> None:
    await client.connect("telescope/0")
    status, text = await client.call("PUT", "telescope/0/slewtocoordinatesasync", **params)
    assert status == 400
    assert message in text


async def test_values_out_of_range_are_invalid_values(client: Client) -> None:
    await client.connect("telescope/0")
    status, body = await client.call(
        "PUT", "telescope/0/slewtocoordinatesasync", RightAscension="25", Declination="10"
    )
    assert status == 200
    assert body["ErrorNumber"] == INVALID_VALUE
    assert "right ascension must be within 0..24 hours, got 25.0" in body["ErrorMessage"]
    await client.connect("camera/0")
    _, body = await client.call("PUT", "camera/0/startexposure", Duration="-1", Light="true")
    assert body["ErrorNumber"] == INVALID_VALUE
    assert "duration must be within 0..3600 s" in body["ErrorMessage"]
    status, text = await client.call("PUT", "camera/0/startexposure", Duration="1", Light="maybe")
    assert (status, "parameter Light='maybe' is not true or false") == (400, text[text.index("param") :])
    _, body = await client.call("PUT", "camera/0/binx", BinX="3")
    assert body["ErrorNumber"] == INVALID_VALUE
    assert "binx must be one of [1, 2, 4], got 3" in body["ErrorMessage"]


async def test_a_device_answers_only_when_connected(client: Client) -> None:
    _, body = await client.call("GET", "telescope/0/rightascension")
    assert body["ErrorNumber"] == NOT_CONNECTED
    assert "not connected; set Connected=true first" in body["ErrorMessage"]
    _, body = await client.call("GET", "telescope/0/name")  # informational members always answer
    assert body["Value"] == "telescope"
    await client.connect("telescope/0")
    _, body = await client.call("GET", "telescope/0/rightascension")
    assert body["ErrorNumber"] == 0
    assert isinstance(body["Value"], float)


async def test_unimplemented_members_and_wrong_methods(client: Client) -> None:
    await client.connect("telescope/0")
    _, body = await client.call("GET", "telescope/0/sideofpier")
    assert body["ErrorNumber"] == NOT_IMPLEMENTED
    assert "telescope member sideofpier is not implemented" in body["ErrorMessage"]
    _, body = await client.call("PUT", "telescope/0/tracking", Tracking="true")  # CanSetTracking is false
    assert body["ErrorNumber"] == NOT_IMPLEMENTED
    status, text = await client.call("PUT", "telescope/0/rightascension", RightAscension="1")
    assert (status, text) == (400, "telescope member rightascension takes GET, not PUT")
    # ConformU: a name that is no member of the interface, or a URL not in lower case, is a bad URL.
    status, text = await client.call("GET", "telescope/0/descrip")
    assert (status, text) == (400, "'descrip' is not a member of the Alpaca Telescope interface")
    status, text = await client.call("GET", "TELESCOPE/0/description")
    assert (status, "Alpaca URLs are lower case") == (400, text[text.index("Alpaca") :].split(" (")[0])
    # Members of the interface nightcrew does not implement are NotImplemented, with either method.
    _, body = await client.call("PUT", "telescope/0/synctotarget")
    assert body["ErrorNumber"] == NOT_IMPLEMENTED
    _, body = await client.call("PUT", "telescope/0/action", Action="nosuch", Parameters="")
    assert body["ErrorNumber"] == ACTION_NOT_IMPLEMENTED
    assert "supports no actions" in body["ErrorMessage"]


async def test_refusals_of_the_module_reach_the_client(client: Client) -> None:
    await client.connect("telescope/0")
    # Parked: nightcrew refuses the move (MoveError) before anything moves.
    status, body = await client.call(
        "PUT", "telescope/0/slewtocoordinatesasync", RightAscension="17.963", Declination="4.7"
    )
    if body["ErrorNumber"] == 0:  # refused after the request returned: the next poll says so
        status, body = await client.call("GET", "telescope/0/slewing")
    assert (status, body["ErrorNumber"]) == (200, INVALID_OPERATION)
    assert "telescope is parked; call init() first" in body["ErrorMessage"]
    _, body = await client.call("GET", "telescope/0/slewing")
    assert body == {**body, "ErrorNumber": 0, "Value": False}  # reported once, not again

    await client.connect("camera/0")
    _, body = await client.call("GET", "camera/0/imagearray")
    assert body["ErrorNumber"] == INVALID_OPERATION
    assert "no image is ready" in body["ErrorMessage"]


async def test_a_slew_below_the_horizon_is_refused_on_the_request_or_the_next_poll(client: Client) -> None:
    await client.connect("telescope/0")
    _, body = await client.call("PUT", "telescope/0/unpark")
    assert body["ErrorNumber"] == 0
    _, body = await client.call("PUT", "telescope/0/slewtoaltazasync", Altitude="-10", Azimuth="0")
    if body["ErrorNumber"] == 0:  # refused after the request returned: the next poll says so
        _, body = await client.call("GET", "telescope/0/slewing")
    assert body["ErrorNumber"] == INVALID_OPERATION
    assert "below the limit of 10°" in body["ErrorMessage"]


async def test_query_names_ignore_case_form_names_do_not_and_transaction_ids_are_echoed(
    client: Client,
) -> None:
    status, text = await client.call("PUT", "focuser/0/connected", connected="true")
    assert (status, text) == (
        400,
        "connected: missing parameter Connected (got connected: form parameter names are case sensitive)",
    )
    status, body = await client.call("PUT", "focuser/0/connected", Connected="true", clienttransactionid="41")
    assert (status, body["ErrorNumber"], body["ClientTransactionID"]) == (200, 0, 0)  # mis-cased: ignored
    status, body = await client.call("GET", "focuser/0/connected", clienttransactionid="41")
    assert (status, body["Value"], body["ClientTransactionID"]) == (200, True, 41)
    first = body["ServerTransactionID"]
    _, body = await client.call("GET", "focuser/0/position", ClientTransactionID="4294967295")
    assert body["ClientTransactionID"] == 4294967295
    assert body["ServerTransactionID"] > first
    for bad in ("-5", "abc", "4294967296"):
        _, body = await client.call("GET", "focuser/0/position", ClientTransactionID=bad)
        assert body["ClientTransactionID"] == 0
    _, body = await client.call("PUT", "focuser/0/move", Position="1000")
    assert body["ErrorNumber"] == 0
    _, body = await client.call("GET", "focuser/0/position", ClientID="x" * 5000)  # ignored
    assert body["ErrorNumber"] == 0


async def test_a_module_that_is_not_online_is_a_clear_error() -> None:
    async with Observatory(speed=1.0) as obs:
        server = await obs.start(
            AlpacaServer, "alpaca", devices={"focuser": "ghost"}, port=0, discovery_port=None
        )
        async with aiohttp.ClientSession() as session:
            client = Client(session, f"http://127.0.0.1:{server.port}")
            status, body = await client.call("PUT", "focuser/0/connected", Connected="true")
            assert status == 200
            assert body["ErrorNumber"] >= 0x500
            assert "module 'ghost' is not online" in body["ErrorMessage"]
            # The server is still there.
            _, body = await client.call("GET", "focuser/0/connected")
            assert body["Value"] is False


async def test_bad_configurations_name_the_key() -> None:
    with pytest.raises(ConfigError, match=r"key 'devices\.toaster': unknown Alpaca device type"):
        AlpacaServer(name="alpaca", devices={"toaster": "x"})
    with pytest.raises(ConfigError, match="key 'devices': name at least one device"):
        AlpacaServer(name="alpaca", devices={})
    with pytest.raises(ConfigError, match="key 'port': must be a port number"):
        AlpacaServer(name="alpaca", devices={"focuser": "focuser"}, port=70000)
    with pytest.raises(ConfigError, match=r"key 'devices\.camera': give a module name"):
        AlpacaServer(name="alpaca", devices={"camera": []})
    with pytest.raises(ConfigError, match=r"key 'pixel_sizes\.guider': guider is not a served camera"):
        AlpacaServer(name="alpaca", devices={"camera": "camera"}, pixel_sizes={"guider": 5.0})
    with pytest.raises(ConfigError, match=r"key 'pixel_sizes\.camera': must be > 0 µm, got -1"):
        AlpacaServer(name="alpaca", devices={"camera": "camera"}, pixel_sizes={"camera": -1})


async def test_a_busy_port_is_a_config_error(served: Served) -> None:
    async with Observatory(speed=1.0) as obs:
        with pytest.raises(ConfigError, match=f"key 'port': cannot listen on 127.0.0.1:{served.server.port}"):
            await obs.start(AlpacaServer, "second", devices={"focuser": "focuser"}, port=served.server.port)


async def test_a_frame_that_is_gone_is_a_clear_error(served: Served, client: Client) -> None:
    await client.connect("camera/0")
    _, body = await client.call("PUT", "camera/0/startexposure", Duration="0.1", Light="true")
    assert body["ErrorNumber"] == 0

    async def ready() -> bool:
        _, reply = await client.call("GET", "camera/0/imageready")
        return bool(reply["Value"])

    await wait_for(ready, 60.0, message="image ready")
    vfs = served.observatory.vfs
    (path,) = await vfs.find("/cache/*.fits")
    await vfs.remove(path)
    _, body = await client.call("GET", "camera/0/imagearray")
    assert body["ErrorNumber"] == DRIVER_ERROR
    assert f"GrabImageError: cannot read the frame {path} through the server's VFS" in body["ErrorMessage"]
    _, body = await client.call("GET", "camera/0/camerastate")  # still serving
    assert (body["ErrorNumber"], body["Value"]) == (0, 0)


async def test_a_second_slew_is_refused_but_park_always_wins() -> None:
    async with served_observatory(slew_rate=1.0) as served, aiohttp.ClientSession() as session:
        client = Client(session, served.url)  # slews of a minute: the first is still running
        await client.connect("telescope/0")
        await client.call("PUT", "telescope/0/unpark")
        await wait_for(lambda: _value(client, "telescope/0/atpark", False), 10.0, message="unparked")
        _, body = await client.call("PUT", "telescope/0/slewtoaltazasync", Altitude="30", Azimuth="90")
        assert body["ErrorNumber"] == 0
        _, body = await client.call("PUT", "telescope/0/slewtoaltazasync", Altitude="40", Azimuth="90")
        assert body["ErrorNumber"] == INVALID_OPERATION
        assert "busy with slewtoaltazasync; wait for it or abort it" in body["ErrorMessage"]

        _, body = await client.call("PUT", "telescope/0/park")
        assert body["ErrorNumber"] == 0
        await wait_for(lambda: _value(client, "telescope/0/atpark", True), 120.0, message="parked")
        # The slew that park interrupted is not reported as a failure.
        _, body = await client.call("GET", "telescope/0/slewing")
        assert (body["ErrorNumber"], body["Value"]) == (0, False)


async def _value(client: Client, path: str, expected: object) -> bool:
    _, body = await client.call("GET", path)
    assert body["ErrorNumber"] == 0, body
    return bool(body["Value"] == expected)


@pytest.mark.parametrize(
    ("method", "path", "params"),
    [
        ("GET", "telescope/0/__init__", {}),
        ("GET", "telescope/0/Get_Proxy", {}),
        ("GET", "telescope/-1/connected", {}),
        ("GET", "telescope/99999999999999999999/connected", {}),
        ("PUT", "telescope/0/slewtoaltazasync", {"Altitude": "1e400", "Azimuth": "0"}),
        ("PUT", "telescope/0/slewtoaltazasync", {"Altitude": "١٢", "Azimuth": "0"}),
        ("PUT", "telescope/0/targetdeclination", {"TargetDeclination": ""}),
        ("PUT", "camera/0/numx", {"NumX": "2.5"}),
        ("PUT", "camera/0/numx", {"NumX": "-3"}),
        ("PUT", "camera/0/startexposure", {"Duration": "1", "Light": ""}),
        ("PUT", "focuser/0/move", {"Position": "99999999999999999999999"}),
        ("PUT", "filterwheel/0/position", {"Position": "-1"}),
        ("PUT", "dome/0/slewtoazimuth", {"Azimuth": "nan"}),
    ],
)
async def test_odd_requests_get_an_answer_and_never_stop_the_server(
    client: Client, method: str, path: str, params: dict[str, str]
) -> None:
    device = path.rsplit("/", 1)[0]
    if device.split("/")[1] == "0":
        await client.connect(device)
    status, body = await client.call(method, path, **params)
    assert status in (200, 400)
    if status == 200:
        assert body["ErrorNumber"] != 0 and body["ErrorMessage"], body
    else:
        assert isinstance(body, str) and body
    status, body = await client.call("GET", "telescope/0/name")
    assert (status, body["Value"]) == (200, "telescope")
