"""Rendering one simulated camera frame: stars, sky, camera effects and noise, as 16-bit ADU.

Pipeline of :func:`render_frame` (electrons until the last step):

1. Light (only with the roof open, the shutter open and a positive exposure time): stars from the
   catalog projected with :func:`~nightcrew.sim.projection.sky_to_pixel` and drawn as Moffat
   stamps (:mod:`~nightcrew.sim.psf`), plus the sky background (:mod:`~nightcrew.sim.sky`), the
   sum multiplied by the vignetting flat.
2. Dark current (uniform rate plus the camera's fixed hot pixels) and cosmic rays (a Poisson
   number of hits with mean ``cosmic_rays_per_s * exposure * window fraction``).
Motion (:class:`Motion`): when the pointing moves during the exposure (a mount following a moving
body) the stars are trailed along the field centre's path (:mod:`~nightcrew.sim.trail`), and each
moving body is drawn at its own positions at the same sub-times, so a followed body stays a point
and one the mount does not follow leaves a trail.

3. Charge binning, then photon + read noise (:func:`~nightcrew.sim.detector.sample_noise`), then
   gain, bias and clipping to [0, 65535] ADU.

Rendering happens at unbinned resolution over the readout window only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from nightcrew.sim.detector import (
    add_cosmic_rays,
    bin_image,
    digitize,
    hot_pixels,
    sample_noise,
    vignetting_flat,
)
from nightcrew.sim.projection import FrameGeometry, Pointing, Window, sky_to_pixel
from nightcrew.sim.psf import fwhm_arcsec, render_stars
from nightcrew.sim.sky import (
    sky_brightness_mag,
    sky_electrons_per_pixel_per_second,
    star_electrons_per_second,
)
from nightcrew.sim.trail import trail

__all__ = [
    "CameraModel",
    "Conditions",
    "Exposure",
    "Motion",
    "MovingBody",
    "Optics",
    "RenderedFrame",
    "StarTruth",
    "field_radius_deg",
    "frame_geometry",
    "render_frame",
]

FloatArray = npt.NDArray[np.float64]
ARCSEC_PER_RAD = 206264.806
#: Sub-times at which moving paths are projected exactly (see ``_pixels_along``).
_PATH_KNOTS = 65


@dataclass(frozen=True)
class CameraModel:
    """The camera: chip, electronics and fixed defects (``pattern_seed`` fixes hot pixels)."""

    chip_width: int = 2048
    chip_height: int = 2048
    pixel_size_um: float = 9.0
    gain_e_per_adu: float = 1.5
    read_noise_e: float = 8.0
    bias_adu: float = 1000.0
    dark_e_per_s: float = 0.02
    full_well_e: float | None = 100_000.0
    hot_pixel_fraction: float = 2e-5
    cosmic_rays_per_s: float = 0.1
    vignetting: float = 0.1
    pattern_seed: int = 0


@dataclass(frozen=True)
class Optics:
    """The telescope: focal length (sets the pixel scale), zero point (see sky), PSF and focus."""

    focal_length_mm: float = 1600.0
    zero_point_mag: float = 21.5
    optics_fwhm_arcsec: float = 0.8
    best_focus: float = 0.0
    defocus_arcsec_per_unit: float = 30.0
    moffat_beta: float = 3.0

    def pixel_scale_arcsec(self, pixel_size_um: float) -> float:
        """Unbinned pixel scale (arcsec/px) of a pixel of ``pixel_size_um`` at this focal length."""
        return ARCSEC_PER_RAD * pixel_size_um * 1e-3 / self.focal_length_mm


@dataclass(frozen=True)
class Conditions:
    """Atmosphere, sky and dome at the time of the exposure."""

    seeing_arcsec: float = 1.5
    airmass: float = 1.0
    extinction_mag_per_airmass: float = 0.2
    sun_altitude_deg: float = -30.0
    moon_altitude_deg: float = -30.0
    moon_illumination: float = 0.0
    dark_sky_mag: float = 21.0
    transmission: float = 1.0
    """Cloud transmission of starlight, 0..1 (the sky background is not dimmed)."""
    roof_open: bool = True
    panel_e_per_s: float = 0.0
    """Light of a flat panel in front of the optics, electrons per unbinned pixel and second
    before the filter (0: no panel lit)."""


@dataclass(frozen=True)
class Exposure:
    """What the camera is asked for: time (s), binning, window (unbinned px), shutter, filter."""

    exposure_time_s: float
    binning: int = 1
    window: Window | None = None
    shutter_open: bool = True
    filter_throughput: float = 1.0

    def __post_init__(self) -> None:
        if self.exposure_time_s < 0:
            raise ValueError(f"exposure_time_s must be >= 0, got {self.exposure_time_s}")
        if not 0.0 <= self.filter_throughput <= 1.0:
            raise ValueError(f"filter_throughput must be within [0, 1], got {self.filter_throughput}")


@dataclass(frozen=True)
class StarTruth:
    """Stars drawn on the frame: output-pixel positions, electrons received (after flat), magnitudes."""

    x: FloatArray
    y: FloatArray
    flux_e: FloatArray
    mag: FloatArray


@dataclass(frozen=True)
class MovingBody:
    """A body that moves among the stars: ICRS (ra, dec) degrees at each of :class:`Motion`'s
    sub-times, and its magnitude."""

    ra: FloatArray
    dec: FloatArray
    mag: float


@dataclass(frozen=True)
class Motion:
    """What moves during the exposure, sampled at the mid-times of equal parts of it.

    Attributes:
        pointing_ra: Where the axis points at each sub-time, degrees.
        pointing_dec: The same, declination.
        bodies: Moving bodies, sampled at the same sub-times.
    """

    pointing_ra: FloatArray
    pointing_dec: FloatArray
    bodies: tuple[MovingBody, ...] = ()

    def __post_init__(self) -> None:
        count = len(self.pointing_ra)
        if count == 0 or len(self.pointing_dec) != count or any(len(b.ra) != count for b in self.bodies):
            raise ValueError("a motion needs at least one sub-time and the same number for each path")


def _no_truth() -> StarTruth:
    return StarTruth(np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0))


@dataclass(frozen=True)
class RenderedFrame:
    """The frame (uint16 ADU, rows x cols) and what went into it."""

    data: npt.NDArray[np.uint16]
    stars: StarTruth
    geometry: FrameGeometry
    fwhm_px: float
    """Star FWHM in output (binned) pixels."""
    sky_e_per_pixel: float
    """Sky electrons per output pixel over the exposure, before the flat."""
    bodies: StarTruth = field(default_factory=_no_truth)
    """Moving bodies: mean output-pixel positions over the exposure, electrons, magnitudes."""


def frame_geometry(camera: CameraModel, optics: Optics, exposure: Exposure) -> FrameGeometry:
    """The projection geometry of a frame taken with this camera, telescope and readout."""
    return FrameGeometry(
        chip_width=camera.chip_width,
        chip_height=camera.chip_height,
        pixel_scale_arcsec=optics.pixel_scale_arcsec(camera.pixel_size_um),
        binning=exposure.binning,
        window=exposure.window,
    )


def render_frame(
    stars: npt.NDArray[np.void],
    *,
    pointing: Pointing,
    focus: float,
    camera: CameraModel,
    optics: Optics,
    conditions: Conditions,
    exposure: Exposure,
    rng: np.random.Generator,
    motion: Motion | None = None,
) -> RenderedFrame:
    """Render one frame of ``stars`` (structured array with ``ra``, ``dec``, ``mag`` fields).

    ``pointing`` is where the axis points at the start; ``motion`` (None: it stays there) moves it
    during the exposure and adds moving bodies.

    ``stars`` should cover the field (e.g. a catalog cone of the frame's half diagonal); stars off
    the frame are ignored. Randomness (noise, cosmic rays) comes from ``rng`` only: the same seed
    gives the same frame.
    """
    geometry = frame_geometry(camera, optics, exposure)
    window = geometry.full_window
    b = geometry.binning
    rows, cols = geometry.shape
    shape_unbinned = (rows * b, cols * b)
    t = exposure.exposure_time_s
    scale = geometry.pixel_scale_arcsec
    fwhm_px = (
        fwhm_arcsec(
            conditions.seeing_arcsec,
            focus,
            best_focus=optics.best_focus,
            optics_fwhm_arcsec=optics.optics_fwhm_arcsec,
            defocus_arcsec_per_unit=optics.defocus_arcsec_per_unit,
        )
        / scale
    )

    electrons = np.zeros(shape_unbinned, dtype=np.float32)
    truth, bodies = _no_truth(), _no_truth()
    sky_e = 0.0
    if conditions.roof_open and exposure.shutter_open and t > 0:
        electrons, truth, bodies, sky_e = _light(
            stars, pointing, geometry, fwhm_px, shape_unbinned, camera, optics, conditions, exposure, motion
        )
    if conditions.panel_e_per_s > 0 and exposure.shutter_open and t > 0:
        # An even panel: only the optics' vignetting shapes it (what a flat field records).
        flat = vignetting_flat(camera.chip_width, camera.chip_height, window, camera.vignetting)
        panel = np.float32(conditions.panel_e_per_s * exposure.filter_throughput * t)
        electrons += panel * flat[: shape_unbinned[0], : shape_unbinned[1]]
    electrons += np.float32(camera.dark_e_per_s * t)
    _add_hot_pixels(electrons, camera, window, t)
    window_fraction = (shape_unbinned[0] * shape_unbinned[1]) / (camera.chip_width * camera.chip_height)
    n_rays = int(rng.poisson(camera.cosmic_rays_per_s * t * window_fraction))
    add_cosmic_rays(electrons, count=n_rays, rng=rng)
    binned = bin_image(electrons, b)
    noisy = sample_noise(binned, read_noise_e=camera.read_noise_e, rng=rng)
    data = digitize(
        noisy, gain_e_per_adu=camera.gain_e_per_adu, bias_adu=camera.bias_adu, full_well_e=camera.full_well_e
    )
    return RenderedFrame(
        data=data,
        stars=truth,
        geometry=geometry,
        fwhm_px=fwhm_px / b,
        sky_e_per_pixel=sky_e * b * b,
        bodies=bodies,
    )


def _light(
    stars: npt.NDArray[np.void],
    pointing: Pointing,
    geometry: FrameGeometry,
    fwhm_px: float,
    shape_unbinned: tuple[int, int],
    camera: CameraModel,
    optics: Optics,
    conditions: Conditions,
    exposure: Exposure,
    motion: Motion | None,
) -> tuple[npt.NDArray[np.float32], StarTruth, StarTruth, float]:
    """Star, body and sky electrons (after the flat) over the window at unbinned resolution."""
    window = geometry.full_window
    t = exposure.exposure_time_s
    # Project on the unbinned full chip, then shift to the window's corner.
    chip = FrameGeometry(camera.chip_width, camera.chip_height, geometry.pixel_scale_arcsec)
    u, v = sky_to_pixel(stars["ra"], stars["dec"], pointing, chip)
    x, y = u - window.x, v - window.y
    margin = 4.0 * fwhm_px + 50.0
    near = np.isfinite(x) & (x > -margin) & (x < shape_unbinned[1] + margin)
    near &= (y > -margin) & (y < shape_unbinned[0] + margin)
    mag = np.asarray(stars["mag"][near], dtype=np.float64)

    def electrons_of(mags: FloatArray) -> FloatArray:
        return t * star_electrons_per_second(
            mags,
            zero_point_mag=optics.zero_point_mag,
            throughput=exposure.filter_throughput,
            airmass=conditions.airmass,
            extinction_mag_per_airmass=conditions.extinction_mag_per_airmass,
            transmission=conditions.transmission,
        )

    flux = electrons_of(mag)
    image = render_stars(shape_unbinned, x[near], y[near], flux, fwhm_px=fwhm_px, beta=optics.moffat_beta)
    body_x, body_y, body_flux, body_mag = (np.zeros(0),) * 4
    if motion is not None:
        # The field centre's path in pixels moves every star alike (the field is small).
        path = _pixels_along(pointing.ra_deg, pointing.dec_deg, motion, pointing.rotation_deg, chip)
        still = sky_to_pixel(np.array([pointing.ra_deg]), np.array([pointing.dec_deg]), pointing, chip)
        image = trail(image, path[0] - still[0][0], path[1] - still[1][0])
        body_mag = np.array([body.mag for body in motion.bodies], dtype=np.float64)
        body_flux = electrons_of(body_mag)
        xs_all, ys_all = [], []
        for body, total in zip(motion.bodies, body_flux, strict=True):
            bu, bv = _pixels_along(body.ra, body.dec, motion, pointing.rotation_deg, chip)
            share = np.full(len(bu), total / len(bu))
            image += render_stars(
                shape_unbinned, bu - window.x, bv - window.y, share, fwhm_px=fwhm_px, beta=optics.moffat_beta
            )
            xs_all.append(float(np.mean(bu)))
            ys_all.append(float(np.mean(bv)))
        body_x, body_y = geometry.unbinned_to_output(np.array(xs_all), np.array(ys_all))
    sky_mag = sky_brightness_mag(
        conditions.sun_altitude_deg,
        moon_altitude_deg=conditions.moon_altitude_deg,
        moon_illumination=conditions.moon_illumination,
        dark_sky_mag=conditions.dark_sky_mag,
    )
    sky_e = t * sky_electrons_per_pixel_per_second(
        sky_mag,
        zero_point_mag=optics.zero_point_mag,
        pixel_area_arcsec2=geometry.pixel_scale_arcsec**2,
        throughput=exposure.filter_throughput,
    )
    image += np.float32(sky_e)
    flat = vignetting_flat(camera.chip_width, camera.chip_height, window, camera.vignetting)
    flat = flat[: shape_unbinned[0], : shape_unbinned[1]]
    image *= flat
    on_frame = (x[near] >= -0.5) & (x[near] < shape_unbinned[1] - 0.5)
    on_frame &= (y[near] >= -0.5) & (y[near] < shape_unbinned[0] - 0.5)
    xs, ys = x[near][on_frame], y[near][on_frame]
    star_flat = flat[np.rint(ys).astype(np.int64), np.rint(xs).astype(np.int64)]
    out_x, out_y = geometry.unbinned_to_output(xs + window.x, ys + window.y)
    truth = StarTruth(x=out_x, y=out_y, flux_e=flux[on_frame] * star_flat, mag=mag[on_frame])
    bodies = StarTruth(x=np.asarray(body_x), y=np.asarray(body_y), flux_e=body_flux, mag=body_mag)
    return image, truth, bodies, sky_e


def _pixels_along(
    ra: float | FloatArray, dec: float | FloatArray, motion: Motion, rotation: float, chip: FrameGeometry
) -> tuple[FloatArray, FloatArray]:
    """Unbinned chip pixels of (``ra``, ``dec``) (one position, or one per sub-time) seen with the
    pointing of each of ``motion``'s sub-times.

    Projected exactly at up to :data:`_PATH_KNOTS` sub-times and interpolated between them: over
    one exposure the paths are smooth, and a satellite's has thousands of sub-times.
    """
    count = len(motion.pointing_ra)
    ras, decs = np.broadcast_to(ra, count), np.broadcast_to(dec, count)
    knots = np.unique(np.linspace(0, count - 1, min(count, _PATH_KNOTS)).round().astype(np.int64))
    u, v = np.empty(len(knots)), np.empty(len(knots))
    for i, k in enumerate(knots):
        here = Pointing(float(motion.pointing_ra[k]), float(motion.pointing_dec[k]), rotation)
        uk, vk = sky_to_pixel(ras[k : k + 1], decs[k : k + 1], here, chip)
        u[i], v[i] = uk[0], vk[0]
    every = np.arange(count)
    return np.interp(every, knots, u), np.interp(every, knots, v)


def _add_hot_pixels(
    electrons: npt.NDArray[np.float32], camera: CameraModel, window: Window, t: float
) -> None:
    """Add the camera's hot-pixel dark charge for ``t`` seconds to the window image in place."""
    if camera.hot_pixel_fraction <= 0 or t <= 0:
        return
    rows, cols, rates = hot_pixels(
        camera.chip_width, camera.chip_height, fraction=camera.hot_pixel_fraction, seed=camera.pattern_seed
    )
    r, c = rows - window.y, cols - window.x
    inside = (r >= 0) & (r < electrons.shape[0]) & (c >= 0) & (c < electrons.shape[1])
    np.add.at(electrons, (r[inside], c[inside]), (rates[inside] * t).astype(np.float32))


def field_radius_deg(geometry: FrameGeometry) -> float:
    """Half the diagonal of the full chip, in degrees: the catalog cone that covers any window."""
    half_diag_px = 0.5 * math.hypot(geometry.chip_width, geometry.chip_height)
    return half_diag_px * geometry.pixel_scale_arcsec / 3600.0
