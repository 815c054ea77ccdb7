"""The last frame of each camera, rendered for the browser: a region, a stretch, a size.

Pure apart from the data it is given: :func:`frame_from_hdul` takes what the VFS read,
:func:`render_png` turns a frame and :class:`View` into PNG bytes (the house's PNG encoder and
display stretch, :mod:`nightcrew.images.png`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from datetime import datetime
from typing import Any

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.errors import InvalidArgumentError
from nightcrew.images.png import encode_png, stretch_to_uint8

__all__ = ["STRETCHES", "Frame", "View", "frame_from_hdul", "render_png"]

STRETCHES = ("linear", "asinh", "log")
#: How much of the range the non-linear stretches compress (larger: more of the faint end shown).
_SOFTENING = 10.0


@dataclass(frozen=True)
class Frame:
    """A camera's frame as the console keeps it (pixels in display orientation: row 0 at the top)."""

    module: str
    id: int
    filename: str
    time: datetime
    pixels: npt.NDArray[np.float32]
    header: tuple[tuple[str, Any, str], ...]  # (key, value, comment) in order

    @property
    def width(self) -> int:
        return int(self.pixels.shape[1])

    @property
    def height(self) -> int:
        return int(self.pixels.shape[0])

    def describe(self) -> dict[str, Any]:
        return {
            "module": self.module,
            "id": self.id,
            "filename": self.filename,
            "time": self.time.isoformat(),
            "width": self.width,
            "height": self.height,
        }


def frame_from_hdul(hdul: fits.HDUList, *, module: str, id: int, filename: str, time: datetime) -> Frame:
    """The first image HDU of ``hdul`` as a Frame; InvalidArgumentError when it holds none."""
    for hdu in hdul:
        data = hdu.data
        if data is not None and getattr(data, "ndim", 0) >= 2:
            pixels = np.asarray(data, dtype=np.float32)
            while pixels.ndim > 2:  # a cube: show its first plane
                pixels = pixels[0]
            header = tuple(
                (card.keyword, _header_value(card.value), str(card.comment))
                for card in hdul[0].header.cards
                if card.keyword
            )
            # FITS row 0 is the bottom of the picture.
            return Frame(module, id, filename, time, np.ascontiguousarray(pixels[::-1]), header)
    raise InvalidArgumentError(f"{filename} holds no image")


def _header_value(value: Any) -> Any:
    if isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, np.generic):
        return value.item()
    return None  # an undefined value or a COMMENT/HISTORY placeholder


@dataclass(frozen=True)
class View:
    """What to show: a region (display pixels, 0,0 top-left), a stretch, the PNG's longest side."""

    stretch: str = "linear"
    low: float = 1.0
    high: float = 99.5
    max_size: int = 1024
    left: int | None = None
    top: int | None = None
    width: int | None = None
    height: int | None = None

    @classmethod
    def from_query(cls, query: Mapping[str, str]) -> View:
        """A View from URL query parameters; InvalidArgumentError names a bad one."""
        stretch = query.get("stretch", "linear")
        if stretch not in STRETCHES:
            raise InvalidArgumentError(f"stretch must be one of {', '.join(STRETCHES)}, got {stretch!r}")
        low, high = _number(query, "low", 1.0), _number(query, "high", 99.5)
        if not 0 <= low < high <= 100:
            raise InvalidArgumentError(f"need 0 <= low < high <= 100 (percentiles), got {low} and {high}")
        max_size = int(_number(query, "max_size", 1024))
        if not 16 <= max_size <= 4096:
            raise InvalidArgumentError(f"max_size must be within 16..4096, got {max_size}")
        region = {key: _whole(query, key) for key in ("left", "top", "width", "height")}
        return cls(stretch, low, high, max_size, **region)

    def region(self, frame: Frame) -> tuple[slice, slice]:
        """Rows and columns of ``frame`` to show; InvalidArgumentError when outside the frame."""
        left, top = self.left or 0, self.top or 0
        width = self.width if self.width is not None else frame.width - left
        height = self.height if self.height is not None else frame.height - top
        if left < 0 or top < 0 or width < 1 or height < 1:
            raise InvalidArgumentError(f"region {left},{top} {width}x{height} is empty or negative")
        if left + width > frame.width or top + height > frame.height:
            raise InvalidArgumentError(
                f"region {left},{top} {width}x{height} is outside the {frame.width}x{frame.height} frame"
            )
        return slice(top, top + height), slice(left, left + width)


def _number(query: Mapping[str, str], key: str, default: float) -> float:
    text = query.get(key)
    if text is None or text == "":
        return default
    try:
        return float(text)
    except ValueError:
        raise InvalidArgumentError(f"{key} must be a number, got {text!r}") from None


def _whole(query: Mapping[str, str], key: str) -> int | None:
    text = query.get(key)
    if text is None or text == "":
        return None
    try:
        return int(text)
    except ValueError:
        raise InvalidArgumentError(f"{key} must be a whole number of pixels, got {text!r}") from None


def render_png(frame: Frame, view: View) -> bytes:
    """The region of ``frame`` that ``view`` asks for, stretched, binned to fit, as PNG."""
    rows, cols = view.region(frame)
    region = frame.pixels[rows, cols]
    # stretch_to_uint8 flips FITS-style data; ours is top-down already, so hand it bottom-up.
    if view.stretch == "linear":
        pixels = stretch_to_uint8(region[::-1], low=view.low, high=view.high, max_size=view.max_size)
    else:
        scaled = _scaled(region, view.low, view.high)
        curved = (
            np.arcsinh(_SOFTENING * scaled) / np.arcsinh(_SOFTENING)
            if view.stretch == "asinh"
            else np.log1p(_SOFTENING * scaled) / np.log1p(_SOFTENING)
        )
        # The clipped percentiles fill 0 and 1, so min..max is (nearly) the curve's whole range.
        pixels = stretch_to_uint8(curved[::-1], low=0.0, high=100.0, max_size=view.max_size)
    return encode_png(pixels)


def _scaled(region: npt.NDArray[np.float32], low: float, high: float) -> npt.NDArray[np.float64]:
    finite = region[np.isfinite(region)]
    if finite.size == 0:
        return np.zeros(region.shape)
    lo, hi = np.percentile(finite, [low, high])
    scaled = (np.nan_to_num(region.astype(np.float64), nan=lo) - lo) / (hi - lo if hi > lo else 1.0)
    clipped: npt.NDArray[np.float64] = np.clip(scaled, 0.0, 1.0)
    return clipped
