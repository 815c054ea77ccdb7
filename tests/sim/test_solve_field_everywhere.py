"""Simulated frames solve with astrometry.net anywhere on the sky, not only in star-rich fields.

The real stars of the simulated sky include the Tycho-2 stars of the solver's own index, so a
frame at a random position, far from the Milky Way too, holds the quads ``solve-field`` looks for.
Each frame is solved blind in position (only the pixel scale is known), two at a time.
"""

from __future__ import annotations

import asyncio

import numpy as np
import pytest
from astropy.coordinates import SkyCoord  # type: ignore[import-untyped]
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

from .solving import offset_arcsec, solve_field_executable

pytestmark = pytest.mark.solver

POSITIONS = 20
PARALLEL_SOLVES = 2


def random_pointings(seed: int, count: int) -> list[Pointing]:
    """Positions uniform on the sphere, with random camera rotations."""
    rng = np.random.default_rng(seed)
    ra = rng.uniform(0.0, 360.0, count)
    dec = np.degrees(np.arcsin(rng.uniform(-1.0, 1.0, count)))
    rotation = rng.uniform(0.0, 360.0, count)
    return [Pointing(float(a), float(d), float(r)) for a, d, r in zip(ra, dec, rotation, strict=True)]


@pytest.mark.timeout(900)
async def test_frames_at_20_random_sky_positions_solve_within_5_arcsec() -> None:
    executable = solve_field_executable()
    pointings = random_pointings(2026, POSITIONS)
    latitudes = SkyCoord([p.ra_deg for p in pointings], [p.dec_deg for p in pointings], unit="deg").galactic.b
    assert np.count_nonzero(np.abs(latitudes.deg) > 20.0) >= POSITIONS // 2
    catalog = StarCatalog(depth=15.0, seed=5)
    camera, optics, exposure = CameraModel(), Optics(), Exposure(30.0)
    geometry = frame_geometry(camera, optics, exposure)
    solver = SolveField(executable=executable, cpu_limit_s=60.0, timeout_s=240.0)
    slots = asyncio.Semaphore(PARALLEL_SOLVES)

    async def solve(index: int, pointing: Pointing) -> float:
        async with slots:  # one frame in memory per solve slot
            stars = catalog.query(pointing.ra_deg, pointing.dec_deg, field_radius_deg(geometry), epoch=2026.0)
            frame = render_frame(
                stars,
                pointing=pointing,
                focus=0.0,
                camera=camera,
                optics=optics,
                conditions=Conditions(seeing_arcsec=2.0),
                exposure=exposure,
                rng=np.random.default_rng(index),
            )
            header = await solver.solve_image(
                frame.data, hints=SolveHints(pixel_scale_arcsec=geometry.pixel_scale_arcsec)
            )
        return offset_arcsec(WCS(header), frame.data.shape, pointing.ra_deg, pointing.dec_deg)

    offsets = await asyncio.gather(*(solve(i, p) for i, p in enumerate(pointings)))
    far = {
        f"{p.ra_deg:.1f},{p.dec_deg:.1f}": round(o, 2)
        for p, o in zip(pointings, offsets, strict=True)
        if o >= 5.0
    }
    assert not far, f"solved more than 5 arcsec from the pointing: {far}"
