"""The Alpaca ImageBytes format: a binary image array, encoded and decoded with numpy.

Facts from the ASCOM Alpaca ImageBytes specification: a reply starts with a 44-byte header of
eleven little-endian 32-bit integers::

    offset  field
     0      MetadataVersion (1)
     4      ErrorNumber (0: an image follows; else a UTF-8 error message follows)
     8      ClientTransactionID
    12      ServerTransactionID
    16      DataStart (offset of the data, 44 for version 1)
    20      ImageElementType (the camera's native pixel type)
    24      TransmissionElementType (the type on the wire)
    28      Rank (2 or 3)
    32      Dimension1 (x, the number of columns)
    36      Dimension2 (y, the number of rows)
    40      Dimension3 (colour planes; 0 for rank 2)

The data are the ``ImageArray`` ``[x][y]`` (``[x][y][plane]`` for rank 3) in that index order,
the last index varying fastest, little-endian. nightcrew arrays are ``[y, x]`` (rows first), so
:func:`encode` and :func:`decode` transpose.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from enum import IntEnum
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = [
    "HEADER_SIZE",
    "ElementType",
    "ImageBytesError",
    "ImageBytesHeader",
    "decode",
    "decode_header",
    "element_type_of",
    "encode",
    "encode_error",
    "error_message",
]

HEADER_SIZE = 44
_HEADER = struct.Struct("<11I")
_METADATA_VERSION = 1


class ElementType(IntEnum):
    """Alpaca ImageArrayElementType values."""

    UNKNOWN = 0
    INT16 = 1
    INT32 = 2
    DOUBLE = 3
    SINGLE = 4
    UINT64 = 5
    BYTE = 6
    INT64 = 7
    UINT16 = 8
    UINT32 = 9


_DTYPES: dict[ElementType, str] = {
    ElementType.INT16: "<i2",
    ElementType.INT32: "<i4",
    ElementType.DOUBLE: "<f8",
    ElementType.SINGLE: "<f4",
    ElementType.UINT64: "<u8",
    ElementType.BYTE: "u1",
    ElementType.INT64: "<i8",
    ElementType.UINT16: "<u2",
    ElementType.UINT32: "<u4",
}
_ELEMENT_OF_KIND = {np.dtype(code).newbyteorder("="): element for element, code in _DTYPES.items()}


class ImageBytesError(ValueError):
    """Bytes that are not a valid ImageBytes reply (the message says what is wrong)."""


@dataclass(frozen=True)
class ImageBytesHeader:
    """The decoded 44-byte header."""

    metadata_version: int
    error_number: int
    client_transaction_id: int
    server_transaction_id: int
    data_start: int
    image_element_type: int
    transmission_element_type: int
    rank: int
    dimension1: int
    dimension2: int
    dimension3: int


def element_type_of(dtype: npt.DTypeLike) -> ElementType:
    """The Alpaca element type of a numpy dtype; ImageBytesError if Alpaca has none for it."""
    key = np.dtype(dtype).newbyteorder("=")
    if key not in _ELEMENT_OF_KIND:
        raise ImageBytesError(f"no Alpaca element type for pixels of type {np.dtype(dtype)}")
    return _ELEMENT_OF_KIND[key]


def encode(
    image: npt.NDArray[Any],
    *,
    client_transaction_id: int = 0,
    server_transaction_id: int = 0,
    image_element_type: ElementType | None = None,
) -> bytes:
    """ImageBytes of ``image`` (``[y, x]`` or ``[y, x, plane]``), sent with the array's own type.

    Args:
        image: The pixels, rank 2 or 3.
        client_transaction_id: Echoed from the request.
        server_transaction_id: The server's counter.
        image_element_type: The camera's native type, if it differs from the array's (e.g. INT32
            for a camera whose ImageArray is specified as Int32 but sends UInt16 on the wire).
    """
    if image.ndim not in (2, 3):
        raise ImageBytesError(f"an image must have rank 2 or 3, got rank {image.ndim}")
    transmission = element_type_of(image.dtype)
    native = transmission if image_element_type is None else image_element_type
    axes = (1, 0) if image.ndim == 2 else (1, 0, 2)
    data = np.ascontiguousarray(image.transpose(axes), dtype=np.dtype(_DTYPES[transmission]))
    dim1, dim2 = data.shape[0], data.shape[1]
    dim3 = data.shape[2] if image.ndim == 3 else 0
    header = _HEADER.pack(
        _METADATA_VERSION,
        0,
        _uint32(client_transaction_id),
        _uint32(server_transaction_id),
        HEADER_SIZE,
        int(native),
        int(transmission),
        image.ndim,
        dim1,
        dim2,
        dim3,
    )
    return header + data.tobytes()


def encode_error(
    error_number: int, message: str, *, client_transaction_id: int = 0, server_transaction_id: int = 0
) -> bytes:
    """An ImageBytes reply carrying an Alpaca error instead of an image."""
    if error_number == 0:
        raise ImageBytesError("an error reply needs a non-zero error number")
    header = _HEADER.pack(
        _METADATA_VERSION,
        error_number,
        _uint32(client_transaction_id),
        _uint32(server_transaction_id),
        HEADER_SIZE,
        0,
        0,
        0,
        0,
        0,
        0,
    )
    return header + message.encode("utf-8")


def decode_header(payload: bytes | memoryview) -> ImageBytesHeader:
    """The header of an ImageBytes reply; ImageBytesError if it is short or inconsistent."""
    if len(payload) < HEADER_SIZE:
        raise ImageBytesError(f"ImageBytes reply of {len(payload)} bytes is shorter than its 44-byte header")
    header = ImageBytesHeader(*_HEADER.unpack_from(payload, 0))
    if header.metadata_version != _METADATA_VERSION:
        raise ImageBytesError(f"unknown ImageBytes metadata version {header.metadata_version}")
    if not HEADER_SIZE <= header.data_start <= len(payload):
        raise ImageBytesError(
            f"ImageBytes data start {header.data_start} lies outside the {len(payload)}-byte reply"
        )
    return header


def decode(payload: bytes | memoryview) -> tuple[ImageBytesHeader, npt.NDArray[Any]]:
    """The header and the image (``[y, x]`` or ``[y, x, plane]``) of an ImageBytes reply.

    The array is a view of ``payload`` in the transmission type, read-only when the payload is.

    Raises:
        ImageBytesError: Malformed bytes, named in the message. A reply carrying an Alpaca error is
            returned with ``header.error_number`` set and an empty array; the caller maps the
            error (its message is :func:`error_message`).
    """
    header = decode_header(payload)
    if header.error_number != 0:
        return header, np.zeros((0, 0), dtype=np.uint16)
    try:
        transmission = ElementType(header.transmission_element_type)
    except ValueError:
        raise ImageBytesError(
            f"unknown ImageBytes transmission element type {header.transmission_element_type}"
        ) from None
    if transmission is ElementType.UNKNOWN:
        raise ImageBytesError("ImageBytes transmission element type is 0 (unknown)")
    if header.rank == 2:
        shape: tuple[int, ...] = (header.dimension1, header.dimension2)
    elif header.rank == 3:
        shape = (header.dimension1, header.dimension2, header.dimension3)
    else:
        raise ImageBytesError(f"ImageBytes rank must be 2 or 3, got {header.rank}")
    if any(size <= 0 for size in shape):
        raise ImageBytesError(f"ImageBytes dimensions must be positive, got {shape}")
    dtype = np.dtype(_DTYPES[transmission])
    expected = int(np.prod(shape)) * dtype.itemsize
    got = len(payload) - header.data_start
    if got != expected:
        size = "x".join(str(s) for s in shape)
        raise ImageBytesError(
            f"ImageBytes data of {got} bytes do not match a {size} {transmission.name} image "
            f"({expected} bytes)"
        )
    data = np.frombuffer(payload, dtype=dtype, count=int(np.prod(shape)), offset=header.data_start)
    image = data.reshape(shape)
    axes = (1, 0) if header.rank == 2 else (1, 0, 2)
    return header, image.transpose(axes)


def error_message(payload: bytes | memoryview, header: ImageBytesHeader) -> str:
    """The UTF-8 error message of an error reply (undecodable bytes replaced)."""
    return bytes(payload[header.data_start :]).decode("utf-8", errors="replace")


def _uint32(value: int) -> int:
    # Transaction ids are unsigned 32-bit counters that may wrap.
    return value & 0xFFFFFFFF
