"""Moving bodies in the simulated observatory: the camera draws the body the mount follows where its
ephemeris says (a point, the stars trailed), and the Pipeline measures it on the solved frame and
writes its MPC line. The bodies are docs/tasks.md's moving-target examples, each near its best time
on the example's night."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from nightcrew.config import build_object
from nightcrew.images.image import Image
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.images.processors.misc import moffat_fwhm
from nightcrew.modules import Module
from nightcrew.modules.image import Pipeline
from nightcrew.modules.sim import SimCamera, SimRoof, SimTelescope
from nightcrew.sim.catalog import STAR_DTYPE
from nightcrew.sim.projection import FrameGeometry, Pointing, sky_to_pixel
from nightcrew.sim.render import CameraModel, Conditions, Exposure, Motion, MovingBody, Optics, render_frame
from nightcrew.sim.trail import trail_kernel
from nightcrew.testing import Observatory
from nightcrew.testing.solver import simulated_sky_indexes
from nightcrew.vfs import LocalFile, VirtualFileSystem
from tests.robotic.test_moving_targets import example

SEED, DEPTH = 3, 15.0
DETECTOR = {"chip_width": 1024, "chip_height": 1024, "cosmic_rays_per_s": 0.0}


def targets() -> dict[str, dict[str, Any]]:
    """The example's four targets by kind."""
    found = [r["configurations"][0]["target"] for r in example()["requests"]]
    return {t["type"]: t for t in found}


def test_a_trail_kernel_spreads_a_point_evenly_along_its_path() -> None:
    dx, dy = np.linspace(-10.0, 10.0, 81), np.linspace(0.0, 5.0, 81)
    kernel = trail_kernel(dx, dy)
    assert kernel.shape == (2 * 6 + 1, 2 * 11 + 1) and kernel.sum() == pytest.approx(1.0)
    rows, cols = np.indices(kernel.shape)
    assert float((cols * kernel).sum()) - 11 == pytest.approx(0.0, abs=1e-6)  # mean shift: dx's mean
    assert float((rows * kernel).sum()) - 6 == pytest.approx(2.5, abs=1e-6)


def test_a_followed_body_is_a_point_among_trailed_stars() -> None:
    # The axis moves by 60" of RA (52" on the sky at Dec 30: 45 px) and the body with it.
    count = 300
    ra = 100.0 + np.linspace(0.0, 60.0, count) / 3600.0
    dec = np.full(count, 30.0)
    stars = np.zeros(1, STAR_DTYPE)
    stars["ra"], stars["dec"], stars["mag"] = 100.02, 30.02, 12.0
    motion = Motion(ra, dec, (MovingBody(ra + 0.01, dec, mag=12.0),))
    frame = render_frame(
        stars,
        pointing=Pointing(100.0, 30.0),
        focus=0.0,
        camera=CameraModel(chip_width=256, chip_height=256, read_noise_e=0.0, cosmic_rays_per_s=0.0),
        optics=Optics(),
        conditions=Conditions(),
        exposure=Exposure(60.0),
        rng=np.random.default_rng(1),
        motion=motion,
    )
    data = frame.data.astype(float) - np.median(frame.data)
    bx, by = round(float(frame.bodies.x[0])), round(float(frame.bodies.y[0]))
    body_fwhm = moffat_fwhm(data[by - 7 : by + 8, bx - 7 : bx + 8], 7.0, 7.0)
    assert body_fwhm == pytest.approx(frame.fwhm_px, rel=0.1)
    sx, sy = float(frame.stars.x[0]), float(frame.stars.y[0])
    row = data[round(sy), :]
    lit = np.flatnonzero(row > 0.5 * row.max())
    assert 43 <= lit.max() - lit.min() <= 47  # the star's trail, from where it was at the start
    assert min(abs(sx - lit.min()), abs(sx - lit.max())) < 2


@pytest.mark.parametrize(
    ("kind", "name", "epoch", "seconds"),
    [
        ("MPC_ELEMENTS", "(example) 2026 XA", "2026-11-10T21:00:00", 120.0),
        ("ORBITAL_ELEMENTS", "C/2026 X1 (example)", "2026-11-10T18:30:00", 60.0),
        ("MAJOR_BODY", "jupiter", "2026-11-11T03:00:00", 1.0),
    ],
)
async def test_the_pipeline_measures_the_followed_body_and_writes_its_mpc_line(
    kind: str, name: str, epoch: str, seconds: float, tmp_path: Path
) -> None:
    frame = await followed_frame(kind, epoch, seconds)
    if kind != "MAJOR_BODY":
        assert body_fwhm_ratio(frame) == pytest.approx(1.0, abs=0.1)
    index_dir = simulated_sky_indexes(
        [(frame.header["RA"], frame.header["DEC"])], width_arcmin=20.0, seed=SEED, depth=DEPTH
    )
    vfs = VirtualFileSystem({"data": LocalFile(str(tmp_path))})
    await vfs.write_bytes("/data/masters/README", b"no masters")
    await frame.to_vfs(vfs, "/data/raw/frame.fits")
    async with Observatory(epoch=epoch + "+00:00") as observatory:
        pipeline = await observatory.start(
            Pipeline,
            "pipeline",
            vfs=vfs,
            masters="/data/masters",
            output="/data/reduced",
            index_dir=str(index_dir),
        )
        reduced = Image.from_hdul(await vfs.read_fits(await pipeline.reduce("/data/raw/frame.fits")))
    header = reduced.header
    assert header["MOVOBJ"] == name and "EPH-RAR" in header and "EPH-DIST" in header
    if kind == "MAJOR_BODY":  # Jupiter saturates: noted, no MPC line (the MPC takes no planets)
        assert header["MOV-NOTE"] == "saturated: not measured"
        assert not (tmp_path / "reduced" / "frame_red.mpc").exists()
        return
    assert header["MOV-DIFF"] < 0.5, header["MOV-DIFF"]
    line = (tmp_path / "reduced" / "frame_red.mpc").read_text()
    assert len(line) == 81 and line.endswith("XXX\n") and line[14] == "C"


async def test_a_followed_satellite_is_a_point_and_the_stars_long_trails() -> None:
    frame = await followed_frame("SATELLITE", "2026-11-10T18:38:30", 1.0)
    assert body_fwhm_ratio(frame) == pytest.approx(1.0, abs=0.1)
    stars = (await SepSourceDetection()(frame)).catalog
    assert stars is not None
    brightest = stars[np.argsort(stars["flux"])[-10:]]
    assert float(np.median(brightest["a"] / brightest["b"])) > 3.0  # round stars: about 1


def body_fwhm_ratio(frame: Image) -> float:
    """FWHM of the body over the stars' (the simulator's SIM-FWHM: the stars are trailed). The body
    is found where the simulator's true pointing at the start puts its ephemeris position then: it
    stays there while the mount follows it."""
    h = frame.header
    rows, cols = frame.shape
    geometry = FrameGeometry(cols, rows, float(h["PIXSCALE"]))
    u, v = sky_to_pixel(h["EPH-RA"], h["EPH-DEC"], Pointing(h["SIM-RA"], h["SIM-DEC"]), geometry)
    data = frame.data.astype(float) - float(np.median(frame.data))
    x0, y0 = round(float(u)), round(float(v))
    near = data[y0 - 5 : y0 + 6, x0 - 5 : x0 + 6]
    dy, dx = (int(d) - 5 for d in np.unravel_index(np.argmax(near), near.shape))
    x, y = x0 + dx, y0 + dy
    fwhm = moffat_fwhm(data[y - 7 : y + 8, x - 7 : x + 8], 7.0, 7.0)
    assert fwhm is not None
    return fwhm * float(h["PIXSCALE"]) / float(h["SIM-FWHM"])


async def followed_frame(kind: str, epoch: str, seconds: float) -> Image:
    """One frame taken while the simulated mount follows the example's target of ``kind``."""
    async with Observatory(epoch=epoch + "+00:00") as observatory:
        telescope = await observatory.start(
            SimTelescope, "telescope", init_time=0.0, drift_rate=0.0, periodic_amplitude=0.0
        )
        roof = await observatory.start(SimRoof, "roof", open_time=1.0)
        await telescope.init()
        await roof.open_roof()
        await telescope.move_ephemeris(targets()[kind])
        await observatory.clock.sleep(1.0)  # the first update sets the rates
        camera = await observatory.start(
            SimCamera,
            "camera",
            detector=DETECTOR,
            focuser=None,
            filters=None,
            weather=None,
            catalog_depth=DEPTH,
            seed=SEED,
            readout_time=0.5,
        )
        await camera.set_exposure_time(seconds)
        raw = await camera.grab_data()
        return Image.from_hdul(await observatory.vfs.read_fits(raw))


def test_the_documented_pipeline_with_an_observatory_code_builds() -> None:
    section = (Path(__file__).parents[2] / "docs/pipeline.md").read_text().split("### Moving bodies", 1)[1]
    block = next(b for b in re.findall(r"```yaml\n(.*?)```", section, flags=re.S) if "observatory_code" in b)
    pipeline = build_object({**yaml.safe_load(block), "name": "pipeline"}, Module)
    assert isinstance(pipeline, Pipeline)
