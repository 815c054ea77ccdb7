"""Plate solving of rendered frames, compared with the renderer's true WCS.

The frames come from :func:`nightcrew.sim.render.render_frame` on the simulation's own star
catalog; the header's RA/DEC is off by several arcminutes (a telescope's pointing error). Accuracy
is the largest sky distance, over a grid of pixels covering the frame, between the solution and
the true WCS (:func:`nightcrew.sim.projection.wcs_header`).
"""

from __future__ import annotations

import math
import os
import re
import shutil
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from astropy.wcs import WCS  # type: ignore[import-untyped]

import nightcrew.images.astrometry
from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.images import Image, NoStarsError
from nightcrew.images.astrometry import (
    AstrometryResult,
    CatalogAstrometry,
    CatalogMatcher,
    NoSolutionError,
    SolveField,
    SolveFieldAstrometry,
    SolverUnavailableError,
    TanWcs,
)
from nightcrew.images.processors.detection import detect_sources_sep
from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.projection import Pointing, wcs_header
from nightcrew.sim.render import (
    CameraModel,
    Conditions,
    Exposure,
    Optics,
    field_radius_deg,
    frame_geometry,
    render_frame,
)
from nightcrew.testing.solver import simulated_sky_indexes

TRUE_POINTING = Pointing(100.0, 30.0, 10.0)
#: The telescope believes it points 6' east and 4' south of where it does.
HEADER_RA = TRUE_POINTING.ra_deg + 6.0 / 60.0 / math.cos(math.radians(TRUE_POINTING.dec_deg))
HEADER_DEC = TRUE_POINTING.dec_deg - 4.0 / 60.0
CAMERA, OPTICS, EXPOSURE = CameraModel(), Optics(), Exposure(30.0)
GEOMETRY = frame_geometry(CAMERA, OPTICS, EXPOSURE)
SCALE = GEOMETRY.pixel_scale_arcsec


def solve_field_available() -> None:
    """Skip without solve-field on a developer machine; fail on CI, where it must be installed."""
    if shutil.which("solve-field") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("solve-field is missing on CI: install astrometry.net and astrometry-data-tycho2")
        pytest.skip("solve-field is not installed")


def max_error_arcsec(wcs: WCS, pointing: Pointing = TRUE_POINTING) -> float:
    """Largest distance (arcsec) between ``wcs`` and the true WCS over a 9x9 grid of the frame."""
    true = WCS(wcs_header(pointing, GEOMETRY))
    rows, cols = GEOMETRY.shape
    gx, gy = np.meshgrid(np.linspace(0, cols - 1, 9), np.linspace(0, rows - 1, 9))
    ra_t, dec_t = true.all_pix2world(gx.ravel(), gy.ravel(), 0)
    ra_s, dec_s = wcs.all_pix2world(gx.ravel(), gy.ravel(), 0)
    d_ra = (ra_s - ra_t + 180.0) % 360.0 - 180.0
    return float(np.max(3600.0 * np.hypot(d_ra * np.cos(np.radians(dec_t)), dec_s - dec_t)))


@pytest.fixture(scope="module")
def sky_index() -> str:
    """The index files of the rendered sky (seed 0, G = 16) around the frame: the matcher's stars."""
    return str(
        simulated_sky_indexes([(HEADER_RA, HEADER_DEC)], width_arcmin=GEOMETRY.shape[1] * SCALE / 60.0)
    )


@pytest.fixture(scope="module")
def detected() -> Image:
    """A 2k x 2k rendered frame with the telescope's header and SEP detections."""
    stars = StarCatalog().query(
        TRUE_POINTING.ra_deg, TRUE_POINTING.dec_deg, field_radius_deg(GEOMETRY), epoch=2026.0
    )
    frame = render_frame(
        stars,
        pointing=TRUE_POINTING,
        focus=0.0,
        camera=CAMERA,
        optics=OPTICS,
        conditions=Conditions(seeing_arcsec=2.0),
        exposure=EXPOSURE,
        rng=np.random.default_rng(3),
    )
    header = {"RA": HEADER_RA, "DEC": HEADER_DEC, "DATE-OBS": "2026-01-01T00:00:00", "EXPTIME": 30.0}
    catalog = detect_sources_sep(np.array(frame.data, dtype=np.float64))
    return Image(frame.data, header=header, catalog=catalog)


async def test_catalog_matcher_is_within_one_arcsec_despite_a_pointing_error(
    detected: Image, sky_index: str
) -> None:
    solved = await CatalogAstrometry(index_dir=sky_index, pixel_scale_arcsec=SCALE)(detected)
    assert solved.wcs is not None
    assert max_error_arcsec(solved.wcs) < 1.0
    result = solved.metadata["astrometry"]
    assert isinstance(result, AstrometryResult) and result.solver == "catalog"
    assert result.matched is not None and result.matched >= 50
    assert solved.header["AST-SOLV"] == "catalog"
    assert solved.catalog is not None and {"ra", "dec"} <= set(solved.catalog.colnames)
    assert "CTYPE1" not in detected.header  # the input image is left alone


async def test_catalog_matcher_reads_the_scale_from_the_header_and_binning(
    detected: Image, sky_index: str
) -> None:
    # PIXSCALE is the binned scale; XBINNING only scales a configured (unbinned) one.
    header = detected.header.copy()
    header["PIXSCALE"] = SCALE * 1.01  # a scale known to 1 %
    solved = await CatalogAstrometry(index_dir=sky_index)(detected.replace(header=header))
    assert solved.wcs is not None and max_error_arcsec(solved.wcs) < 1.0


async def test_catalog_matcher_reports_no_solution_far_from_the_field(
    detected: Image, sky_index: str
) -> None:
    header = detected.header.copy()
    header["DEC"] = HEADER_DEC + 3.0  # beyond the index files too
    with pytest.raises(NoSolutionError, match="covers RA"):
        await CatalogAstrometry(index_dir=sky_index, pixel_scale_arcsec=SCALE)(
            detected.replace(header=header)
        )


async def test_astrometry_needs_detections_first(detected: Image, sky_index: str) -> None:
    with pytest.raises(NoStarsError, match="run a detection first"):
        await CatalogAstrometry(index_dir=sky_index, pixel_scale_arcsec=SCALE)(detected.replace(catalog=None))


def test_bad_matcher_configuration_names_the_key() -> None:
    config = {
        "class": "nightcrew.images.astrometry.CatalogAstrometry",
        "matcher": {"class": "nightcrew.images.astrometry.CatalogMatcher", "search_radius_arcmin": 0.0},
    }
    with pytest.raises(ConfigError, match="search_radius_arcmin must be positive") as info:
        build_object(config)
    assert info.value.key == "matcher"


@pytest.mark.parametrize(
    ("processor", "key", "solver"),
    [
        (
            "CatalogAstrometry",
            "search_radius_arcmin",
            "matcher: {class: nightcrew.images.astrometry.CatalogMatcher",
        ),
        ("SolveFieldAstrometry", "timeout_s", "solver: {class: nightcrew.images.astrometry.SolveField"),
        ("RemoteAstrometry", "url", "solver: {class: nightcrew.images.astrometry.RemoteSolver"),
    ],
)
def test_a_solver_option_on_the_processor_says_where_it_goes_now(
    processor: str, key: str, solver: str
) -> None:
    config = {"class": f"nightcrew.images.astrometry.{processor}", key: "http://127.0.0.1:1"}
    with pytest.raises(ConfigError, match=re.escape(solver)) as info:
        build_object(config)
    assert info.value.key == key
    with pytest.raises(ConfigError, match=re.escape(solver)):  # built in code: the same message
        getattr(nightcrew.images.astrometry, processor)(**{key: 1.0})


def test_matcher_solves_a_mirrored_camera() -> None:
    """Pure arrays: true star positions of a flipped camera (x mirrored), with centroid noise."""
    pointing = Pointing(200.0, -20.0, 45.0)
    stars = StarCatalog().query(pointing.ra_deg, pointing.dec_deg, field_radius_deg(GEOMETRY))
    true = TanWcs(
        crval=(pointing.ra_deg, pointing.dec_deg),
        crpix=((GEOMETRY.shape[1] - 1) / 2.0, (GEOMETRY.shape[0] - 1) / 2.0),
        cd=_mirrored_cd(pointing),
    )
    x, y = true.sky_to_pixel(stars["ra"], stars["dec"])
    rng = np.random.default_rng(5)
    on = (x > 0) & (x < 2047) & (y > 0) & (y < 2047) & (stars["mag"] < 15.0)
    flux = 10 ** (-0.4 * stars["mag"][on])
    match = CatalogMatcher().solve(
        x[on] + rng.normal(0, 0.1, on.sum()),
        y[on] + rng.normal(0, 0.1, on.sum()),
        flux,
        shape=GEOMETRY.shape,
        catalog_ra=stars["ra"],
        catalog_dec=stars["dec"],
        catalog_mag=stars["mag"],
        ra_deg=pointing.ra_deg + 0.1,
        dec_deg=pointing.dec_deg + 0.05,
        pixel_scale_arcsec=SCALE,
    )
    ra_t, dec_t = true.pixel_to_sky([0.0, 2047.0, 1000.0], [0.0, 2047.0, 300.0])
    ra_s, dec_s = match.wcs.pixel_to_sky([0.0, 2047.0, 1000.0], [0.0, 2047.0, 300.0])
    error = 3600 * np.hypot((ra_s - ra_t) * math.cos(math.radians(pointing.dec_deg)), dec_s - dec_t)
    assert float(error.max()) < 0.5


def _mirrored_cd(pointing: Pointing) -> tuple[tuple[float, float], tuple[float, float]]:
    c, s = math.cos(math.radians(pointing.rotation_deg)), math.sin(math.radians(pointing.rotation_deg))
    k = SCALE / 3600.0
    cd: npt.NDArray[np.float64] = k * np.array([[c, s], [-s, c]])  # +x towards east: a mirror image
    return (float(cd[0, 0]), float(cd[0, 1])), (float(cd[1, 0]), float(cd[1, 1]))


@pytest.mark.solver
async def test_solve_field_on_detected_stars_is_within_five_arcsec(detected: Image) -> None:
    solve_field_available()
    solved = await SolveFieldAstrometry(
        pixel_scale_arcsec=SCALE, radius_deg=0.5, solver=SolveField(timeout_s=60.0)
    )(detected)
    assert solved.wcs is not None
    assert max_error_arcsec(solved.wcs) < 5.0
    assert solved.metadata["astrometry"].solver == "astrometry.net"


async def test_missing_solve_field_is_one_clear_error(detected: Image) -> None:
    solver = SolveFieldAstrometry(
        pixel_scale_arcsec=SCALE, solver=SolveField(executable="no-such-solve-field")
    )
    with pytest.raises(SolverUnavailableError, match=r"no-such-solve-field not found: install"):
        await solver(detected)


@pytest.mark.parametrize("key", ["catalog_seed", "catalog_depth"])
def test_the_old_simulated_catalog_keys_say_what_replaced_them(key: str) -> None:
    config = {"class": "nightcrew.images.astrometry.CatalogAstrometry", key: 42}
    with pytest.raises(
        ConfigError, match="is gone: the matcher's stars are those of the index files in index_dir"
    ):
        build_object(config)
    old: dict[str, Any] = {key: 42}
    with pytest.raises(ConfigError, match="index_dir"):  # built in code: the same message
        CatalogAstrometry(**old)
