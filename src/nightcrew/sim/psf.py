"""Point spread function: FWHM from seeing and focus, and Moffat star stamps added to an image.

Focus model (documented in :func:`fwhm_arcsec`): the in-focus FWHM combines seeing and the optics'
own blur in quadrature; defocus adds a blur growing linearly with the focus error, also in
quadrature, which gives the hyperbola that focus-series fits expect.

Star profile: a circular Moffat, ``I(r) = (beta - 1) / (pi alpha^2) * (1 + r^2/alpha^2)^-beta``, with
``FWHM = 2 alpha sqrt(2^(1/beta) - 1)``, point-sampled at pixel centres on a square stamp around
each star, and normalised so the stamp holds the star's whole flux (the wing beyond the stamp,
< 0.5 % for beta = 3 and a 4-FWHM radius, is folded back in). Real defocused stars are rings;
here they stay Moffat profiles of the larger FWHM.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = ["fwhm_arcsec", "moffat_alpha", "render_stars", "stamp_radius"]

FloatArray = npt.NDArray[np.float64]
Float32Array = npt.NDArray[np.float32]

MAX_STAMP_RADIUS = 200
"""Largest stamp half-size in pixels (very bright stars' wings are cut there)."""


def fwhm_arcsec(
    seeing_arcsec: float,
    focus: float,
    *,
    best_focus: float,
    optics_fwhm_arcsec: float = 0.0,
    defocus_arcsec_per_unit: float = 30.0,
) -> float:
    """Image FWHM (arcsec): ``sqrt(seeing^2 + optics^2 + (a * (focus - best_focus))^2)``.

    ``a`` (``defocus_arcsec_per_unit``) is the FWHM growth per unit of focus error (e.g. per mm of
    focuser travel: about the blur circle ``206265 * dz / (N * f)`` for an f/N telescope of focal
    length f). Far from focus the FWHM grows linearly with |focus - best_focus| (the hyperbola's
    asymptotes), near it the seeing and optics set the minimum.
    """
    if seeing_arcsec < 0 or optics_fwhm_arcsec < 0:
        raise ValueError(f"seeing and optics FWHM must be >= 0, got {seeing_arcsec}, {optics_fwhm_arcsec}")
    defocus = defocus_arcsec_per_unit * (focus - best_focus)
    return math.sqrt(seeing_arcsec**2 + optics_fwhm_arcsec**2 + defocus**2)


def moffat_alpha(fwhm_px: float, beta: float) -> float:
    """Moffat core width alpha (pixels) for a FWHM (pixels) and power index beta."""
    return fwhm_px / (2.0 * math.sqrt(2.0 ** (1.0 / beta) - 1.0))


def stamp_radius(
    flux_e: FloatArray, fwhm_px: float, beta: float, *, floor_e: float = 0.5
) -> npt.NDArray[np.int64]:
    """Stamp half-size (pixels) per star: at least 4 FWHM, more where the wing exceeds ``floor_e``.

    The Moffat wing falls as ``(beta-1)/(pi alpha^2) (r/alpha)^(-2 beta)``; the radius where a star
    of ``flux_e`` electrons drops below ``floor_e`` per pixel is used for bright stars, rounded up
    to a power-of-two multiple of the base radius so that stars share a few stamp sizes.
    """
    alpha = moffat_alpha(fwhm_px, beta)
    base = max(3, math.ceil(4.0 * fwhm_px))
    peak = np.maximum(flux_e, floor_e) * (beta - 1.0) / (math.pi * alpha**2)
    wing = alpha * (peak / floor_e) ** (1.0 / (2.0 * beta))
    factor = np.maximum(1.0, wing / base)
    radius = base * 2 ** np.ceil(np.log2(factor))
    return np.asarray(np.minimum(radius, max(base, MAX_STAMP_RADIUS)), dtype=np.int64)


def render_stars(
    shape: tuple[int, int],
    x: FloatArray,
    y: FloatArray,
    flux_e: FloatArray,
    *,
    fwhm_px: float,
    beta: float = 3.0,
) -> Float32Array:
    """An image of ``shape`` (rows, cols) holding Moffat stars at (``x``, ``y``) with ``flux_e`` electrons.

    Coordinates are 0-based pixel centres (x = column). Stars are evaluated on stamps, vectorised
    over stars of equal stamp size, and added with clipping at the image edge; stars whose stamp
    misses the image add nothing.
    """
    if fwhm_px <= 0:
        raise ValueError(f"fwhm_px must be positive, got {fwhm_px}")
    if beta <= 1.0:
        raise ValueError(f"beta must be > 1, got {beta}")
    image = np.zeros(shape, dtype=np.float32)
    rows, cols = shape
    radii = stamp_radius(flux_e, fwhm_px, beta)
    ix = np.rint(x).astype(np.int64)
    iy = np.rint(y).astype(np.int64)
    visible = (ix + radii >= 0) & (ix - radii < cols) & (iy + radii >= 0) & (iy - radii < rows)
    inv_alpha2 = np.float32(1.0 / moffat_alpha(fwhm_px, beta) ** 2)
    for radius in np.unique(radii[visible]):
        sel = np.flatnonzero(visible & (radii == radius))
        r = int(radius)
        offsets = np.arange(-r, r + 1, dtype=np.float32)
        dx = offsets[None, None, :] - (x[sel] - ix[sel]).astype(np.float32)[:, None, None]
        dy = offsets[None, :, None] - (y[sel] - iy[sel]).astype(np.float32)[:, None, None]
        stamps = (np.float32(1.0) + (dx * dx + dy * dy) * inv_alpha2) ** np.float32(-beta)
        scale = (flux_e[sel] / stamps.sum(axis=(1, 2), dtype=np.float64)).astype(np.float32)
        stamps *= scale[:, None, None]
        for k, star in enumerate(sel):
            _add_clipped(image, stamps[k], int(iy[star]) - r, int(ix[star]) - r)
    return image


def _add_clipped(image: Float32Array, stamp: Float32Array, top: int, left: int) -> None:
    """Add ``stamp`` to ``image`` with its corner at (top, left), dropping what falls outside."""
    size_y, size_x = stamp.shape
    y0, x0 = max(top, 0), max(left, 0)
    y1, x1 = min(top + size_y, image.shape[0]), min(left + size_x, image.shape[1])
    if y0 < y1 and x0 < x1:
        image[y0:y1, x0:x1] += stamp[y0 - top : y1 - top, x0 - left : x1 - left]
