"""Rendered frames: positions, PSF width vs focus, photometry, sky, roof, saturation, determinism."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import numpy.typing as npt
import pytest
import sep  # type: ignore[import-not-found]

from nightcrew.sim.catalog import STAR_DTYPE
from nightcrew.sim.projection import Pointing, Window, pixel_to_sky
from nightcrew.sim.psf import fwhm_arcsec
from nightcrew.sim.render import (
    CameraModel,
    Conditions,
    Exposure,
    Optics,
    RenderedFrame,
    frame_geometry,
    render_frame,
)

POINTING = Pointing(150.0, 20.0, 25.0)
CAMERA = CameraModel(chip_width=512, chip_height=512, cosmic_rays_per_s=0.0, hot_pixel_fraction=0.0)
OPTICS = Optics(focal_length_mm=1600.0, optics_fwhm_arcsec=0.0, best_focus=0.0, defocus_arcsec_per_unit=30.0)
CONDITIONS = Conditions(seeing_arcsec=3.0)
EXPOSURE = Exposure(10.0)


def grid_stars(mags: list[float], *, exposure: Exposure = EXPOSURE, seed: int = 0) -> npt.NDArray[np.void]:
    """Stars on a jittered grid well inside the frame, with the given magnitudes."""
    geometry = frame_geometry(CAMERA, OPTICS, exposure)
    rows, cols = geometry.shape
    n = len(mags)
    side = int(np.ceil(np.sqrt(n)))
    rng = np.random.default_rng(seed)
    gx, gy = np.meshgrid(np.linspace(0.15, 0.85, side), np.linspace(0.15, 0.85, side))
    x = gx.ravel()[:n] * cols + rng.uniform(-0.5, 0.5, n)
    y = gy.ravel()[:n] * rows + rng.uniform(-0.5, 0.5, n)
    ra, dec = pixel_to_sky(x, y, POINTING, geometry)
    stars = np.zeros(n, STAR_DTYPE)
    stars["ra"], stars["dec"], stars["mag"] = ra, dec, mags
    return stars


def render(stars: npt.NDArray[np.void], seed: int = 1, **changes: object) -> RenderedFrame:
    parts: dict[str, object] = {
        "pointing": POINTING,
        "focus": 0.0,
        "camera": CAMERA,
        "optics": OPTICS,
        "conditions": CONDITIONS,
        "exposure": EXPOSURE,
    }
    parts.update(changes)
    return render_frame(stars, rng=np.random.default_rng(seed), **parts)  # type: ignore[arg-type]


def background_subtracted(frame: RenderedFrame) -> tuple[npt.NDArray[np.float64], float]:
    data = frame.data.astype(np.float64)
    background = sep.Background(data)
    return data - background.back(), float(background.globalrms)


def test_bright_star_centroids_match_truth() -> None:
    frame = render(grid_stars([11.0] * 25))
    data, _ = background_subtracted(frame)
    x, y = frame.stars.x, frame.stars.y
    sigma = frame.fwhm_px / 2.3548
    wx, wy, flags = sep.winpos(data, x + 0.3, y - 0.3, np.full(len(x), sigma))
    assert np.all(flags == 0)
    assert np.max(np.hypot(wx - x, wy - y)) < 0.05


def test_centroids_match_truth_with_binning_and_window() -> None:
    exposure = Exposure(10.0, binning=2, window=Window(64, 32, 400, 440))
    seeing = replace(CONDITIONS, seeing_arcsec=6.0)  # keep ~2.6 binned pixels FWHM: well sampled
    frame = render(grid_stars([10.5] * 16, exposure=exposure), exposure=exposure, conditions=seeing)
    assert frame.data.shape == (220, 200)
    data, _ = background_subtracted(frame)
    x, y = frame.stars.x, frame.stars.y
    assert len(x) == 16
    wx, wy, _ = sep.winpos(data, x, y, np.full(len(x), frame.fwhm_px / 2.3548))
    assert np.max(np.hypot(wx - x, wy - y)) < 0.05


def measured_fwhm(frame: RenderedFrame) -> float:
    """Median FWHM from the half-light radius: for a Moffat r_half = alpha sqrt(2^(1/(beta-1)) - 1).

    sep integrates pixels as uniform squares, which widens a point-sampled profile by the pixel
    box: FWHM^2 grows by about 8 ln2 / 12 px^2 (the box's variance, as for a Gaussian).
    """
    data, _ = background_subtracted(frame)
    beta = OPTICS.moffat_beta
    r_half, _ = sep.flux_radius(
        data, frame.stars.x, frame.stars.y, np.full(len(frame.stars.x), 8.0 * frame.fwhm_px), 0.5, subpix=10
    )
    alpha = r_half / np.sqrt(2.0 ** (1.0 / (beta - 1.0)) - 1.0)
    fwhm_with_box = np.median(2.0 * alpha * np.sqrt(2.0 ** (1.0 / beta) - 1.0))
    return float(np.sqrt(fwhm_with_box**2 - 8.0 * np.log(2.0) / 12.0))


@pytest.mark.parametrize("focus", [-0.3, -0.15, -0.05, 0.0, 0.1, 0.25])
def test_measured_fwhm_follows_the_focus_hyperbola(focus: float) -> None:
    stars = grid_stars([11.0] * 9)
    frame = render(stars, focus=focus)
    scale = frame.geometry.pixel_scale_arcsec
    model = (
        fwhm_arcsec(3.0, focus, best_focus=0.0, optics_fwhm_arcsec=0.0, defocus_arcsec_per_unit=30.0) / scale
    )
    assert frame.fwhm_px == pytest.approx(model)
    assert measured_fwhm(frame) == pytest.approx(model, rel=0.03)


def test_relative_brightness_matches_magnitudes() -> None:
    mags = list(np.linspace(11.0, 14.0, 16))
    camera = replace(CAMERA, vignetting=0.0)
    frame = render(grid_stars(mags), camera=camera)
    data, _ = background_subtracted(frame)
    radius = 5.0 * frame.fwhm_px
    flux, _, _ = sep.sum_circle(data, frame.stars.x, frame.stars.y, radius, subpix=5)
    assert frame.data.max() < 60000  # unsaturated
    measured_ratio = flux / flux[0]
    expected_ratio = 10.0 ** (-0.4 * (np.asarray(mags) - mags[0]))
    np.testing.assert_allclose(measured_ratio, expected_ratio, rtol=0.1)
    # And absolute: electrons = ADU * gain, matching the truth flux within a few %.
    np.testing.assert_allclose(flux[:6] * camera.gain_e_per_adu, frame.stars.flux_e[:6], rtol=0.05)


@pytest.mark.parametrize("vignetting", [0.0, 0.3])
def test_truth_flux_includes_airmass_clouds_filter_and_flat(vignetting: float) -> None:
    stars = grid_stars([12.0])
    clear = render(stars, camera=replace(CAMERA, vignetting=vignetting))
    murky = render(
        stars,
        camera=replace(CAMERA, vignetting=vignetting),
        conditions=replace(CONDITIONS, airmass=2.0, transmission=0.5),
        exposure=replace(EXPOSURE, filter_throughput=0.8),
    )
    ratio = murky.stars.flux_e[0] / clear.stars.flux_e[0]
    assert ratio == pytest.approx(0.5 * 0.8 * 10 ** (-0.4 * 0.2), rel=1e-6)


def sky_level_e(frame: RenderedFrame) -> float:
    """Sky electrons per pixel from the median of the frame's centre, where the flat is ~1."""
    rows, cols = frame.data.shape
    centre = frame.data[rows // 2 - 40 : rows // 2 + 40, cols // 2 - 40 : cols // 2 + 40]
    return float((np.median(centre) - CAMERA.bias_adu) * CAMERA.gain_e_per_adu)


def test_sky_follows_sun_altitude() -> None:
    stars = grid_stars([13.0])
    levels = []
    for sun in [-4.0, -8.0, -12.0, -16.0, -25.0]:
        frame = render(stars, conditions=replace(CONDITIONS, sun_altitude_deg=sun), exposure=Exposure(1.0))
        levels.append(sky_level_e(frame))
        assert sky_level_e(frame) == pytest.approx(frame.sky_e_per_pixel, rel=0.03, abs=3.0)
    assert all(a > 2.0 * b for a, b in itertools.pairwise(levels[:4]))
    assert levels[3] > levels[4]


def test_moon_brightens_the_sky() -> None:
    stars = grid_stars([13.0])
    dark = render(stars)
    moon = render(stars, conditions=replace(CONDITIONS, moon_altitude_deg=50.0, moon_illumination=0.9))
    assert sky_level_e(moon) > 2.0 * sky_level_e(dark)


def test_closed_roof_shows_no_stars_and_no_sky() -> None:
    stars = grid_stars([8.0] * 4)
    frame = render(stars, conditions=replace(CONDITIONS, roof_open=False), exposure=Exposure(60.0))
    assert len(frame.stars.x) == 0 and frame.sky_e_per_pixel == 0.0
    expected_adu = CAMERA.bias_adu + CAMERA.dark_e_per_s * 60.0 / CAMERA.gain_e_per_adu
    assert np.median(frame.data) == pytest.approx(expected_adu, abs=1.0)
    noise_adu = CAMERA.read_noise_e / CAMERA.gain_e_per_adu
    assert frame.data.max() < expected_adu + 7.0 * noise_adu
    open_roof = render(stars, exposure=Exposure(60.0))
    assert open_roof.data.max() == 65535


def test_bias_frame_is_bias_plus_read_noise() -> None:
    frame = render(grid_stars([8.0]), exposure=Exposure(0.0))
    data = frame.data.astype(np.float64)
    assert np.mean(data) == pytest.approx(CAMERA.bias_adu, abs=0.2)
    assert np.std(data) == pytest.approx(CAMERA.read_noise_e / CAMERA.gain_e_per_adu, rel=0.05)


def test_saturation_clips_at_65535_without_wrapping() -> None:
    frame = render(grid_stars([4.0]), camera=replace(CAMERA, full_well_e=None, gain_e_per_adu=4.0))
    assert frame.data.dtype == np.uint16
    assert frame.data.max() == 65535
    x, y = np.rint(frame.stars.x[0]).astype(int), np.rint(frame.stars.y[0]).astype(int)
    assert np.all(frame.data[y - 1 : y + 2, x - 1 : x + 2] == 65535)


def test_same_seed_same_frame_other_seed_other_noise() -> None:
    stars = grid_stars([12.0] * 4)
    camera = replace(CAMERA, cosmic_rays_per_s=1.0, hot_pixel_fraction=1e-3)
    a = render(stars, seed=5, camera=camera)
    b = render(stars, seed=5, camera=camera)
    c = render(stars, seed=6, camera=camera)
    np.testing.assert_array_equal(a.data, b.data)
    assert not np.array_equal(a.data, c.data)


def test_hot_pixels_are_fixed_and_grow_with_exposure_time() -> None:
    camera = replace(CAMERA, hot_pixel_fraction=1e-3, dark_e_per_s=0.0)
    closed = replace(CONDITIONS, roof_open=False)
    short = render(grid_stars([12.0]), seed=1, camera=camera, conditions=closed, exposure=Exposure(10.0))
    long = render(grid_stars([12.0]), seed=2, camera=camera, conditions=closed, exposure=Exposure(100.0))
    threshold = CAMERA.bias_adu + 50
    hot_short = set(zip(*np.nonzero(short.data > threshold), strict=True))
    hot_long = set(zip(*np.nonzero(long.data > threshold), strict=True))
    assert len(hot_short) > 20 and hot_short <= hot_long
    assert len(hot_long) > len(hot_short)


def test_cosmic_rays_scale_with_exposure_time() -> None:
    camera = replace(CAMERA, cosmic_rays_per_s=2.0)
    closed = replace(CONDITIONS, roof_open=False)
    counts = []
    for t in (10.0, 100.0):
        frame = render(grid_stars([12.0]), camera=camera, conditions=closed, exposure=Exposure(t))
        counts.append(np.count_nonzero(frame.data > CAMERA.bias_adu + 100))
    assert counts[0] > 5 and counts[1] > 5 * counts[0]
