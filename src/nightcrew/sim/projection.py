"""Gnomonic (TAN) projection between the sky and a camera's pixels, and the matching FITS WCS.

Conventions:

- The pointing (``Pointing.ra_deg``, ``Pointing.dec_deg``) is the optical axis and falls on the
  centre of the full, unbinned chip, ``((chip_width - 1) / 2, (chip_height - 1) / 2)``.
- Pixel coordinates are 0-based with integer values at pixel centres, ``x`` along columns (the
  last numpy axis) and ``y`` along rows, in the *output* frame: after windowing and binning.
- With ``rotation_deg = 0`` north is +y and east is -x (the sky as seen on the sky). A positive
  rotation turns the detector's +y axis from north towards east: it is the position angle of +y.
- Standard coordinates (xi east, eta north) on the tangent plane relate to unbinned offsets
  ``(du, dv)`` from the chip centre by ``xi = s (-cos r du + sin r dv)``,
  ``eta = s (sin r du + cos r dv)`` with ``s`` the pixel scale — the FITS ``CD`` matrix.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]

__all__ = ["FrameGeometry", "Pointing", "Window", "pixel_to_sky", "sky_to_pixel", "wcs_header"]

FloatArray = npt.NDArray[np.float64]
ArrayLike = npt.ArrayLike


@dataclass(frozen=True)
class Pointing:
    """Where the optical axis points (ICRS degrees) and the detector's position angle (degrees)."""

    ra_deg: float
    dec_deg: float
    rotation_deg: float = 0.0

    def __post_init__(self) -> None:
        if not -90.0 <= self.dec_deg <= 90.0:
            raise ValueError(f"dec_deg must be within [-90, 90], got {self.dec_deg}")


@dataclass(frozen=True)
class Window:
    """A readout window in unbinned pixels of the full chip: left/bottom corner and size."""

    x: int
    y: int
    width: int
    height: int


@dataclass(frozen=True)
class FrameGeometry:
    """Chip size (unbinned pixels), unbinned pixel scale (arcsec/px), binning and optional window."""

    chip_width: int
    chip_height: int
    pixel_scale_arcsec: float
    binning: int = 1
    window: Window | None = None

    def __post_init__(self) -> None:
        if self.chip_width < 1 or self.chip_height < 1:
            raise ValueError(f"chip size must be positive, got {self.chip_width}x{self.chip_height}")
        if self.pixel_scale_arcsec <= 0:
            raise ValueError(f"pixel_scale_arcsec must be positive, got {self.pixel_scale_arcsec}")
        if self.binning < 1:
            raise ValueError(f"binning must be >= 1, got {self.binning}")
        w = self.full_window
        if w.x < 0 or w.y < 0 or w.width < 1 or w.height < 1:
            raise ValueError(f"window must be non-empty and inside the chip, got {w}")
        if w.x + w.width > self.chip_width or w.y + w.height > self.chip_height:
            raise ValueError(f"window {w} exceeds the {self.chip_width}x{self.chip_height} chip")
        if w.width < self.binning or w.height < self.binning:
            raise ValueError(f"window {w} is smaller than binning {self.binning}")

    @property
    def full_window(self) -> Window:
        """The readout window, the whole chip when none is set."""
        return self.window or Window(0, 0, self.chip_width, self.chip_height)

    @property
    def shape(self) -> tuple[int, int]:
        """Shape (rows, columns) of the output frame; partial bins at the window edge are dropped."""
        w = self.full_window
        return w.height // self.binning, w.width // self.binning

    def unbinned_to_output(self, u: FloatArray, v: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Unbinned chip coordinates to output (windowed, binned) pixel coordinates."""
        w, b = self.full_window, self.binning
        return (u - w.x - (b - 1) / 2.0) / b, (v - w.y - (b - 1) / 2.0) / b

    def output_to_unbinned(self, x: FloatArray, y: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Output pixel coordinates to unbinned chip coordinates (the centre of the bin)."""
        w, b = self.full_window, self.binning
        return w.x + b * x + (b - 1) / 2.0, w.y + b * y + (b - 1) / 2.0


def _cd_matrix(scale_deg: float, rotation_deg: float) -> FloatArray:
    c, s = math.cos(math.radians(rotation_deg)), math.sin(math.radians(rotation_deg))
    return scale_deg * np.array([[-c, s], [s, c]])


def _tangent_basis(ra_deg: float, dec_deg: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    ra, dec = math.radians(ra_deg), math.radians(dec_deg)
    centre = np.array([math.cos(dec) * math.cos(ra), math.cos(dec) * math.sin(ra), math.sin(dec)])
    east = np.array([-math.sin(ra), math.cos(ra), 0.0])
    north = np.array([-math.sin(dec) * math.cos(ra), -math.sin(dec) * math.sin(ra), math.cos(dec)])
    return centre, east, north


def sky_to_pixel(
    ra_deg: ArrayLike, dec_deg: ArrayLike, pointing: Pointing, geometry: FrameGeometry
) -> tuple[FloatArray, FloatArray]:
    """Output pixel coordinates of sky positions (degrees); NaN for points 90 deg or more away."""
    ra = np.radians(np.asarray(ra_deg, dtype=np.float64))
    dec = np.radians(np.asarray(dec_deg, dtype=np.float64))
    centre, east, north = _tangent_basis(pointing.ra_deg, pointing.dec_deg)
    cos_dec = np.cos(dec)
    vec = np.stack([cos_dec * np.cos(ra), cos_dec * np.sin(ra), np.sin(dec)], axis=-1)
    depth = vec @ centre
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = np.degrees(np.where(depth > 0, (vec @ east) / depth, np.nan))
        eta = np.degrees(np.where(depth > 0, (vec @ north) / depth, np.nan))
    cd = _cd_matrix(geometry.pixel_scale_arcsec / 3600.0, pointing.rotation_deg)
    inv = np.linalg.inv(cd)
    du = inv[0, 0] * xi + inv[0, 1] * eta
    dv = inv[1, 0] * xi + inv[1, 1] * eta
    u = du + (geometry.chip_width - 1) / 2.0
    v = dv + (geometry.chip_height - 1) / 2.0
    return geometry.unbinned_to_output(u, v)


def pixel_to_sky(
    x: ArrayLike, y: ArrayLike, pointing: Pointing, geometry: FrameGeometry
) -> tuple[FloatArray, FloatArray]:
    """Sky positions (degrees; RA in [0, 360)) of output pixel coordinates."""
    u, v = geometry.output_to_unbinned(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
    du = u - (geometry.chip_width - 1) / 2.0
    dv = v - (geometry.chip_height - 1) / 2.0
    cd = _cd_matrix(geometry.pixel_scale_arcsec / 3600.0, pointing.rotation_deg)
    xi = np.radians(cd[0, 0] * du + cd[0, 1] * dv)
    eta = np.radians(cd[1, 0] * du + cd[1, 1] * dv)
    centre, east, north = _tangent_basis(pointing.ra_deg, pointing.dec_deg)
    vec = centre + xi[..., None] * east + eta[..., None] * north
    vec /= np.linalg.norm(vec, axis=-1, keepdims=True)
    ra = np.mod(np.degrees(np.arctan2(vec[..., 1], vec[..., 0])), 360.0)
    dec = np.degrees(np.arcsin(np.clip(vec[..., 2], -1.0, 1.0)))
    return ra, dec


def wcs_header(pointing: Pointing, geometry: FrameGeometry) -> fits.Header:
    """A FITS header with the exact TAN WCS (CD matrix, ICRS) of frames rendered at ``pointing``."""
    b = geometry.binning
    w = geometry.full_window
    crpix1 = ((geometry.chip_width - 1) / 2.0 - w.x - (b - 1) / 2.0) / b + 1.0
    crpix2 = ((geometry.chip_height - 1) / 2.0 - w.y - (b - 1) / 2.0) / b + 1.0
    cd = _cd_matrix(geometry.pixel_scale_arcsec * b / 3600.0, pointing.rotation_deg)
    rows, cols = geometry.shape
    header = fits.Header()
    header["NAXIS"] = 2
    header["NAXIS1"] = cols
    header["NAXIS2"] = rows
    header["WCSAXES"] = 2
    header["CTYPE1"] = "RA---TAN"
    header["CTYPE2"] = "DEC--TAN"
    header["CUNIT1"] = "deg"
    header["CUNIT2"] = "deg"
    header["CRVAL1"] = pointing.ra_deg % 360.0
    header["CRVAL2"] = pointing.dec_deg
    header["CRPIX1"] = crpix1
    header["CRPIX2"] = crpix2
    header["CD1_1"], header["CD1_2"] = float(cd[0, 0]), float(cd[0, 1])
    header["CD2_1"], header["CD2_2"] = float(cd[1, 0]), float(cd[1, 1])
    header["RADESYS"] = "ICRS"
    header["EQUINOX"] = 2000.0
    return header
