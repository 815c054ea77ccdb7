"""The moving body's position on a plate-solved frame, and its MPC 80-column line.

A frame taken while the telescope follows a body carries the body's ephemeris at the exposure's
start (``MOVOBJ``, ``EPH-RA``/``EPH-DEC``, rates ``EPH-RAR``/``EPH-DECR`` in arcsec/s, the RA rate
on the sky). :func:`predicted_position` moves it by the rates over half the exposure to the
mid-time (``MJD-OBS`` + ``EXPTIME``/2). :func:`measure_moving_body` looks for the brightest source
within ``search_radius`` of that position on the background-subtracted frame and centroids it
(a 2-D Gaussian fit, photutils), then turns the centroid into (ra, dec) with the frame's WCS (the
plate solution): an astrometric ICRS position measured against the field stars.

A saturated body (a flat-topped core: a bright planet) is not measured: its centroid would not be
astrometry, and the MPC takes no planets. It is noted in ``MOV-NOTE`` instead.

Cards written (:data:`MOVING_CARDS`): ``MOV-X``/``MOV-Y`` (0-based pixels), ``MOV-RA``/``MOV-DEC``
(degrees, ICRS), ``MOV-MJD`` (mid-exposure, UTC MJD), ``MOV-DIFF`` (arcsec from the ephemeris),
or ``MOV-NOTE`` when nothing was measured. Only the frame's pixels and headers are read.
"""

from __future__ import annotations

import asyncio
import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
from photutils.centroids import centroid_2dg  # type: ignore[import-untyped]

from nightcrew.astro.mpc_report import mpc_observation_line
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require
from nightcrew.images.processors._shared import estimate_background, float_data

__all__ = [
    "MOVING_CARDS",
    "MeasureMovingBody",
    "MovingBodyMeasurement",
    "measure_moving_body",
    "mpc_line_of",
    "predicted_position",
]

FloatArray = npt.NDArray[np.float64]
MOVING_CARDS = ("MOV-X", "MOV-Y", "MOV-RA", "MOV-DEC", "MOV-MJD", "MOV-DIFF", "MOV-NOTE")
_UNIX_MJD0 = 40_587.0  # MJD of 1970-01-01
_EPHEMERIS_CARDS = ("MOVOBJ", "EPH-RA", "EPH-DEC", "EPH-RAR", "EPH-DECR", "EXPTIME", "MJD-OBS")
#: Pixels within this fraction of the brightest that make a flat top (saturated): more than a
#: Moffat core's one or two.
_PLATEAU_LEVEL, _PLATEAU_PIXELS = 0.98, 4


@dataclass(frozen=True)
class MovingBodyMeasurement:
    """Where the body was found: 0-based pixels, ICRS degrees, mid-exposure MJD (UTC), and the
    distance from the ephemeris position in arcsec."""

    x: float
    y: float
    ra: float
    dec: float
    mjd: float
    offset_arcsec: float


def predicted_position(header: Any) -> tuple[float, float, float] | None:
    """The ephemeris (ra, dec) at mid-exposure and that time (UTC MJD); None without the cards."""
    if any(key not in header for key in _EPHEMERIS_CARDS):
        return None
    half = float(header["EXPTIME"]) / 2.0
    dec = float(header["EPH-DEC"]) + float(header["EPH-DECR"]) * half / 3600.0
    cos_dec = max(math.cos(math.radians(dec)), 1e-6)
    ra = (float(header["EPH-RA"]) + float(header["EPH-RAR"]) * half / 3600.0 / cos_dec) % 360.0
    return ra, dec, float(header["MJD-OBS"]) + half / 86_400.0


def measure_moving_body(
    image: Image, *, search_radius_arcsec: float = 10.0, box_px: int = 7
) -> MovingBodyMeasurement | str:
    """The body's position on ``image`` (which needs a WCS and the ephemeris cards), or a note
    saying why there is none."""
    predicted = predicted_position(image.header)
    scale = image.pixel_scale
    if predicted is None:
        return f"no ephemeris: the frame lacks one of {', '.join(_EPHEMERIS_CARDS)}"
    if image.wcs is None or scale is None:
        return "no WCS: the field was not solved"
    ra0, dec0, mjd = predicted
    x0, y0 = (float(v) for v in image.sky_to_pixel(ra0, dec0))
    data = float_data(image)
    rows, cols = data.shape
    reach = max(box_px, math.ceil(search_radius_arcsec / scale))
    top, left = max(0, round(y0) - reach), max(0, round(x0) - reach)
    bottom, right = min(rows, round(y0) + reach + 1), min(cols, round(x0) + reach + 1)
    if top >= bottom or left >= right:
        return "the ephemeris position is off the frame"
    background = estimate_background(data)
    clean = data - background.level
    region = clean[top:bottom, left:right]
    yy, xx = np.indices(region.shape)
    inside = np.hypot(xx + left - x0, yy + top - y0) <= search_radius_arcsec / scale
    if not inside.any():
        return "the ephemeris position is off the frame"
    peak_index = np.unravel_index(np.argmax(np.where(inside, region, -np.inf)), region.shape)
    py, px = int(peak_index[0]) + top, int(peak_index[1]) + left
    peak = float(clean[py, px])
    if peak < 5.0 * background.global_rms:
        return f"nothing above 5 sigma within {search_radius_arcsec:g} arcsec of the ephemeris"
    half = box_px // 2
    cut_top, cut_left = max(0, py - half), max(0, px - half)
    cutout = clean[cut_top : py + half + 1, cut_left : px + half + 1]
    if int(np.count_nonzero(cutout >= _PLATEAU_LEVEL * peak)) > _PLATEAU_PIXELS:
        return "saturated: not measured"
    cx, cy = centroid_2dg(cutout)
    if not (np.isfinite(cx) and np.isfinite(cy)):
        return "the centroid fit failed"
    x, y = float(cx) + cut_left, float(cy) + cut_top
    ra, dec = (float(v) for v in image.pixel_to_sky(x, y))
    d_ra = ((ra - ra0 + 180.0) % 360.0 - 180.0) * math.cos(math.radians(dec))
    offset = math.hypot(d_ra, dec - dec0) * 3600.0
    return MovingBodyMeasurement(x=x, y=y, ra=ra, dec=dec, mjd=mjd, offset_arcsec=offset)


def mpc_line_of(header: Any, observatory_code: str) -> str | None:
    """The MPC 80-column line of a frame's measured position (``MOV-*`` cards); None if none.

    The designation is ``MOVOBJ`` reduced to letters and digits, its first seven as a temporary
    designation: replace it with the packed designation before submitting a known body.
    """
    if "MOV-RA" not in header or "MOVOBJ" not in header:
        return None
    designation = re.sub(r"[^A-Za-z0-9]", "", str(header["MOVOBJ"]))[:7] or "UNKNOWN"
    return mpc_observation_line(
        unix_time=(float(header["MOV-MJD"]) - _UNIX_MJD0) * 86_400.0,
        ra=float(header["MOV-RA"]),
        dec=float(header["MOV-DEC"]),
        observatory_code=observatory_code,
        designation=designation,
    )


class MeasureMovingBody(ImageProcessor):
    """Measure the followed body on a plate-solved frame (see the module docstring); a frame
    without ephemeris cards passes unchanged.

    Args:
        search_radius: How far from the ephemeris position to look, arcsec.
        box: Side of the centroid's box, pixels (odd, >= 5).
    """

    def __init__(self, *, search_radius: float = 10.0, box: int = 7, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        require(math.isfinite(search_radius) and search_radius > 0, "search_radius", "must be > 0 arcsec")
        require(box >= 5 and box % 2 == 1, "box", f"must be odd and >= 5 pixels, got {box}")
        self._search_radius, self._box = float(search_radius), int(box)

    async def __call__(self, image: Image) -> Image:
        if "MOVOBJ" not in image.header:
            return image
        found = await asyncio.to_thread(
            measure_moving_body, image, search_radius_arcsec=self._search_radius, box_px=self._box
        )
        header = image.header.copy()
        for key in MOVING_CARDS:
            header.remove(key, ignore_missing=True)
        if isinstance(found, str):
            header["MOV-NOTE"] = found[:68]
        else:
            header["MOV-X"] = (round(found.x, 3), "Moving body x, 0-based [px]")
            header["MOV-Y"] = (round(found.y, 3), "Moving body y, 0-based [px]")
            header["MOV-RA"] = (round(found.ra, 7), "Moving body RA measured, ICRS [deg]")
            header["MOV-DEC"] = (round(found.dec, 7), "Moving body Dec measured, ICRS [deg]")
            header["MOV-MJD"] = (round(found.mjd, 8), "Mid-exposure, UTC [MJD]")
            header["MOV-DIFF"] = (round(found.offset_arcsec, 3), "Measured minus ephemeris [arcsec]")
        return image.replace(header=header)
