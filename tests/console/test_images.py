"""The last frame of a camera: taken from the browser, announced live, served as PNG with its header."""

from __future__ import annotations

import logging
import struct
import zlib
from collections.abc import Callable
from datetime import UTC, datetime

import numpy as np
import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.errors import InvalidArgumentError
from nightcrew.events import NewImageEvent
from nightcrew.modules import Module
from nightcrew.modules.console._images import Frame, View, render_png
from nightcrew.modules.sim import SimCamera

from .conftest import OPERATOR, OPERATOR_PASSWORD, ApiClient, Observatory, eventually, open_socket

DETECTOR = {"chip_width": 300, "chip_height": 200, "cosmic_rays_per_s": 0.0}


def png_pixels(png: bytes) -> np.ndarray:
    """The greyscale pixels of a PNG written by nightcrew's encoder (filter byte per row)."""
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", png[16:24])
    data, offset = b"", 8
    while offset < len(png):
        (length,) = struct.unpack(">I", png[offset : offset + 4])
        kind = png[offset + 4 : offset + 8]
        if kind == b"IDAT":
            data += png[offset + 8 : offset + 8 + length]
        offset += 12 + length
    rows = np.frombuffer(zlib.decompress(data), np.uint8).reshape(height, width + 1)
    assert set(rows[:, 0]) <= {2}  # "Up" filter everywhere
    return np.cumsum(rows[:, 1:], axis=0, dtype=np.uint8)


def gradient_frame() -> Frame:
    """A frame whose value is its column number, with a bright top-left pixel block."""
    pixels = np.tile(np.arange(100, dtype=np.float32), (50, 1))
    pixels[:5, :5] = 1000.0
    return Frame("cam", 1, "/cache/x.fits", datetime(2024, 1, 1, tzinfo=UTC), pixels, ())


def test_a_region_is_cut_in_display_coordinates_and_stretched() -> None:
    frame = gradient_frame()
    whole = png_pixels(render_png(frame, View(low=0.0, high=90.0)))
    assert whole.shape == (50, 100)
    assert whole[0, 0] == 255 and whole[-1, 0] == 0  # the bright block is at the top left
    assert whole[-1, 1] < whole[-1, 50] < whole[-1, 98]  # rising with the column
    region = png_pixels(render_png(frame, View(left=50, top=10, width=20, height=30, low=0.0, high=100.0)))
    assert region.shape == (30, 20)
    assert region[0, 0] == 0 and region[0, -1] == 255
    small = png_pixels(render_png(frame, View(max_size=25)))
    assert small.shape == (12, 25)


def test_the_non_linear_stretches_lift_the_faint_end() -> None:
    frame = gradient_frame()
    row = {
        s: png_pixels(render_png(frame, View(stretch=s, low=0.0, high=99.0)))[-1]
        for s in ("linear", "asinh", "log")
    }
    assert row["asinh"][20] > row["linear"][20] and row["log"][20] > row["linear"][20]


@pytest.mark.parametrize(
    ("query", "message"),
    [
        ({"stretch": "gamma"}, "stretch must be one of linear, asinh, log"),
        ({"low": "50", "high": "10"}, "need 0 <= low < high <= 100"),
        ({"max_size": "5"}, "max_size must be within 16..4096"),
        ({"left": "a"}, "left must be a whole number"),
    ],
)
def test_bad_view_parameters_are_named(query: dict[str, str], message: str) -> None:
    with pytest.raises(InvalidArgumentError, match=message):
        View.from_query(query)


def test_a_region_outside_the_frame_is_refused() -> None:
    with pytest.raises(InvalidArgumentError, match="outside the 100x50 frame"):
        View(left=90, width=20).region(gradient_frame())


async def test_an_exposure_from_the_browser_shows_up_as_a_png_with_its_header(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    await observatory.start(SimCamera, "camera", detector=DETECTOR, seed=3)
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    status, body = await client.get("/api/images/camera/latest.png")
    assert status == 404 and "no frame from 'camera' yet" in body["error"]["message"]
    socket = await open_socket(client)
    assert await client.call("camera", "set_exposure_time", 1.0) == (200, {"result": None})
    status, body = await client.call("camera", "grab_data")
    assert status == 200
    path = body["result"]
    shown = await socket.wait_for(lambda m: m["type"] == "image", "the new frame")
    assert shown["module"] == "camera" and shown["filename"] == path
    status, png, headers = await client.get_bytes("/api/images/camera/latest.png")
    assert status == 200 and headers["Content-Type"] == "image/png"
    assert (headers["X-Image-Width"], headers["X-Image-Height"], headers["X-Image-Id"]) == (
        "300",
        "200",
        str(shown["id"]),
    )
    assert png_pixels(png).shape == (200, 300)
    status, png, _ = await client.get_bytes(
        "/api/images/camera/latest.png", left=0, top=0, width=100, height=50
    )
    assert status == 200 and png_pixels(png).shape == (50, 100)
    status, _, _ = await client.get_bytes("/api/images/camera/latest.png", stretch="gamma")
    assert status == 400
    status, info = await client.get("/api/images/camera/latest.json")
    assert status == 200 and info["filename"] == path and (info["width"], info["height"]) == (300, 200)
    keys = {card["key"]: card["value"] for card in info["header"]}
    assert keys["EXPTIME"] == pytest.approx(1.0) and keys["NAXIS1"] == 300
    assert (await client.get("/api/images"))[1]["images"][0]["module"] == "camera"


async def test_frames_arriving_faster_than_they_load_skip_to_the_newest(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    camera = await observatory.start(Module, "fastcam")
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    socket = await open_socket(client)
    paths = [f"/cache/frame{n}.fits" for n in range(5)]
    for n, path in enumerate(paths):
        await camera.vfs.write_fits(path, fits.PrimaryHDU(np.full((20, 30), n, np.float32)))
    for path in paths:  # all at once: the console is still loading the first when the rest arrive
        await camera.comm.send_event(NewImageEvent(filename=path))
    await socket.wait_for(lambda m: m["type"] == "image" and m["filename"] == paths[-1], "the newest frame")
    shown = [m["filename"] for m in socket.messages if m["type"] == "image"]
    assert shown == [paths[0], paths[-1]]
    assert console.frames["fastcam"].filename == paths[-1]


async def test_a_frame_that_cannot_be_read_is_skipped_and_the_console_stays_up(
    observatory: Observatory, clients: Callable[[str], ApiClient], caplog: pytest.LogCaptureFixture
) -> None:
    camera = await observatory.start(Module, "brokencam")
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    await camera.vfs.write_bytes("/cache/broken.fits", b"SIMPLE  = not a FITS file")
    await camera.vfs.write_fits("/cache/good.fits", fits.PrimaryHDU(np.ones((20, 30), np.float32)))
    socket = await open_socket(client)
    with caplog.at_level(logging.WARNING):
        for path in ("/cache/missing.fits", "/cache/broken.fits"):
            await camera.comm.send_event(NewImageEvent(filename=path))
            refused = f"cannot show {path}"
            await eventually(lambda: refused in caplog.text, f"{path} refused")  # noqa: B023 - awaited here
    await camera.comm.send_event(NewImageEvent(filename="/cache/good.fits"))
    await socket.wait_for(lambda m: m["type"] == "image", "the good frame")
    assert [m["filename"] for m in socket.messages if m["type"] == "image"] == ["/cache/good.fits"]
    assert console.state == "ready"
    assert (await client.get("/api/images/brokencam/latest.json"))[1]["filename"] == "/cache/good.fits"
