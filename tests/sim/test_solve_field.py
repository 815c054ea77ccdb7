"""astrometry.net's solve-field, unmodified, solves a rendered frame near the true pointing.

Needs Debian ``astrometry.net`` + ``astrometry-data-tycho2``. Skipped when solve-field is missing,
except under CI (``CI=true``), where a missing solver is a failure.
"""

from __future__ import annotations

import os
import shutil

import numpy as np
import pytest
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.images.astrometry import SolveField, SolveHints
from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.projection import Pointing
from nightcrew.sim.render import (
    CameraModel,
    Conditions,
    Exposure,
    Optics,
    field_radius_deg,
    frame_geometry,
    render_frame,
)

pytestmark = pytest.mark.solver


def solve_field_executable() -> str:
    path = shutil.which("solve-field")
    if path is None:
        if os.environ.get("CI") == "true":
            pytest.fail("solve-field is missing on CI: install astrometry.net and astrometry-data-tycho2")
        pytest.skip("solve-field is not installed")
    return path


# Barnard's star field, near the Milky Way (test_solve_field_everywhere covers random fields).
@pytest.mark.parametrize("pointing", [Pointing(269.45, 4.7, 0.0), Pointing(269.0, 5.0, 30.0)])
async def test_solve_field_finds_the_true_pointing(pointing: Pointing) -> None:
    executable = solve_field_executable()
    camera, optics, exposure = CameraModel(), Optics(), Exposure(30.0)
    geometry = frame_geometry(camera, optics, exposure)
    stars = StarCatalog(depth=15.0).query(
        pointing.ra_deg, pointing.dec_deg, field_radius_deg(geometry), epoch=2026.0
    )
    frame = render_frame(
        stars,
        pointing=pointing,
        focus=0.0,
        camera=camera,
        optics=optics,
        conditions=Conditions(seeing_arcsec=2.0),
        exposure=exposure,
        rng=np.random.default_rng(11),
    )
    # A blind solve (no position hint) with a pixel-scale hint, through the shared solve-field helper.
    solver = SolveField(executable=executable, cpu_limit_s=60.0, timeout_s=240.0)
    header = await solver.solve_image(
        frame.data, hints=SolveHints(pixel_scale_arcsec=geometry.pixel_scale_arcsec)
    )
    wcs = WCS(header)
    rows, cols = frame.data.shape
    ra, dec = wcs.all_pix2world([(cols - 1) / 2.0], [(rows - 1) / 2.0], 0)
    cos_dec = np.cos(np.radians(pointing.dec_deg))
    d_ra = ((float(ra[0]) - pointing.ra_deg + 180.0) % 360.0 - 180.0) * cos_dec
    offset_arcsec = 3600.0 * float(np.hypot(d_ra, float(dec[0]) - pointing.dec_deg))
    assert offset_arcsec < 5.0
