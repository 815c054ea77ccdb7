"""Benchmark of the image processors on simulated frames, against baselines timed in the same run.

Run: ``.venv/bin/python bench/images.py [runs]``. Prints one table: median and min milliseconds per
case, the target where there is one, and the ratio to the case's baseline. A case is one
decorated async function; to add a row (e.g. a plate solver), write::

    @case("catalog-matcher solve 1k", baseline="FITS read 1k", target_ms=500.0)
    async def solve_1k(frames: Frames) -> object:
        return await solver(frames.image_1k)
"""

from __future__ import annotations

import asyncio
import statistics
import sys
import time
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field

import numpy as np
from tests.images.frames import as_image, random_field, render

from nightcrew.images import Image
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.images.processors.misc import MeasureFwhm
from nightcrew.images.processors.offsets import NStarOffsets, ProjectedOffsets


@dataclass
class Frames:
    """The frames every case may use (rendered once): a 2k frame, a 1k reference and shifted 1k."""

    image_2k: Image
    bytes_2k: bytes
    image_1k: Image
    shifted_1k: Image
    bytes_1k: bytes
    state: dict[str, object] = field(default_factory=dict)


def make_frames() -> Frames:
    field_2k, field_1k = random_field(2048, 4800, seed=1), random_field(1024, 1200, seed=2)
    image_2k = as_image(render(field_2k, 2048, seed=3))
    image_1k = as_image(render(field_1k, 1024, seed=4))
    shifted_1k = as_image(render(field_1k, 1024, seed=5, shift=(7.3, -4.6)))
    return Frames(image_2k, image_2k.to_bytes(), image_1k, shifted_1k, image_1k.to_bytes())


@dataclass(frozen=True)
class Case:
    name: str
    run: Callable[[Frames], Awaitable[object]]
    baseline: str | None
    target_ms: float | None


CASES: list[Case] = []


def case(
    name: str, *, baseline: str | None = None, target_ms: float | None = None
) -> Callable[[Callable[[Frames], Awaitable[object]]], Callable[[Frames], Awaitable[object]]]:
    """Register an async function of the frames as a table row."""

    def register(run: Callable[[Frames], Awaitable[object]]) -> Callable[[Frames], Awaitable[object]]:
        CASES.append(Case(name, run, baseline, target_ms))
        return run

    return register


# --- baselines --------------------------------------------------------------------------------


@case("FITS read 2k")
async def read_2k(frames: Frames) -> object:
    return Image.from_bytes(frames.bytes_2k)


@case("numpy median 2k")
async def median_2k(frames: Frames) -> object:
    return np.median(frames.image_2k.data)


@case("FITS read 1k")
async def read_1k(frames: Frames) -> object:
    return Image.from_bytes(frames.bytes_1k)


# --- processors ---------------------------------------------------------------------------------


@case("SEP detection 2k", baseline="numpy median 2k")
async def detect_2k(frames: Frames) -> object:
    return await SepSourceDetection()(frames.image_2k)


@case("FWHM (detect + fit) 2k", baseline="numpy median 2k")
async def fwhm_2k(frames: Frames) -> object:
    return await MeasureFwhm()(frames.image_2k)


@case("NStarOffsets ref (detect) 1k", baseline="FITS read 1k")
async def nstar_reference_1k(frames: Frames) -> object:
    processor = NStarOffsets()
    await processor(frames.image_1k)
    frames.state["nstar"] = processor
    return processor


@case("NStarOffsets offset 1k", baseline="FITS read 1k", target_ms=30.0)
async def nstar_1k(frames: Frames) -> object:
    processor = frames.state["nstar"]
    assert isinstance(processor, NStarOffsets)
    return await processor(frames.shifted_1k)


@case("ProjectedOffsets ref 1k", baseline="FITS read 1k")
async def projected_reference_1k(frames: Frames) -> object:
    processor = ProjectedOffsets()
    await processor(frames.image_1k)
    frames.state["projected"] = processor
    return processor


@case("ProjectedOffsets offset 1k", baseline="FITS read 1k", target_ms=30.0)
async def projected_1k(frames: Frames) -> object:
    processor = frames.state["projected"]
    assert isinstance(processor, ProjectedOffsets)
    return await processor(frames.shifted_1k)


# --- plate solving (part B) ----------------------------------------------------------------------
# The frames above place stars at random pixels; a solver needs the simulated sky, so these rows
# render one 2k frame of StarCatalog stars (once, cached in ``frames.state``, outside the timing of
# any but the first run: the medians are what count) with the header RA/DEC 6'/4' off the truth.


def _catalog_sky_2k(frames: Frames) -> Image:
    cached = frames.state.get("catalog_sky_2k")
    if isinstance(cached, Image):
        return cached
    from nightcrew.images.processors.detection import detect_sources_sep
    from nightcrew.sim.catalog import StarCatalog
    from nightcrew.sim.projection import Pointing
    from nightcrew.sim.render import CameraModel, Conditions, Exposure, Optics, frame_geometry, render_frame

    pointing, camera, optics, exposure = Pointing(100.0, 30.0, 10.0), CameraModel(), Optics(), Exposure(30.0)
    stars = StarCatalog().query(100.0, 30.0, 0.5, epoch=2026.0)
    frame = render_frame(
        stars, pointing=pointing, focus=0.0, camera=camera, optics=optics,
        conditions=Conditions(seeing_arcsec=2.0), exposure=exposure, rng=np.random.default_rng(3),
    )  # fmt: skip
    header = {"RA": 100.1155, "DEC": 29.9333, "DATE-OBS": "2026-01-01T00:00:00", "EXPTIME": 30.0}
    header["PIXSCALE"] = frame_geometry(camera, optics, exposure).pixel_scale_arcsec
    image = Image(frame.data, header=header, catalog=detect_sources_sep(np.array(frame.data, np.float64)))
    frames.state["catalog_sky_2k"] = image
    return image


@case("catalog-matcher solve 2k", baseline="FITS read 2k", target_ms=500.0)
async def catalog_solve_2k(frames: Frames) -> object:
    from nightcrew.images.astrometry import CatalogAstrometry

    return await CatalogAstrometry()(_catalog_sky_2k(frames))


@case("astrometry.net solve-field 2k", baseline="FITS read 2k")
async def solve_field_2k(frames: Frames) -> object:
    from nightcrew.images.astrometry import SolveFieldAstrometry

    return await SolveFieldAstrometry(radius_deg=0.5)(_catalog_sky_2k(frames))


async def timed(run: Callable[[Frames], Awaitable[object]], frames: Frames, runs: int) -> list[float]:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        await run(frames)
        times.append((time.perf_counter() - start) * 1e3)
    return times


async def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    frames = make_frames()
    medians: dict[str, float] = {}
    print(f"{runs} runs per case; frames rendered by nightcrew.sim (FWHM ~3.4 px)")
    print(f"{'case':<30}{'median ms':>10}{'min ms':>9}{'target':>8}{'ratio':>7}  baseline")
    for item in CASES:
        times = await timed(item.run, frames, runs)
        medians[item.name] = statistics.median(times)
        target = f"{item.target_ms:.0f}" if item.target_ms is not None else ""
        ratio = f"{medians[item.name] / medians[item.baseline]:.1f}" if item.baseline in medians else ""
        print(
            f"{item.name:<30}{medians[item.name]:>10.1f}{min(times):>9.1f}{target:>8}{ratio:>7}"
            f"  {item.baseline or ''}"
        )
    offset = (await nstar_1k(frames)).metadata["offsets"]  # type: ignore[attr-defined]
    print(f"check: NStarOffsets found ({offset.dx:.3f}, {offset.dy:.3f}) for a true (7.300, -4.600)")


if __name__ == "__main__":
    asyncio.run(main())
