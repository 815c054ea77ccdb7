"""The camera's fast read of a plain 16-bit FITS BLOB gives what astropy's full reader gives."""

from __future__ import annotations

import io

import numpy as np
import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.bridges.indi import Blob, IndiError
from nightcrew.modules.indi.camera import blocking_read_fits, fits_frame, plain_fits_frame


def _fits(data: np.ndarray, **cards: object) -> bytes:
    hdu = fits.PrimaryHDU(data)
    for key, value in cards.items():
        hdu.header[key] = value
    buffer = io.BytesIO()
    hdu.writeto(buffer)
    return buffer.getvalue()


@pytest.mark.parametrize(
    "pixels",
    [
        np.random.default_rng(1).integers(0, 65536, (48, 64)).astype(np.uint16),  # BZERO 32768
        np.random.default_rng(2).integers(0, 32768, (30, 20)).astype(np.int16),  # BZERO 0
        np.array([[0, 65535], [32767, 32768]], dtype=np.uint16),
    ],
)
def test_the_fast_read_equals_astropys(pixels: np.ndarray) -> None:
    blob = Blob(_fits(pixels, INSTRUME="Sim CCD", GAIN=90, OBJECT="not a driver card"), ".fits")
    fast = plain_fits_frame(blob, "CCD")
    full = blocking_read_fits(blob, "CCD")
    assert fast is not None
    assert fast.data.dtype == np.uint16 and np.array_equal(fast.data, full.data)
    assert np.array_equal(fast.data, pixels.astype(np.uint16))
    assert fast.header == full.header == {"INSTRUME": ("Sim CCD", ""), "GAIN": (90, "")}


async def test_other_images_go_to_astropy_in_a_thread() -> None:
    floats = Blob(_fits(np.full((4, 5), 7.0, dtype=np.float32)), ".fits")
    assert plain_fits_frame(floats, "CCD") is None
    frame = await fits_frame(floats, "CCD")
    assert frame.data.dtype == np.uint16 and frame.data.shape == (4, 5) and int(frame.data[0, 0]) == 7
    assert plain_fits_frame(Blob(b"not a FITS file", ".fits"), "CCD") is None


def test_bad_plain_images_name_the_problem() -> None:
    negative = Blob(_fits(np.array([[-5, 3]], dtype=np.int16)), ".fits")
    with pytest.raises(IndiError, match=r"CCD\.CCD1: pixels outside 0\.\.65535"):
        plain_fits_frame(negative, "CCD")
    whole = _fits(np.ones((100, 100), dtype=np.uint16))
    with pytest.raises(IndiError, match="100x100 pixels announced, the data is shorter"):
        plain_fits_frame(Blob(whole[: len(whole) // 2], ".fits"), "CCD")
