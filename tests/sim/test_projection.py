"""Gnomonic projection: round trips, orientation, binning/window, and the WCS header."""

from __future__ import annotations

import numpy as np
import pytest
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.sim.projection import FrameGeometry, Pointing, Window, pixel_to_sky, sky_to_pixel, wcs_header

GEOMETRIES = [
    FrameGeometry(2048, 2048, 1.2),
    FrameGeometry(3000, 2000, 0.6, binning=3, window=Window(100, 250, 1500, 900)),
    FrameGeometry(512, 256, 4.0, binning=2),
]
POINTINGS = [Pointing(83.8, -5.4, 0.0), Pointing(359.9, 89.7, 37.0), Pointing(0.05, -60.0, -120.0)]


@pytest.mark.parametrize("geometry", GEOMETRIES)
@pytest.mark.parametrize("pointing", POINTINGS)
def test_round_trip_is_exact(geometry: FrameGeometry, pointing: Pointing) -> None:
    rng = np.random.default_rng(1)
    rows, cols = geometry.shape
    x = rng.uniform(-0.5, cols - 0.5, 500)
    y = rng.uniform(-0.5, rows - 0.5, 500)
    ra, dec = pixel_to_sky(x, y, pointing, geometry)
    x2, y2 = sky_to_pixel(ra, dec, pointing, geometry)
    assert np.max(np.abs(x2 - x)) < 1e-6
    assert np.max(np.abs(y2 - y)) < 1e-6


@pytest.mark.parametrize("geometry", GEOMETRIES)
@pytest.mark.parametrize("pointing", POINTINGS)
def test_wcs_header_agrees_with_projection(geometry: FrameGeometry, pointing: Pointing) -> None:
    rng = np.random.default_rng(2)
    rows, cols = geometry.shape
    x = rng.uniform(0, cols - 1, 200)
    y = rng.uniform(0, rows - 1, 200)
    ra, dec = pixel_to_sky(x, y, pointing, geometry)
    header = wcs_header(pointing, geometry)
    assert (header["NAXIS1"], header["NAXIS2"]) == (cols, rows)
    xw, yw = WCS(header).all_world2pix(ra, dec, 0)
    assert np.max(np.abs(xw - x)) < 1e-6
    assert np.max(np.abs(yw - y)) < 1e-6


def test_pointing_falls_on_chip_centre() -> None:
    geometry = FrameGeometry(2048, 1024, 1.0)
    x, y = sky_to_pixel(10.0, 20.0, Pointing(10.0, 20.0), geometry)
    assert (float(x), float(y)) == pytest.approx((1023.5, 511.5), abs=1e-9)


def test_north_is_up_and_east_is_left_without_rotation() -> None:
    geometry = FrameGeometry(1000, 1000, 1.0)
    pointing = Pointing(10.0, 20.0)
    x, y = sky_to_pixel([10.0, 10.0 + 0.01 / np.cos(np.radians(20.0))], [20.01, 20.0], pointing, geometry)
    assert x[0] == pytest.approx(499.5, abs=1e-3) and y[0] == pytest.approx(499.5 + 36.0, abs=1e-2)
    assert x[1] == pytest.approx(499.5 - 36.0, abs=1e-2) and y[1] == pytest.approx(499.5, abs=1e-2)


def test_rotation_is_the_position_angle_of_plus_y() -> None:
    geometry = FrameGeometry(1000, 1000, 1.0)
    x, y = sky_to_pixel(10.0 + 0.01 / np.cos(np.radians(20.0)), 20.0, Pointing(10.0, 20.0, 90.0), geometry)
    assert float(x) == pytest.approx(499.5, abs=1e-2)
    assert float(y) == pytest.approx(499.5 + 36.0, abs=1e-2)


def test_binning_and_window_map_to_the_unbinned_chip() -> None:
    full = FrameGeometry(2000, 2000, 1.0)
    part = FrameGeometry(2000, 2000, 1.0, binning=2, window=Window(300, 500, 800, 600))
    pointing = Pointing(150.0, 2.0, 15.0)
    ra, dec = pixel_to_sky([400.0, 1000.0], [700.0, 900.0], pointing, full)
    x, y = sky_to_pixel(ra, dec, pointing, part)
    np.testing.assert_allclose(x, (np.array([400.0, 1000.0]) - 300 - 0.5) / 2, atol=1e-9)
    np.testing.assert_allclose(y, (np.array([700.0, 900.0]) - 500 - 0.5) / 2, atol=1e-9)
    assert part.shape == (300, 400)


def test_points_behind_the_tangent_plane_are_nan() -> None:
    x, y = sky_to_pixel(190.0, -20.0, Pointing(10.0, 20.0), FrameGeometry(100, 100, 1.0))
    assert np.isnan(x) and np.isnan(y)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"binning": 0}, "binning must be >= 1"),
        ({"pixel_scale_arcsec": 0.0}, "pixel_scale_arcsec must be positive"),
        ({"window": Window(900, 0, 200, 100)}, "exceeds the 1000x1000 chip"),
        ({"window": Window(0, 0, 1, 1), "binning": 2}, "smaller than binning"),
    ],
)
def test_invalid_geometry_is_refused(kwargs: dict[str, object], message: str) -> None:
    args: dict[str, object] = {"chip_width": 1000, "chip_height": 1000, "pixel_scale_arcsec": 1.0}
    args.update(kwargs)
    with pytest.raises(ValueError, match=message):
        FrameGeometry(**args)  # type: ignore[arg-type]


def test_invalid_declination_is_refused() -> None:
    with pytest.raises(ValueError, match="dec_deg must be within"):
        Pointing(0.0, 91.0)
