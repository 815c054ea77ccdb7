"""The async Alpaca client against alpaca-simulators, and against a server that misbehaves."""

from __future__ import annotations

import numpy as np
import pytest

from nightcrew.bridges.alpaca import (
    AlpacaClient,
    AlpacaConnectionError,
    AlpacaReplyError,
    check_server_url,
    imagebytes,
)
from nightcrew.errors import InvalidArgumentError, NotSupportedError, RemoteTimeoutError
from nightcrew.testing.alpaca import AlpacaSimulator, free_port
from tests.alpaca.faulty_server import FaultyServer, alpaca_error, image_bytes, json_image, raw, value


async def test_get_put_and_connect_on_alpaca_simulators(alpaca_simulator: AlpacaSimulator) -> None:
    async with AlpacaClient(alpaca_simulator.url) as client:
        focuser = client.device("focuser", 0)
        await focuser.connect()
        assert await focuser.get("connected") is True
        assert await focuser.get("absolute") is True
        assert isinstance(await focuser.get("maxstep"), int)
        wheel = client.device("filterwheel", 0)
        await wheel.connect()
        assert await wheel.get("names") == ["Red", "Green", "Blue", "Clear", "Luminance"]


async def test_device_errors_name_device_and_call(alpaca_simulator: AlpacaSimulator) -> None:
    async with AlpacaClient(alpaca_simulator.url) as client:
        with pytest.raises(
            NotSupportedError,
            match=r"telescope 7 at http://127\.0\.0\.1:\d+: GET connected: NotImplemented \(0x400\)",
        ):
            await client.device("telescope", 7).get("connected")
        with pytest.raises(AlpacaReplyError, match=r"telescope 0 at .*: GET nosuchthing: HTTP 404"):
            await client.device("telescope", 0).get("nosuchthing")


async def test_ids_and_form_encoding(faulty: FaultyServer) -> None:
    async with AlpacaClient(faulty.url, client_id=4242) as client:
        device = client.device("telescope", 0)
        await device.get("altitude")
        await device.put("slewtocoordinatesasync", RightAscension=1.5, Declination=-20.25, Flag=True)
    (m1, _, get_fields), (m2, _, put_fields) = faulty.requests
    assert (m1, m2) == ("GET", "PUT")
    assert get_fields["ClientID"] == put_fields["ClientID"] == "4242"
    assert int(put_fields["ClientTransactionID"]) == int(get_fields["ClientTransactionID"]) + 1
    assert (put_fields["RightAscension"], put_fields["Declination"], put_fields["Flag"]) == (
        "1.5",
        "-20.25",
        "True",
    )


async def test_connect_falls_back_to_connected_before_platform_7(faulty: FaultyServer) -> None:
    faulty.replies["connect"] = alpaca_error(0x400, "no such method")
    async with AlpacaClient(faulty.url) as client:
        await client.device("focuser", 0).connect()
    puts = [
        (member, fields.get("Connected")) for method, member, fields in faulty.requests if method == "PUT"
    ]
    assert puts == [("connect", None), ("connected", "True")]


async def test_connect_waits_for_connecting(faulty: FaultyServer) -> None:
    states = iter([True, True, False])

    async def connecting(request: object) -> object:
        return await value(next(states))(request)  # type: ignore[arg-type]

    faulty.replies["connecting"] = connecting  # type: ignore[assignment]
    async with AlpacaClient(faulty.url) as client:
        await client.device("camera", 0).connect(poll_interval=0.01)
    assert [m for _, m, _ in faulty.requests].count("connecting") == 3


async def test_alpaca_error_reply(faulty: FaultyServer) -> None:
    faulty.replies["gain"] = alpaca_error(0x401, "gain 99 is out of range")
    async with AlpacaClient(faulty.url) as client:
        with pytest.raises(
            InvalidArgumentError, match=r"camera 0 at .*: PUT gain: InvalidValue \(0x401\): gain 99"
        ):
            await client.device("camera", 0).put("gain", Gain=99)


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (b"{not json", r"malformed reply \(not JSON\): '\{not json'"),
        (b"[1, 2]", r"malformed reply \(not a JSON object\)"),
        (b'{"ErrorNumber": "x"}', r"malformed reply: ErrorNumber is 'x'"),
        (b'{"ErrorNumber": 0, "ErrorMessage": ""}', r"malformed reply: no 'Value'"),
    ],
)
async def test_malformed_json_is_one_clear_error(faulty: FaultyServer, body: bytes, message: str) -> None:
    faulty.replies["position"] = raw(body)
    async with AlpacaClient(faulty.url) as client:
        with pytest.raises(
            AlpacaReplyError, match=r"focuser 0 at http://127\.0\.0\.1:\d+: GET position: .*" + message
        ):
            await client.device("focuser", 0).get("position")


async def test_http_error_status(faulty: FaultyServer) -> None:
    faulty.replies["position"] = raw(b"Internal server error", "text/plain", status=500)
    async with AlpacaClient(faulty.url) as client:
        with pytest.raises(AlpacaReplyError, match=r"GET position: HTTP 500: Internal server error"):
            await client.device("focuser", 0).get("position")


async def test_timeout(faulty: FaultyServer) -> None:
    faulty.replies["position"] = faulty.hang()
    async with AlpacaClient(faulty.url, timeout=0.2) as client:
        with pytest.raises(RemoteTimeoutError, match=r"focuser 0 at .*: GET position: no reply within 0.2 s"):
            await client.device("focuser", 0).get("position")


async def test_unreachable_server() -> None:
    async with AlpacaClient(f"http://127.0.0.1:{free_port()}") as client:
        with pytest.raises(AlpacaConnectionError, match=r"dome 0 at http://127\.0\.0\.1:\d+: GET azimuth: "):
            await client.device("dome", 0).get("azimuth")


async def test_imagebytes_and_json_fallback(faulty: FaultyServer) -> None:
    image = np.arange(6, dtype=np.uint16).reshape(2, 3)
    faulty.replies["imagearray"] = image_bytes(imagebytes.encode(image))
    async with AlpacaClient(faulty.url) as client:
        camera = client.device("camera", 0)
        np.testing.assert_array_equal(await camera.image_array(), image)
        faulty.replies["imagearray"] = json_image(image.T.tolist())  # JSON is [x][y]
        np.testing.assert_array_equal(await camera.image_array(), image)
    accept = [fields for _, member, fields in faulty.requests if member == "imagearray"]
    assert len(accept) == 2


@pytest.mark.parametrize(
    ("payload", "error", "message"),
    [
        (
            imagebytes.encode(np.ones((4, 4), np.uint16))[:-2],
            AlpacaReplyError,
            r"malformed image: ImageBytes data of 30 bytes do not match a 4x4 UINT16",
        ),
        (
            imagebytes.encode_error(0x40B, "no image taken yet"),
            Exception,
            r"InvalidOperation \(0x40B\): no image taken yet",
        ),
        (b"short", AlpacaReplyError, r"shorter than its 44-byte header"),
    ],
)
async def test_broken_images(
    faulty: FaultyServer, payload: bytes, error: type[Exception], message: str
) -> None:
    faulty.replies["imagearray"] = image_bytes(payload)
    async with AlpacaClient(faulty.url) as client:
        with pytest.raises(error, match=r"camera 0 at .*: GET imagearray: .*" + message):
            await client.device("camera", 0).image_array()


@pytest.mark.parametrize(
    ("url", "message"),
    [
        ("ftp://host:1", "starts with http:// or https://"),
        ("http://", "names no host"),
        ("http://host:99999", r"not a URL: .*Port out of range"),
        ("http://host:1/api/v1", "only scheme://host:port"),
    ],
)
def test_bad_server_urls(url: str, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        check_server_url(url)


def test_unknown_device_type() -> None:
    with pytest.raises(ValueError, match="unknown Alpaca device type 'toaster'"):
        AlpacaClient("http://127.0.0.1:1").device("toaster", 0)
