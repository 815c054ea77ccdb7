"""Turning a frame and its header cards into FITS bytes (astropy, imported on first use)."""

from __future__ import annotations

import io
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from nightcrew.interfaces import FitsCard

__all__ = ["blocking_fits_bytes", "build_hdu_list"]

_CARD_LENGTH = 80


def _fitted(keyword: str, value: Any, comment: str) -> tuple[Any, str]:
    """Shorten a long string value or comment so the card fits in 80 characters (no warnings)."""
    if isinstance(value, str):
        value = value[:66]
        value_length = max(20, len(value) + 2)
    else:
        value_length = 20
    room = _CARD_LENGTH - 10 - value_length - 3  # "KEYWORD = ", value, " / "
    return value, comment[: max(0, room)]


def build_hdu_list(data: npt.NDArray[Any], cards: Mapping[str, FitsCard]) -> Any:
    """A one-HDU astropy HDUList holding ``data`` with ``cards`` (keyword → (value, comment))."""
    from astropy.io import fits  # type: ignore[import-untyped]

    hdu = fits.PrimaryHDU(np.asarray(data))
    for keyword, (value, comment) in cards.items():
        if keyword in ("SIMPLE", "BITPIX", "EXTEND", "BZERO", "BSCALE") or keyword.startswith("NAXIS"):
            continue  # structural keywords belong to astropy
        hdu.header[keyword] = _fitted(keyword, value, comment)
    return fits.HDUList([hdu])


def blocking_fits_bytes(data: npt.NDArray[Any], cards: Mapping[str, FitsCard]) -> bytes:
    """The FITS file of ``data`` with ``cards`` (astropy serialises in Python: run it in a thread).

    Raises:
        ValueError: A card astropy cannot write (its verification failed).
    """
    from astropy.io import fits

    buffer = io.BytesIO()
    try:
        build_hdu_list(data, cards).writeto(buffer, output_verify="exception")
    except (OSError, TypeError, fits.VerifyError) as exc:
        raise ValueError(f"cannot write FITS: {exc}") from exc
    return buffer.getvalue()
