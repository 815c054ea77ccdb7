"""The ImageBytes format: round trips, the header's fields, and malformed input."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from nightcrew.bridges.alpaca import imagebytes
from nightcrew.bridges.alpaca.imagebytes import ElementType, ImageBytesError


def test_round_trip_rank2_uint16_keeps_rows_and_columns() -> None:
    image = np.arange(12, dtype=np.uint16).reshape(3, 4)  # 3 rows (y), 4 columns (x)
    payload = imagebytes.encode(image, client_transaction_id=7, server_transaction_id=9)
    header, decoded = imagebytes.decode(payload)
    assert (header.rank, header.dimension1, header.dimension2, header.dimension3) == (2, 4, 3, 0)
    assert header.transmission_element_type == ElementType.UINT16
    assert (header.client_transaction_id, header.server_transaction_id) == (7, 9)
    assert header.data_start == imagebytes.HEADER_SIZE
    np.testing.assert_array_equal(decoded, image)
    assert len(payload) == 44 + 12 * 2


def test_data_are_x_major_as_the_spec_says() -> None:
    # ImageArray[x][y]: the y index varies fastest on the wire.
    image = np.array([[1, 2], [3, 4]], dtype=np.int32)  # image[y, x]
    payload = imagebytes.encode(image)
    assert struct.unpack("<4i", payload[44:]) == (1, 3, 2, 4)


@pytest.mark.parametrize("dtype", ["uint16", "int16", "int32", "uint32", "float64", "float32", "uint8"])
def test_round_trip_every_dtype_and_rank3(dtype: str) -> None:
    rng = np.random.default_rng(1)
    image = (rng.random((5, 6, 3)) * 100).astype(dtype)
    header, decoded = imagebytes.decode(imagebytes.encode(image))
    assert header.rank == 3 and header.dimension3 == 3
    np.testing.assert_array_equal(decoded, image)


def test_native_type_differs_from_transmission_type() -> None:
    image = np.ones((2, 2), dtype=np.uint16)
    header = imagebytes.decode_header(imagebytes.encode(image, image_element_type=ElementType.INT32))
    assert (header.image_element_type, header.transmission_element_type) == (2, 8)


def test_error_reply_carries_number_and_message() -> None:
    payload = imagebytes.encode_error(0x40B, "camera is exposing", client_transaction_id=3)
    header, image = imagebytes.decode(payload)
    assert header.error_number == 0x40B and image.size == 0
    assert imagebytes.error_message(payload, header) == "camera is exposing"


def test_wrapping_transaction_ids() -> None:
    header = imagebytes.decode_header(
        imagebytes.encode(np.ones((1, 1), np.uint16), client_transaction_id=2**32 + 5)
    )
    assert header.client_transaction_id == 5


def _header(**fields: int) -> bytes:
    values = {
        "version": 1,
        "error": 0,
        "ctid": 0,
        "stid": 0,
        "start": 44,
        "native": 8,
        "wire": 8,
        "rank": 2,
        "d1": 2,
        "d2": 2,
        "d3": 0,
    }
    values.update(fields)
    return struct.pack("<11I", *values.values())


@pytest.mark.parametrize(
    ("payload", "message"),
    [
        (b"\x01\x00", "shorter than its 44-byte header"),
        (_header(version=2) + bytes(8), "unknown ImageBytes metadata version 2"),
        (_header(start=100) + bytes(8), "data start 100 lies outside"),
        (_header(wire=42) + bytes(8), "unknown ImageBytes transmission element type 42"),
        (_header(wire=0) + bytes(8), "element type is 0"),
        (_header(rank=4) + bytes(8), "rank must be 2 or 3, got 4"),
        (_header(d1=0) + bytes(8), "dimensions must be positive"),
        (_header() + bytes(7), "data of 7 bytes do not match a 2x2 UINT16 image \\(8 bytes\\)"),
        (_header(d1=4096, d2=4096) + bytes(8), "do not match a 4096x4096"),
    ],
)
def test_malformed_input_is_named(payload: bytes, message: str) -> None:
    with pytest.raises(ImageBytesError, match=message):
        imagebytes.decode(payload)


def test_encode_refuses_what_alpaca_cannot_carry() -> None:
    with pytest.raises(ImageBytesError, match="rank 2 or 3, got rank 1"):
        imagebytes.encode(np.ones(3, np.uint16))
    with pytest.raises(ImageBytesError, match="no Alpaca element type for pixels of type complex128"):
        imagebytes.encode(np.ones((2, 2), complex))
    with pytest.raises(ImageBytesError, match="non-zero error number"):
        imagebytes.encode_error(0, "fine")
