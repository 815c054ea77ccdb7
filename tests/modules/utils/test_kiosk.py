"""Kiosk: a valid PNG of the latest image over real HTTP on 127.0.0.1."""

from __future__ import annotations

import struct
import zlib

import aiohttp
import numpy as np
import numpy.typing as npt
import pytest

from nightcrew.images.png import encode_png, stretch_to_uint8
from nightcrew.modules.utils import Kiosk
from nightcrew.testing import Observatory
from tests.modules.devices import GradientCamera


def decode_png(data: bytes) -> npt.NDArray[np.uint8]:
    """A strict decoder for 8-bit greyscale PNGs: checks signature, chunk CRCs and every row filter."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    position, chunks = 8, []
    while position < len(data):
        (length,) = struct.unpack(">I", data[position : position + 4])
        kind, body = data[position + 4 : position + 8], data[position + 8 : position + 8 + length]
        (crc,) = struct.unpack(">I", data[position + 8 + length : position + 12 + length])
        assert crc == zlib.crc32(kind + body), f"bad CRC in {kind!r}"
        chunks.append((kind, body))
        position += 12 + length
    assert chunks[0][0] == b"IHDR" and chunks[-1][0] == b"IEND"
    width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", chunks[0][1])
    assert (depth, colour, interlace) == (8, 0, 0)
    raw = zlib.decompress(b"".join(body for kind, body in chunks if kind == b"IDAT"))
    rows = np.frombuffer(raw, np.uint8).reshape(height, width + 1)
    image = np.zeros((height, width), np.uint8)
    previous = np.zeros(width, np.uint8)
    for y in range(height):
        assert rows[y, 0] in (0, 2), "only None and Up filters expected"
        image[y] = rows[y, 1:] + (previous if rows[y, 0] == 2 else 0)
        previous = image[y]
    return image


def test_png_round_trip() -> None:
    pixels = np.random.default_rng(1).integers(0, 256, size=(37, 53)).astype(np.uint8)
    np.testing.assert_array_equal(decode_png(encode_png(pixels)), pixels)
    with pytest.raises(ValueError, match="2-D uint8"):
        encode_png(np.zeros((3, 3), np.float32))


def test_stretch_bins_flips_and_scales() -> None:
    image = np.arange(4000.0).reshape(40, 100)
    shown = stretch_to_uint8(image, max_size=50)
    assert shown.shape == (20, 50) and shown.dtype == np.uint8
    assert shown[-1, 0] == 0 and shown[0, -1] == 255  # FITS row 0 at the bottom


async def test_kiosk_serves_the_cameras_image(fast_observatory: Observatory) -> None:
    obs = fast_observatory
    await obs.start(GradientCamera, "camera")
    kiosk = await obs.start(Kiosk, "kiosk", camera="camera", interval=30.0, exposure_time=1.0, port=0)
    assert kiosk.port > 0
    # The camera's exposure is short, but it spends some wall time (many clock seconds) on headers.
    await obs.wait_for(lambda: kiosk.png is not None, 2000.0, interval=1.0)
    async with aiohttp.ClientSession() as session:
        async with session.get(f"http://127.0.0.1:{kiosk.port}/kiosk.png") as response:
            assert response.status == 200 and response.content_type == "image/png"
            image = decode_png(await response.read())
        async with session.get(f"http://127.0.0.1:{kiosk.port}/") as response:
            assert '<img src="kiosk.png"' in await response.text()
    assert image.shape == (48, 64)
    # The gradient grows with row and column: bright at the top right after the flip.
    assert image[0, -1] == 255 and image[-1, 0] == 0


async def test_kiosk_without_camera_shows_new_images(fast_observatory: Observatory) -> None:
    obs = fast_observatory
    kiosk = await obs.start(Kiosk, "kiosk", port=0)
    async with aiohttp.ClientSession() as session:
        async with session.get(f"http://127.0.0.1:{kiosk.port}/kiosk.png") as response:
            assert response.status == 503
        camera = await obs.start(GradientCamera, "camera")
        await camera.grab_data()
        await obs.wait_for(lambda: kiosk.png is not None, 2000.0, interval=1.0)
        async with session.get(f"http://127.0.0.1:{kiosk.port}/kiosk.png") as response:
            assert response.status == 200
            assert decode_png(await response.read()).shape == (48, 64)
