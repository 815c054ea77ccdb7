"""Frames of a fast asteroid in the simulated observatory (bench/moving.py's table 4).

Five 300-s frames, ten minutes apart, of an asteroid passing 0.01 au from the Earth at 60"/min,
taken by the simulated camera (2048 px at 1.16"/px: on a 1024-px chip the catalog matcher often
finds too few of the stars' 260-px trails to solve) while the simulated mount follows it (its own
drift and periodic error off; within an exposure the simulator moves the axis with the body). Each
frame is plate-solved by the catalog matcher on its trailed stars and the body measured by
MeasureMovingBody, as the Pipeline does. Measured on the frames:

- drift: the body's trail, sqrt(12 (l1 - l2)) from the eigenvalues of its image's second moments
  (a trail of length L adds L^2/12 to the variance along it) on the body ("body") and on still
  stars of the sidereal frame ("star": what pixel sampling and noise give), and the body's drift
  beyond that, sqrt(body^2 - star^2); target <= 1 px;
- FWHM: the body's (Moffat fit) over the stars' on a 10-s sidereal frame of the same field just
  before; target within 10 %;
- position: the measured (ra, dec) against the ephemeris at mid-exposure; target <= 0.5" RMS.
"""

from __future__ import annotations

import math
from datetime import UTC, datetime, timedelta
from typing import Any

import numpy as np

from nightcrew.astro.ephemeris import ephemeris
from nightcrew.images.astrometry import CatalogAstrometry
from nightcrew.images.image import Image
from nightcrew.images.processors._shared import estimate_background, float_data
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.images.processors.misc import measure_fwhm, moffat_fwhm
from nightcrew.images.processors.moving import MeasureMovingBody
from nightcrew.modules.sim import SimCamera, SimRoof, SimTelescope
from nightcrew.modules.telescope.following import parse_moving_target
from nightcrew.site import Site
from nightcrew.testing import Observatory
from nightcrew.testing.solver import simulated_sky_indexes

__all__ = ["frames_table"]

#: A near-Earth asteroid 0.01 au away, moving 60"/min at the first frame.
FAST: dict[str, Any] = {
    "type": "ORBITAL_ELEMENTS",
    "scheme": "MPC_MINOR_PLANET",
    "name": "(bench) 2026 XF",
    "epochofel": 61354.91747,
    "orbinc": 15.422992,
    "longascnode": 47.634187,
    "argofperih": 7.921175,
    "eccentricity": 0.100097,
    "meandist": 1.111685,
    "meananom": 354.0237,
}
FIRST = datetime(2026, 11, 10, 22, 0, tzinfo=UTC)
SEED, DEPTH = 3, 15.0
CAMERA: dict[str, Any] = {
    "detector": {"cosmic_rays_per_s": 0.0},
    "focuser": None,
    "filters": None,
    "weather": None,
    "catalog_depth": DEPTH,
    "seed": SEED,
    "readout_time": 0.5,
}


async def two_frames(epoch: datetime) -> tuple[Image, Image]:
    """A 10-s sidereal frame of the field and a 300-s frame following the asteroid."""
    async with Observatory(epoch=epoch.isoformat()) as observatory:
        telescope = await observatory.start(
            SimTelescope, "telescope", init_time=0.0, drift_rate=0.0, periodic_amplitude=0.0
        )
        roof = await observatory.start(SimRoof, "roof", open_time=1.0)
        await telescope.init()
        await roof.open_roof()
        camera = await observatory.start(SimCamera, "camera", **CAMERA)
        body, _ = parse_moving_target(FAST)
        now = ephemeris(body, telescope.observatory, observatory.clock.time())
        await telescope.move_radec(float(now.ra[0]), float(now.dec[0]))
        frames = []
        for seconds, follow in ((10.0, False), (300.0, True)):
            if follow:
                await telescope.move_ephemeris(FAST)
                await observatory.clock.sleep(1.0)  # the first update sets the rates
            await camera.set_exposure_time(seconds)
            frames.append(Image.from_hdul(await observatory.vfs.read_fits(await camera.grab_data())))
        return frames[0], frames[1]


def stars_fwhm(frame: Image, catalog: Any) -> float:
    """Median FWHM (px) of the sidereal frame's well-exposed stars."""
    data = float_data(frame)
    clean = data - estimate_background(data).level
    good = (
        catalog[(catalog["peak"] > 2000) & (catalog["peak"] < 30000)]
        if "peak" in catalog.colnames
        else catalog
    )
    fwhm = measure_fwhm(clean, np.asarray(good["x"]), np.asarray(good["y"]), half_size=7)
    return float(np.nanmedian(fwhm))


def trail_length(stamp: Any) -> float:
    """Length (px) of the trail in a background-free ``stamp``: sqrt(12 (l1 - l2)) of its pixels
    above a tenth of the peak."""
    weights = np.where(stamp > 0.1 * stamp.max(), stamp, 0.0)
    rows, cols = np.indices(stamp.shape)
    total = weights.sum()
    mx, my = (weights * cols).sum() / total, (weights * rows).sum() / total
    dx, dy = cols - mx, rows - my
    cov = np.array([[(weights * dx * dx).sum(), (weights * dx * dy).sum()], [0.0, (weights * dy * dy).sum()]])
    cov[1, 0] = cov[0, 1]
    small, large = np.linalg.eigvalsh(cov / total)
    return math.sqrt(12.0 * max(0.0, float(large - small)))


async def measure(sidereal: Image, followed: Image) -> tuple[float, float, float, float, float]:
    """Drift (px) of the body and the same measure on still stars, body FWHM / stars' FWHM, and
    the measured-minus-ephemeris (ra, dec) in arcsec."""
    sidereal = await SepSourceDetection()(sidereal)
    index_dir = simulated_sky_indexes(
        [(followed.header["RA"], followed.header["DEC"])], width_arcmin=40.0, seed=SEED, depth=DEPTH
    )
    followed = await SepSourceDetection()(followed)
    followed = await CatalogAstrometry(index_dir=str(index_dir))(followed)
    followed = await MeasureMovingBody()(followed)
    h = followed.header
    if "MOV-RA" not in h:
        raise RuntimeError(f"the body was not measured: {h.get('MOV-NOTE')}")
    x, y = float(h["MOV-X"]), float(h["MOV-Y"])
    assert sidereal.catalog is not None
    data = float_data(followed)
    clean = data - estimate_background(data).level
    cx, cy = round(x), round(y)
    drift = trail_length(clean[cy - 7 : cy + 8, cx - 7 : cx + 8])
    body_fwhm = moffat_fwhm(clean[cy - 7 : cy + 8, cx - 7 : cx + 8], 7.0 + x - cx, 7.0 + y - cy)
    ratio = (body_fwhm or math.nan) / stars_fwhm(sidereal, sidereal.catalog)
    # The same measure on untrailed stars: what pixel sampling and noise alone give.
    still = float_data(sidereal)
    still -= estimate_background(still).level
    stars = sidereal.catalog[np.argsort(sidereal.catalog["flux"])[-40:-10]]
    baseline = float(
        np.median(
            [
                trail_length(still[round(sy) - 7 : round(sy) + 8, round(sx) - 7 : round(sx) + 8])
                for sx, sy in zip(stars["x"], stars["y"], strict=True)
                if 7 <= round(sx) < still.shape[1] - 8 and 7 <= round(sy) < still.shape[0] - 8
            ]
        )
    )
    body, _ = parse_moving_target(FAST)
    truth = ephemeris(body, _site(followed), (float(h["MOV-MJD"]) - 40_587.0) * 86_400.0)
    d_ra = ((float(h["MOV-RA"]) - float(truth.ra[0]) + 180.0) % 360.0 - 180.0) * math.cos(
        math.radians(float(truth.dec[0]))
    )
    return drift, baseline, ratio, d_ra * 3600.0, (float(h["MOV-DEC"]) - float(truth.dec[0])) * 3600.0


async def frames_table(count: int = 5) -> None:
    columns = (
        ('rate ("/min)', 12),
        ("body (px)", 9),
        ("star (px)", 9),
        ("drift (px)", 10),
        ("FWHM ratio", 10),
        ('dRA (")', 8),
        ('dDec (")', 8),
    )
    print("\n" + f"{'300-s frame (UTC)':18s}" + "".join(f" {name:>{width}s}" for name, width in columns))
    errors = []
    body, _ = parse_moving_target(FAST)
    for k in range(count):
        epoch = FIRST + timedelta(minutes=10 * k)
        sidereal, followed = await two_frames(epoch)
        drift, baseline, ratio, d_ra, d_dec = await measure(sidereal, followed)
        errors.append((d_ra, d_dec))
        site_rate = float(ephemeris(body, _site(followed), epoch.timestamp()).rate[0]) * 60.0
        trail = math.sqrt(max(0.0, drift**2 - baseline**2))  # the trail adds to the variance along it
        values = f"{site_rate:12.1f} {drift:9.2f} {baseline:9.2f} {trail:10.2f} {ratio:10.3f}"
        values += f" {d_ra:8.3f} {d_dec:8.3f}"
        print(f"{epoch:%H:%M:%S}{'':10s} {values}")
    rms = math.sqrt(float(np.mean(np.square(errors)) * 2.0))
    print(f'position RMS: {rms:.3f}" (target: <= 0.5"); drift target <= 1 px; FWHM ratio target 0.9..1.1')


def _site(frame: Image) -> Site:
    h = frame.header
    return Site(latitude=h["SITELAT"], longitude=h["SITELONG"], elevation=h["SITEELEV"])
