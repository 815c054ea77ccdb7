"""The gnomonic (TAN) projection and a least-squares TAN WCS fit, on plain arrays.

Pixel coordinates are 0-based (numpy/astropy ``origin=0``); :class:`TanWcs` stores ``crpix`` 0-based
too and adds 1 only when it writes FITS cards. Standard coordinates ``xi`` (east) and ``eta``
(north) are in degrees, the FITS "intermediate world coordinates" of a ``RA---TAN`` axis pair.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nightcrew.images.errors import NoStarsError

__all__ = ["TanFit", "TanWcs", "fit_tan_wcs", "sky_to_standard", "standard_to_sky"]

FloatArray = npt.NDArray[np.float64]


def sky_to_standard(
    ra_deg: npt.ArrayLike, dec_deg: npt.ArrayLike, ra0_deg: float, dec0_deg: float
) -> tuple[FloatArray, FloatArray]:
    """Standard coordinates (xi east, eta north; degrees) of sky positions about a tangent point.

    Points 90 degrees or more from the tangent point have no projection and come out as NaN.
    """
    ra = np.radians(np.asarray(ra_deg, dtype=np.float64))
    dec = np.radians(np.asarray(dec_deg, dtype=np.float64))
    ra0, dec0 = math.radians(ra0_deg), math.radians(dec0_deg)
    d_ra = ra - ra0
    cos_dec, sin_dec = np.cos(dec), np.sin(dec)
    depth = sin_dec * math.sin(dec0) + cos_dec * math.cos(dec0) * np.cos(d_ra)
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = np.where(depth > 0, cos_dec * np.sin(d_ra) / depth, np.nan)
        eta = np.where(
            depth > 0, (sin_dec * math.cos(dec0) - cos_dec * math.sin(dec0) * np.cos(d_ra)) / depth, np.nan
        )
    return np.degrees(xi), np.degrees(eta)


def standard_to_sky(
    xi_deg: npt.ArrayLike, eta_deg: npt.ArrayLike, ra0_deg: float, dec0_deg: float
) -> tuple[FloatArray, FloatArray]:
    """Sky positions (degrees, RA in [0, 360)) of standard coordinates about a tangent point."""
    xi = np.radians(np.asarray(xi_deg, dtype=np.float64))
    eta = np.radians(np.asarray(eta_deg, dtype=np.float64))
    ra0, dec0 = math.radians(ra0_deg), math.radians(dec0_deg)
    denominator = math.cos(dec0) - eta * math.sin(dec0)
    ra = ra0 + np.arctan2(xi, denominator)
    dec = np.arctan2(math.sin(dec0) + eta * math.cos(dec0), np.hypot(xi, denominator))
    return np.mod(np.degrees(ra), 360.0), np.degrees(dec)


@dataclass(frozen=True)
class TanWcs:
    """A TAN WCS: tangent point (degrees), its 0-based pixel position and the CD matrix (deg/px)."""

    crval: tuple[float, float]
    crpix: tuple[float, float]
    cd: tuple[tuple[float, float], tuple[float, float]]

    @property
    def pixel_scale_arcsec(self) -> float:
        """Mean pixel scale (arcsec/px): the square root of the CD matrix's absolute determinant."""
        (a, b), (c, d) = self.cd
        return 3600.0 * math.sqrt(abs(a * d - b * c))

    @property
    def rotation_deg(self) -> float:
        """Position angle of the +y axis (north through east), as in :mod:`nightcrew.sim.projection`."""
        (_, b), (_, d) = self.cd
        return math.degrees(math.atan2(b, d)) % 360.0

    def pixel_to_sky(self, x: npt.ArrayLike, y: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Sky positions (degrees) of 0-based pixel coordinates."""
        dx = np.asarray(x, dtype=np.float64) - self.crpix[0]
        dy = np.asarray(y, dtype=np.float64) - self.crpix[1]
        (a, b), (c, d) = self.cd
        return standard_to_sky(a * dx + b * dy, c * dx + d * dy, *self.crval)

    def sky_to_pixel(self, ra_deg: npt.ArrayLike, dec_deg: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
        """0-based pixel coordinates of sky positions (degrees); NaN behind the tangent plane."""
        xi, eta = sky_to_standard(ra_deg, dec_deg, *self.crval)
        inverse = np.linalg.inv(np.array(self.cd))
        return (
            inverse[0, 0] * xi + inverse[0, 1] * eta + self.crpix[0],
            inverse[1, 0] * xi + inverse[1, 1] * eta + self.crpix[1],
        )

    def header_cards(self) -> dict[str, float | str]:
        """FITS WCS keywords (1-based CRPIX), ready to be set on a header."""
        (a, b), (c, d) = self.cd
        return {
            "WCSAXES": 2,
            "CTYPE1": "RA---TAN",
            "CTYPE2": "DEC--TAN",
            "CUNIT1": "deg",
            "CUNIT2": "deg",
            "CRVAL1": self.crval[0] % 360.0,
            "CRVAL2": self.crval[1],
            "CRPIX1": self.crpix[0] + 1.0,
            "CRPIX2": self.crpix[1] + 1.0,
            "CD1_1": a,
            "CD1_2": b,
            "CD2_1": c,
            "CD2_2": d,
            "RADESYS": "ICRS",
            "EQUINOX": 2000.0,
        }


@dataclass(frozen=True)
class TanFit:
    """A fitted WCS, which input pairs it kept and their residual RMS (arcsec)."""

    wcs: TanWcs
    used: npt.NDArray[np.bool_]
    rms_arcsec: float


def fit_tan_wcs(
    x: FloatArray,
    y: FloatArray,
    ra_deg: FloatArray,
    dec_deg: FloatArray,
    *,
    crpix: tuple[float, float],
    crval_guess: tuple[float, float],
    clip_sigma: float = 3.0,
    min_clip_arcsec: float = 0.2,
    min_pairs: int = 4,
    iterations: int = 5,
) -> TanFit:
    """Least-squares TAN WCS through matched pixel/sky pairs, rejecting outliers by sigma clipping.

    ``crpix`` stays fixed (0-based; usually the frame centre) while the CD matrix and the tangent
    point are fitted: a linear fit of standard coordinates against pixel offsets whose constant
    term moves the tangent point, repeated until it stops moving. Pairs off by more than
    ``clip_sigma`` times the RMS (and more than ``min_clip_arcsec``) are left out of the next round.

    Raises:
        NoStarsError: fewer than ``min_pairs`` pairs (before or after clipping).
    """
    used = np.isfinite(x) & np.isfinite(y) & np.isfinite(ra_deg) & np.isfinite(dec_deg)
    crval = crval_guess
    cd = np.eye(2)
    rms = math.inf
    for _ in range(iterations):
        if int(used.sum()) < min_pairs:
            raise NoStarsError(f"a WCS fit needs at least {min_pairs} matched stars, got {int(used.sum())}")
        dx, dy = x[used] - crpix[0], y[used] - crpix[1]
        design = np.column_stack([dx, dy, np.ones_like(dx)])
        for _ in range(4):  # re-centre the tangent point until the constant term vanishes
            xi, eta = sky_to_standard(ra_deg[used], dec_deg[used], *crval)
            (a, b, xi0), *_ = np.linalg.lstsq(design, xi, rcond=None)
            (c, d, eta0), *_ = np.linalg.lstsq(design, eta, rcond=None)
            ra0, dec0 = standard_to_sky(xi0, eta0, *crval)
            crval = (float(ra0), float(dec0))
            cd = np.array([[a, b], [c, d]])
            if math.hypot(xi0, eta0) * 3600.0 < 1e-6:
                break
        wcs = _wcs(crval, crpix, cd)
        residual = _residual_arcsec(wcs, x, y, ra_deg, dec_deg)
        rms = float(np.sqrt(np.mean(residual[used] ** 2)))
        keep = used & (residual <= max(clip_sigma * rms, min_clip_arcsec))
        if np.array_equal(keep, used):
            break
        used = keep
    return TanFit(wcs=_wcs(crval, crpix, cd), used=used, rms_arcsec=rms)


def _wcs(crval: tuple[float, float], crpix: tuple[float, float], cd: FloatArray) -> TanWcs:
    return TanWcs(
        crval=(crval[0] % 360.0, crval[1]),
        crpix=crpix,
        cd=((float(cd[0, 0]), float(cd[0, 1])), (float(cd[1, 0]), float(cd[1, 1]))),
    )


def _residual_arcsec(
    wcs: TanWcs, x: FloatArray, y: FloatArray, ra: FloatArray, dec: FloatArray
) -> FloatArray:
    """Distance (arcsec) between where the WCS puts each pixel and its catalog position."""
    fit_ra, fit_dec = wcs.pixel_to_sky(x, y)
    xi, eta = sky_to_standard(ra, dec, *wcs.crval)
    fit_xi, fit_eta = sky_to_standard(fit_ra, fit_dec, *wcs.crval)
    out = 3600.0 * np.hypot(xi - fit_xi, eta - fit_eta)
    return np.where(np.isfinite(out), out, np.inf)
