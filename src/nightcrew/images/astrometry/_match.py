"""A fast plate solver for frames taken near a known pointing: detected stars against a catalog.

:class:`CatalogMatcher` works on arrays only. The steps:

1. Catalog stars around the hinted pointing are projected onto the tangent plane, in pixels of
   the hinted scale ("sky pixels": +u west, +v north, which is how an unrotated camera sees them).
2. **Rotation and scale** come from a vote over pairs: every pair of bright detected stars is
   compared with every catalog pair of about the same length; a true correspondence votes for the
   frame's rotation (difference of the pair angles) and scale (ratio of the lengths). Pairs are
   translation invariant, so a pointing error of many arcminutes does not matter here.
3. **Offset**: detected stars, rotated and scaled, are compared with catalog stars; the most common
   difference vector is the pointing error.
4. **Refinement**: stars are paired with their mutual nearest neighbours and a TAN WCS is fitted
   by least squares with outlier rejection (:func:`~nightcrew.images.astrometry._tan.fit_tan_wcs`),
   first with the brightest stars and a loose radius, then with many stars and a tight one.

Both parities are tried when ``allow_flip`` is set (a camera mounted mirrored).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nightcrew.images.astrometry._errors import NoSolutionError
from nightcrew.images.astrometry._tan import TanFit, TanWcs, fit_tan_wcs, sky_to_standard
from nightcrew.images.errors import NoStarsError

__all__ = ["CatalogMatch", "CatalogMatcher"]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]

_ANGLE_BIN_DEG = 1.0
_MIN_PAIR_PX = 60.0  # shorter pairs give imprecise angles and only add noise to the vote


@dataclass(frozen=True)
class CatalogMatch:
    """A solution: the WCS, how many stars it rests on and their residual RMS (arcsec)."""

    wcs: TanWcs
    matched: int
    rms_arcsec: float


@dataclass(frozen=True)
class _Similarity:
    """Detected pixel offsets from the centre → sky pixels: mirror, rotate, scale, shift."""

    parity: int
    angle_rad: float
    scale: float
    shift: tuple[float, float] = (0.0, 0.0)

    def apply(self, dx: FloatArray, dy: FloatArray) -> tuple[FloatArray, FloatArray]:
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        mx = self.parity * dx
        return (
            self.scale * (c * mx - s * dy) + self.shift[0],
            self.scale * (s * mx + c * dy) + self.shift[1],
        )


class CatalogMatcher:
    """Solves frames near a known pointing against catalog stars (see the module docstring).

    Args:
        bright_stars: Brightest detections used for the rotation/offset votes.
        fit_stars: Brightest detections used for the final fit.
        search_radius_arcmin: Largest pointing error looked for.
        scale_tolerance: Relative uncertainty of the hinted pixel scale.
        match_radius_px: Final pairing radius (pixels).
        min_matches: Fewest matched stars accepted as a solution.
        allow_flip: Also try a mirrored camera.
    """

    def __init__(
        self,
        *,
        bright_stars: int = 40,
        fit_stars: int = 400,
        search_radius_arcmin: float = 15.0,
        scale_tolerance: float = 0.03,
        match_radius_px: float = 2.0,
        min_matches: int = 10,
        allow_flip: bool = True,
    ) -> None:
        if bright_stars < 5:
            raise ValueError(f"bright_stars must be >= 5, got {bright_stars}")
        if fit_stars < bright_stars:
            raise ValueError(f"fit_stars must be >= bright_stars ({bright_stars}), got {fit_stars}")
        if search_radius_arcmin <= 0:
            raise ValueError(f"search_radius_arcmin must be positive, got {search_radius_arcmin}")
        if not 0.0 < scale_tolerance < 0.5:
            raise ValueError(f"scale_tolerance must be within (0, 0.5), got {scale_tolerance}")
        if match_radius_px <= 0:
            raise ValueError(f"match_radius_px must be positive, got {match_radius_px}")
        if min_matches < 4:
            raise ValueError(f"min_matches must be >= 4, got {min_matches}")
        self.bright_stars = bright_stars
        self.fit_stars = fit_stars
        self.search_radius_arcmin = search_radius_arcmin
        self.scale_tolerance = scale_tolerance
        self.match_radius_px = match_radius_px
        self.min_matches = min_matches
        self.allow_flip = allow_flip

    def catalog_radius_deg(self, shape: tuple[int, int], pixel_scale_arcsec: float) -> float:
        """Radius of the catalog cone a solve needs: the frame's half diagonal plus the search radius."""
        half_diagonal_px = 0.5 * math.hypot(*shape)
        scale = pixel_scale_arcsec * (1.0 + self.scale_tolerance)
        return half_diagonal_px * scale / 3600.0 + self.search_radius_arcmin / 60.0

    def solve(
        self,
        x: npt.ArrayLike,
        y: npt.ArrayLike,
        flux: npt.ArrayLike,
        *,
        shape: tuple[int, int],
        catalog_ra: npt.ArrayLike,
        catalog_dec: npt.ArrayLike,
        catalog_mag: npt.ArrayLike,
        ra_deg: float,
        dec_deg: float,
        pixel_scale_arcsec: float,
    ) -> CatalogMatch:
        """Solve detections (0-based ``x``, ``y``, ``flux``) of a ``shape`` frame near the hint.

        The catalog should cover :meth:`catalog_radius_deg` around the hint.

        Raises:
            NoSolutionError: no consistent match (too few stars, wrong hint or scale).
        """
        if pixel_scale_arcsec <= 0:
            raise ValueError(f"pixel_scale_arcsec must be positive, got {pixel_scale_arcsec}")
        det_x, det_y, det_flux = (np.asarray(a, dtype=np.float64) for a in (x, y, flux))
        good = np.isfinite(det_x) & np.isfinite(det_y) & np.isfinite(det_flux)
        order = np.argsort(-det_flux[good], kind="stable")
        det_x, det_y = det_x[good][order], det_y[good][order]
        centre = ((shape[1] - 1) / 2.0, (shape[0] - 1) / 2.0)
        dx, dy = det_x - centre[0], det_y - centre[1]

        cat_ra, cat_dec, cat_mag = (
            np.asarray(a, dtype=np.float64) for a in (catalog_ra, catalog_dec, catalog_mag)
        )
        xi, eta = sky_to_standard(cat_ra, cat_dec, ra_deg, dec_deg)
        scale_deg = pixel_scale_arcsec / 3600.0
        u, v = -xi / scale_deg, eta / scale_deg
        radius_px = self.catalog_radius_deg(shape, pixel_scale_arcsec) / scale_deg
        near = np.isfinite(u) & (np.hypot(u, v) < radius_px)
        by_mag = np.argsort(cat_mag[near], kind="stable")
        cat_u, cat_v = u[near][by_mag], v[near][by_mag]
        cat_ra, cat_dec = cat_ra[near][by_mag], cat_dec[near][by_mag]
        if len(det_x) < self.min_matches or len(cat_u) < self.min_matches:
            raise NoSolutionError(
                f"too few stars to match: {len(det_x)} detected, {len(cat_u)} in the catalog around the hint"
            )

        # The catalog cone is larger than the frame: take as many of its brightest stars as the
        # frame's share of the cone would hold of the detected brightest.
        area_ratio = math.pi * radius_px**2 / (shape[0] * shape[1])
        n_bright = min(self.bright_stars, len(det_x))
        n_cat = min(len(cat_u), max(n_bright, int(1.5 * area_ratio * n_bright)))
        search_px = self.search_radius_arcmin * 60.0 / pixel_scale_arcsec
        similarity = self._coarse(dx[:n_bright], dy[:n_bright], cat_u[:n_cat], cat_v[:n_cat], search_px)

        # Loose pairing of the brightest stars, then a tight one of many with the fitted WCS.
        guess = TanWcs(crval=(ra_deg, dec_deg), crpix=centre, cd=((-scale_deg, 0.0), (0.0, scale_deg)))
        su, sv = similarity.apply(dx[: self.fit_stars], dy[: self.fit_stars])
        in_frame = self._in_frame_catalog(cat_u, cat_v, similarity, shape)
        fit = self._fit_pairs(
            det_x,
            det_y,
            su,
            sv,
            cat_u[in_frame],
            cat_v[in_frame],
            cat_ra[in_frame],
            cat_dec[in_frame],
            radius=4.0 * self.match_radius_px + 4.0,
            guess=guess,
        )
        for _ in range(2):
            px, py = fit.wcs.sky_to_pixel(cat_ra[in_frame], cat_dec[in_frame])
            fit = self._fit_pairs(
                det_x,
                det_y,
                det_x[: self.fit_stars],
                det_y[: self.fit_stars],
                px,
                py,
                cat_ra[in_frame],
                cat_dec[in_frame],
                radius=self.match_radius_px,
                guess=fit.wcs,
            )
        matched = int(fit.used.sum())
        if matched < self.min_matches:
            raise NoSolutionError(f"only {matched} stars matched the catalog (need {self.min_matches})")
        return CatalogMatch(wcs=fit.wcs, matched=matched, rms_arcsec=fit.rms_arcsec)

    def _coarse(
        self, dx: FloatArray, dy: FloatArray, cat_u: FloatArray, cat_v: FloatArray, search_px: float
    ) -> _Similarity:
        """Parity, rotation, scale and shift: the candidate whose offset vote has the highest peak.

        The pair vote knows the rotation only modulo 180 degrees (a pair has no preferred end), so
        both candidates are tried for each parity.
        """
        best: tuple[int, _Similarity] | None = None
        for parity in (1, -1) if self.allow_flip else (1,):
            angle, scale = self._rotation_vote(parity * dx, dy, cat_u, cat_v)
            for turn in (0.0, math.pi):
                rough = _Similarity(parity, angle + turn, scale)
                su, sv = rough.apply(dx, dy)
                votes, shift = self._offset_vote(su, sv, cat_u, cat_v, search_px)
                if best is None or votes > best[0]:
                    best = (votes, _Similarity(parity, angle + turn, scale, shift))
        assert best is not None
        return best[1]

    def _rotation_vote(
        self, dx: FloatArray, dy: FloatArray, cat_u: FloatArray, cat_v: FloatArray
    ) -> tuple[float, float]:
        """(angle modulo pi, scale) at the peak of the pair-angle / length-ratio histogram."""
        det_len, det_angle = _pairs(dx, dy)
        cat_len, cat_angle = _pairs(cat_u, cat_v)
        order = np.argsort(cat_len)
        cat_log, cat_angle = np.log(cat_len[order]), cat_angle[order]
        log_tol = math.log1p(self.scale_tolerance)
        det_log = np.log(det_len)
        lo = np.searchsorted(cat_log, det_log - log_tol)
        hi = np.searchsorted(cat_log, det_log + log_tol)
        counts = hi - lo
        if counts.sum() == 0:
            raise NoSolutionError("no catalog star pairs match the detected ones at the hinted pixel scale")
        det_index = np.repeat(np.arange(len(det_log)), counts)
        starts = np.repeat(np.cumsum(counts) - counts, counts)
        cat_index = np.arange(counts.sum()) - starts + np.repeat(lo, counts)
        d_angle = np.mod(cat_angle[cat_index] - det_angle[det_index], math.pi)
        d_log = cat_log[cat_index] - det_log[det_index]
        n_angle = round(180.0 / _ANGLE_BIN_DEG)
        n_log = max(3, round(2 * log_tol / 0.01))
        hist, _, _ = np.histogram2d(
            d_angle, d_log, bins=(n_angle, n_log), range=((0.0, math.pi), (-log_tol, log_tol))
        )
        # Sum 2x2 neighbourhoods (the angle wraps) so a peak on a bin edge is not split in two.
        pooled = hist + np.roll(hist, -1, axis=0)
        pooled[:, :-1] += pooled[:, 1:]
        i, j = np.unravel_index(int(np.argmax(pooled)), pooled.shape)
        angle_bin, log_bin = math.pi / n_angle, 2 * log_tol / n_log
        angle_centre, log_centre = (i + 1) * angle_bin, -log_tol + (j + 1) * log_bin
        off_angle = np.mod(d_angle - angle_centre + math.pi / 2, math.pi) - math.pi / 2
        near = (np.abs(off_angle) < angle_bin) & (np.abs(d_log - log_centre) < log_bin)
        return angle_centre + float(np.median(off_angle[near])), math.exp(float(np.median(d_log[near])))

    def _offset_vote(
        self, su: FloatArray, sv: FloatArray, cat_u: FloatArray, cat_v: FloatArray, limit: float
    ) -> tuple[int, tuple[float, float]]:
        """Votes for and value of the most common catalog-minus-detection vector within ``limit``."""
        diff_u = (cat_u[None, :] - su[:, None]).ravel()
        diff_v = (cat_v[None, :] - sv[:, None]).ravel()
        bin_px = 8.0  # wider than the blur of a rotation error of half a vote bin at the frame edge
        n = max(1, int(2 * limit / bin_px))
        hist, u_edges, v_edges = np.histogram2d(
            diff_u, diff_v, bins=n, range=((-limit, limit), (-limit, limit))
        )
        pooled = hist.copy()
        pooled[:-1, :] += hist[1:, :]
        pooled[:, :-1] += pooled[:, 1:]
        i, j = np.unravel_index(int(np.argmax(pooled)), pooled.shape)
        u0, v0 = u_edges[i + 1], v_edges[j + 1]
        near = (np.abs(diff_u - u0) < bin_px) & (np.abs(diff_v - v0) < bin_px)
        return int(pooled[i, j]), (float(np.median(diff_u[near])), float(np.median(diff_v[near])))

    @staticmethod
    def _in_frame_catalog(
        cat_u: FloatArray, cat_v: FloatArray, similarity: _Similarity, shape: tuple[int, int]
    ) -> npt.NDArray[np.bool_]:
        """Catalog stars that fall on the frame (plus a small margin) under the coarse solution."""
        half_diagonal = 0.5 * math.hypot(*shape) * similarity.scale + 20.0
        return np.asarray(
            np.hypot(cat_u - similarity.shift[0], cat_v - similarity.shift[1]) < half_diagonal, dtype=np.bool_
        )

    def _fit_pairs(
        self,
        det_x: FloatArray,
        det_y: FloatArray,
        det_a: FloatArray,
        det_b: FloatArray,
        cat_a: FloatArray,
        cat_b: FloatArray,
        cat_ra: FloatArray,
        cat_dec: FloatArray,
        *,
        radius: float,
        guess: TanWcs,
    ) -> TanFit:
        """Pair detections and catalog stars (both in one plane: ``a``, ``b``) and fit a TAN WCS."""
        n_cat = min(len(cat_a), 3 * len(det_a))  # fainter catalog stars than we detect only confuse
        det_i, cat_i = _mutual_nearest(det_a, det_b, cat_a[:n_cat], cat_b[:n_cat], radius)
        if len(det_i) < self.min_matches:
            raise NoSolutionError(
                f"only {len(det_i)} stars matched within {radius:.1f} px (need {self.min_matches})"
            )
        try:
            return fit_tan_wcs(
                det_x[det_i],
                det_y[det_i],
                cat_ra[cat_i],
                cat_dec[cat_i],
                crpix=guess.crpix,
                crval_guess=guess.crval,
                min_pairs=self.min_matches,
            )
        except NoStarsError as exc:
            raise NoSolutionError(f"the catalog match did not hold up: {exc}") from exc


def _pairs(x: FloatArray, y: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Length and direction of every pair (i < j) at least ``_MIN_PAIR_PX`` long."""
    i, j = np.triu_indices(len(x), k=1)
    ddx, ddy = x[j] - x[i], y[j] - y[i]
    length = np.hypot(ddx, ddy)
    long_enough = length >= _MIN_PAIR_PX
    return length[long_enough], np.arctan2(ddy, ddx)[long_enough]


def _mutual_nearest(
    ax: FloatArray, ay: FloatArray, bx: FloatArray, by: FloatArray, radius: float
) -> tuple[IntArray, IntArray]:
    """Index pairs (i, j) where a[i] and b[j] are each other's nearest neighbour within ``radius``."""
    if len(ax) == 0 or len(bx) == 0:
        return np.zeros(0, np.intp), np.zeros(0, np.intp)
    d2 = (ax[:, None] - bx[None, :]) ** 2 + (ay[:, None] - by[None, :]) ** 2
    nearest_b = np.argmin(d2, axis=1)
    nearest_a = np.argmin(d2, axis=0)
    a_index = np.arange(len(ax))
    mutual = (nearest_a[nearest_b] == a_index) & (d2[a_index, nearest_b] <= radius * radius)
    return a_index[mutual], nearest_b[mutual]
