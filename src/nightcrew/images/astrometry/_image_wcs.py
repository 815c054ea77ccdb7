"""Between images and solvers: hints read from the header, stars from the catalog, the WCS written back."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.images.errors import MissingWcsError, NoStarsError
from nightcrew.images.image import Image

__all__ = [
    "AstrometryResult",
    "image_pixel_scale",
    "image_pointing",
    "image_stars",
    "is_wcs_keyword",
    "require_pointing",
    "with_wcs",
]

FloatArray = npt.NDArray[np.float64]

#: Header keywords that belong to a celestial WCS (removed before a new solution is written).
_WCS_KEYWORD = re.compile(
    r"^(WCSAXES|WCSNAME|CTYPE\d|CUNIT\d|CRVAL\d|CRPIX\d|CD\d_\d|PC\d_\d|CDELT\d|CROTA\d|PV\d_\d+|"
    r"LONPOLE|LATPOLE|RADESYS|EQUINOX|[AB]P?_\d+_\d+|[AB]P?_ORDER|[AB]_DMAX)$"
)


def is_wcs_keyword(keyword: str) -> bool:
    """Whether ``keyword`` belongs to a celestial WCS (CTYPE1, CRVAL2, CD1_1, SIP terms...)."""
    return bool(_WCS_KEYWORD.match(keyword))


@dataclass(frozen=True)
class AstrometryResult:
    """What a solve found, kept in ``image.metadata["astrometry"]`` (and the ``AST-*`` cards).

    Attributes:
        solver: ``catalog``, ``astrometry.net`` or ``remote``.
        matched: Stars the solution rests on, when the solver says.
        rms_arcsec: Their residual RMS, when the solver says.
    """

    solver: str
    matched: int | None = None
    rms_arcsec: float | None = None


def image_pointing(image: Image) -> tuple[float, float] | None:
    """Where the telescope pointed (degrees): the header's ``RA``/``DEC``, else the WCS centre."""
    ra, dec = image.header.get("RA"), image.header.get("DEC")
    if _number(ra) and _number(dec) and -90.0 <= float(dec) <= 90.0:
        return float(ra) % 360.0, float(dec)
    wcs = image.wcs
    if wcs is None:
        return None
    rows, cols = image.shape
    sky = wcs.celestial.all_pix2world([[(cols - 1) / 2.0, (rows - 1) / 2.0]], 0)[0]
    return float(sky[0]) % 360.0, float(sky[1])


def image_pixel_scale(image: Image, unbinned_arcsec: float | None) -> float | None:
    """The frame's pixel scale: ``unbinned_arcsec`` times ``XBINNING`` if given, else the image's own."""
    if unbinned_arcsec is not None:
        binning = image.header.get("XBINNING", 1)
        return unbinned_arcsec * (float(binning) if _number(binning) and binning >= 1 else 1.0)
    return image.pixel_scale


def image_stars(image: Image, flux_column: str = "flux") -> tuple[FloatArray, FloatArray, FloatArray]:
    """x, y (0-based) and flux of the image's catalog, finite rows only.

    Raises:
        NoStarsError: no catalog (run a detection processor first) or no usable rows.
    """
    catalog = image.catalog
    if catalog is None or not {"x", "y", flux_column} <= set(catalog.colnames):
        raise NoStarsError(
            f"astrometry needs a source catalog with x, y and {flux_column}: run a detection first"
        )
    x, y, flux = (np.asarray(catalog[name], dtype=np.float64) for name in ("x", "y", flux_column))
    good = np.isfinite(x) & np.isfinite(y) & np.isfinite(flux)
    if not good.any():
        raise NoStarsError("the source catalog has no usable stars")
    return x[good], y[good], flux[good]


def require_pointing(image: Image) -> tuple[float, float]:
    """:func:`image_pointing`, or :class:`MissingWcsError` when the header has no position."""
    pointing = image_pointing(image)
    if pointing is None:
        raise MissingWcsError("the header has neither RA/DEC nor a WCS: no position to solve near")
    return pointing


def with_wcs(image: Image, cards: fits.Header | dict[str, Any], result: AstrometryResult) -> Image:
    """A copy of ``image`` with the solution's WCS cards (replacing any old WCS) and sky columns.

    The catalog, when present, gains ``ra`` and ``dec`` columns (degrees) from the new WCS.
    """
    header = image.header.copy()
    for keyword in [k for k in header if _WCS_KEYWORD.match(k)]:
        header.remove(keyword, ignore_missing=True, remove_all=True)
    for keyword, value in cards.items():
        if _WCS_KEYWORD.match(keyword):
            header[keyword] = value
    header["AST-SOLV"] = (result.solver, "Plate solver of the WCS")
    if result.matched is not None:
        header["AST-NSTR"] = (result.matched, "Stars matched by the plate solution")
    if result.rms_arcsec is not None:
        header["AST-RMS"] = (round(result.rms_arcsec, 4), "RMS of the plate solution [arcsec]")
    catalog = None if image.catalog is None else image.catalog.copy()
    if catalog is not None and len(catalog) and {"x", "y"} <= set(catalog.colnames):
        wcs = WCS(header, naxis=2)
        ra, dec = wcs.all_pix2world(np.asarray(catalog["x"], float), np.asarray(catalog["y"], float), 0)
        catalog["ra"], catalog["dec"] = ra, dec
    metadata = {**image.metadata, "astrometry": result}
    return image.replace(header=header, catalog=catalog, metadata=metadata)


def _number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
