"""Masters and calibration on :class:`~nightcrew.images.Image`: the array functions plus headers.

A master is an Image whose header says what it is (``IMAGETYP = master_bias`` etc.), how it was
taken (``XBINNING``, ``YBINNING``, ``FILTER``, ``EXPTIME``, ``DATE-OBS`` of its first frame) and
how many frames it holds (``NCOMBINE``); its uncertainty layer is the master's 1-sigma error.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.images.calibration._library import MasterKind, frame_key
from nightcrew.images.calibration._masters import (
    Combined,
    calibrate_pixels,
    master_bias,
    master_dark,
    master_flat,
)
from nightcrew.images.errors import ImageDataError
from nightcrew.images.image import Image

__all__ = ["build_master", "calibrate_image", "master_kind"]

_COPIED = ("DATE-OBS", "MJD-OBS", "XBINNING", "YBINNING", "INSTRUME", "TELESCOP", "XORGSUBF", "YORGSUBF")


def master_kind(image: Image) -> MasterKind | None:
    """The kind of master ``image`` is, or None if it is not a master."""
    value = str(image.header.get("IMAGETYP", "")).strip().lower()
    return next((kind for kind in MasterKind if kind.image_type == value), None)


def build_master(
    kind: MasterKind,
    frames: Sequence[Image],
    *,
    bias: Image | None = None,
    dark: Image | None = None,
    sigma: float = 3.0,
) -> Image:
    """A master of ``kind`` from raw frames (darks and flats need ``bias``; flats may use ``dark``).

    Raises:
        ImageDataError: no frames, a missing bias, or frames of different shapes.
    """
    if not frames:
        raise ImageDataError(f"no frames for a master {kind.value}")
    pixels = [frame.data for frame in frames]
    if kind is MasterKind.BIAS:
        combined = master_bias(pixels, sigma=sigma)
    elif bias is None:
        raise ImageDataError(f"a master {kind.value} needs a master bias")
    elif kind is MasterKind.DARK:
        combined = master_dark(pixels, _combined(bias), sigma=sigma)
    else:
        combined = master_flat(
            pixels,
            _combined(bias),
            dark=None if dark is None else _combined(dark),
            dark_exposure_s=_exposure(dark),
            exposure_times_s=[_exposure(f) for f in frames],
            sigma=sigma,
        )
    first = frames[0].header
    header = fits.Header()
    for keyword in _COPIED:
        if keyword in first:
            header[keyword] = first[keyword]
    header["IMAGETYP"] = (kind.image_type, "Master calibration frame")
    header["EXPTIME"] = (_exposure(frames[0]) if kind is MasterKind.DARK else 0.0, "Exposure time [s]")
    if kind is MasterKind.FLAT and frame_key(first).filter is not None:
        header["FILTER"] = frame_key(first).filter
    header["NCOMBINE"] = (combined.n_frames, "Frames combined")
    return Image(combined.data, header=header, uncertainty=combined.uncertainty)


def calibrate_image(
    image: Image, *, bias: Image, dark: Image | None = None, flat: Image | None = None
) -> Image:
    """``image`` with bias and scaled dark subtracted and divided by the flat (float32 pixels).

    Pixels the flat cannot correct join the image's bad-pixel mask. The header names the masters
    used (``CAL-BIAS``, ``CAL-DARK``, ``CAL-FLAT``: their DATE-OBS/NCOMBINE summary) and the
    image keeps its other layers.
    """
    data, bad = calibrate_pixels(
        image.data,
        bias=_combined(bias),
        dark=None if dark is None else _combined(dark),
        dark_exposure_s=_exposure(dark),
        flat=None if flat is None else _combined(flat),
        exposure_s=_exposure(image),
    )
    mask = bad if image.mask is None else (bad | image.mask)
    header = image.header.copy()
    for keyword, master in (("CAL-BIAS", bias), ("CAL-DARK", dark), ("CAL-FLAT", flat)):
        if master is not None:
            header[keyword] = (_describe(master), "Master used for calibration")
    header["BUNIT"] = ("adu", "Calibrated counts")
    return image.replace(data=data, header=header, mask=mask if mask.any() else None)


def _combined(master: Image) -> Combined:
    uncertainty = master.uncertainty if master.uncertainty is not None else np.zeros(master.shape, np.float32)
    n = master.header.get("NCOMBINE", 1)
    return Combined(
        np.asarray(master.data, np.float32),
        np.asarray(uncertainty, np.float32),
        int(n) if isinstance(n, int) else 1,
    )


def _exposure(image: Image | None) -> float:
    if image is None:
        return 0.0
    value = image.header.get("EXPTIME", 0.0)
    return float(value) if isinstance(value, int | float) and not isinstance(value, bool) else 0.0


def _describe(master: Image) -> str:
    return f"{master.header.get('DATE-OBS', '?')} x{master.header.get('NCOMBINE', '?')}"
