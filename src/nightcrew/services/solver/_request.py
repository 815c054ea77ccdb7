"""A solve request of the service's JSON API (version 1, documented in
:mod:`nightcrew.images.astrometry._remote`), parsed and checked before anything is solved.

Every problem is one :class:`SolveRequestError` naming the field and what is wrong with it; the
server answers it with HTTP 400.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from nightcrew.images.astrometry import API_VERSION

__all__ = ["MAX_SIZE_PX", "MAX_STARS", "MIN_STARS", "SolveRequest", "SolveRequestError", "parse_request"]

FloatArray = npt.NDArray[np.float64]

MIN_STARS = 8
"""Fewest stars a request may hold: a quad takes four and its verification several more."""
MAX_STARS = 5000
MAX_SIZE_PX = 100_000


class SolveRequestError(ValueError):
    """A request the service cannot take; the message names the field."""


@dataclass(frozen=True)
class SolveRequest:
    """A checked request: 0-based star positions (brightest first), frame size and hints."""

    width: int
    height: int
    x: FloatArray
    y: FloatArray
    flux: FloatArray
    ra_deg: float | None = None
    dec_deg: float | None = None
    radius_deg: float = 1.0
    pixel_scale_arcsec: float | None = None
    scale_tolerance: float = 0.1

    @property
    def scale_range_arcsec(self) -> tuple[float, float] | None:
        """(lowest, highest) pixel scale searched, or None for any."""
        if self.pixel_scale_arcsec is None:
            return None
        return (
            self.pixel_scale_arcsec * (1.0 - self.scale_tolerance),
            self.pixel_scale_arcsec * (1.0 + self.scale_tolerance),
        )


def parse_request(body: Any) -> SolveRequest:
    """The :class:`SolveRequest` in a decoded JSON ``body``.

    Raises:
        SolveRequestError: a field is missing, of the wrong type or out of range.
    """
    if not isinstance(body, dict):
        raise SolveRequestError("the request must be a JSON object")
    version = body.get("version", API_VERSION)
    if version != API_VERSION:
        raise SolveRequestError(f"version: this service speaks version {API_VERSION}, got {version!r}")
    width = _integer(body, "width", 1, MAX_SIZE_PX)
    height = _integer(body, "height", 1, MAX_SIZE_PX)
    stars = body.get("stars")
    if not isinstance(stars, dict):
        raise SolveRequestError('stars: expected an object {"x": [...], "y": [...], "flux": [...]}')
    x, y = _column(stars, "x", -0.5, width - 0.5), _column(stars, "y", -0.5, height - 0.5)
    flux = _column(stars, "flux", -math.inf, math.inf)
    if not len(x) == len(y) == len(flux):
        raise SolveRequestError(f"stars: x, y and flux differ in length ({len(x)}, {len(y)}, {len(flux)})")
    if len(x) < MIN_STARS:
        raise SolveRequestError(f"stars: too few stars to solve: {len(x)} (need at least {MIN_STARS})")
    if len(x) > MAX_STARS:
        raise SolveRequestError(f"stars: too many stars: {len(x)} (at most {MAX_STARS}; send the brightest)")
    order = np.argsort(-flux, kind="stable")  # astrometry.net tries the brightest stars first
    hints = body.get("hints", {})
    if not isinstance(hints, dict):
        raise SolveRequestError("hints: expected an object")
    unknown = set(hints) - {"ra", "dec", "radius", "pixel_scale", "scale_tolerance"}
    if unknown:
        raise SolveRequestError(f"hints: unknown field(s) {', '.join(sorted(unknown))}")
    ra, dec = _number(hints, "ra", 0.0, 360.0), _number(hints, "dec", -90.0, 90.0)
    if (ra is None) != (dec is None):
        raise SolveRequestError("hints: give both ra and dec, or neither")
    radius = _number(hints, "radius", 0.0, 180.0, open_low=True)
    scale = _number(hints, "pixel_scale", 0.0, 3600.0, open_low=True)
    tolerance = _number(hints, "scale_tolerance", 0.0, 1.0, open_low=True, open_high=True)
    return SolveRequest(
        width=width,
        height=height,
        x=x[order],
        y=y[order],
        flux=flux[order],
        ra_deg=None if ra is None else ra % 360.0,
        dec_deg=dec,
        radius_deg=1.0 if radius is None else radius,
        pixel_scale_arcsec=scale,
        scale_tolerance=0.1 if tolerance is None else tolerance,
    )


def _integer(body: dict[str, Any], name: str, low: int, high: int) -> int:
    value = body.get(name)
    if not isinstance(value, int) or isinstance(value, bool):
        raise SolveRequestError(f"{name}: expected an integer number of pixels, got {value!r}")
    if not low <= value <= high:
        raise SolveRequestError(f"{name}: must be within {low}..{high}, got {value}")
    return value


def _column(stars: dict[str, Any], name: str, low: float, high: float) -> FloatArray:
    values = stars.get(name)
    if not isinstance(values, list) or not all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in values
    ):
        raise SolveRequestError(f"stars.{name}: expected a list of numbers")
    array = np.asarray(values, dtype=np.float64)
    bad = ~np.isfinite(array) | (array < low) | (array > high)
    if bad.any():
        index = int(np.argmax(bad))
        raise SolveRequestError(
            f"stars.{name}[{index}]: {values[index]!r} is outside the frame"
            if math.isfinite(low)
            else f"stars.{name}[{index}]: {values[index]!r} is not a finite number"
        )
    return array


def _number(
    hints: dict[str, Any],
    name: str,
    low: float,
    high: float,
    *,
    open_low: bool = False,
    open_high: bool = False,
) -> float | None:
    value = hints.get(name)
    if value is None:
        return None
    if not isinstance(value, int | float) or isinstance(value, bool) or not math.isfinite(value):
        raise SolveRequestError(f"hints.{name}: expected a number, got {value!r}")
    too_low = value <= low if open_low else value < low
    too_high = value >= high if open_high else value > high
    if too_low or too_high:
        lo, hi = "(" if open_low else "[", ")" if open_high else "]"
        raise SolveRequestError(f"hints.{name}: must be within {lo}{low:g}, {high:g}{hi}, got {value}")
    return float(value)
