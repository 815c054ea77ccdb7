"""Benchmark: the plate-solving service (``nightcrew solver``) against ``solve-field`` on the same frames.

Run ``.venv/bin/python bench/solver.py [--frames 50] [--chip 1024]``. Renders the frames (the
``make sim`` night's camera: 1024 px at 1.16"/px, a 20' field, sky seed 42 to G = 16; ``--chip
2048`` for 40' frames) at seeded random pointings, detects their stars, builds the simulated sky's
index files for those fields (:mod:`nightcrew.sim.sky_index`, cached; the time is printed), then
solves each star list with the service (on those index files) given a position hint (6' off) and
scale, with the service blind, and with ``solve-field`` (on the same index files) given the same
hints (each gives up after 10 s). Prints median/p90 seconds per solve against the targets, the
speed-up of the service over solve-field and the largest distance of the solved frame centre from
the truth.
"""

from __future__ import annotations

import argparse
import asyncio
import math
import statistics
import time
from collections.abc import Awaitable, Callable

import numpy as np
from astropy.io import fits  # type: ignore[import-untyped]
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.images.astrometry import AstrometryError, RemoteSolver, SolveField, SolveHints
from nightcrew.sim.catalog import StarCatalog
from nightcrew.testing.solver import (
    RenderedField,
    rendered_field,
    running_solver,
    simulated_sky_indexes,
    sky_distance_arcsec,
)

SEED, DEPTH = 42, 16.0

Solve = Callable[[RenderedField, SolveHints], Awaitable[fits.Header]]


def fields(count: int, chip_px: int) -> list[RenderedField]:
    rng = np.random.default_rng(2026)
    sky = StarCatalog(seed=SEED, depth=DEPTH)
    return [
        rendered_field(
            float(rng.uniform(0.0, 360.0)),
            float(np.degrees(np.arcsin(rng.uniform(-0.5, 0.98)))),
            rotation_deg=float(rng.uniform(0.0, 360.0)),
            seed=index,
            chip_px=chip_px,
            catalog=sky,
            seeing_arcsec=1.5,
        )
        for index in range(count)
    ]


def hinted(field: RenderedField) -> SolveHints:
    offset = 6.0 / 60.0
    return SolveHints(
        ra_deg=(field.true_ra_deg + offset / math.cos(math.radians(field.true_dec_deg))) % 360.0,
        dec_deg=field.true_dec_deg - offset if field.true_dec_deg > 0 else field.true_dec_deg + offset,
        radius_deg=1.0,
        pixel_scale_arcsec=field.pixel_scale_arcsec,
        scale_tolerance=0.1,
    )


async def run(
    name: str, solve: Solve, frames: list[RenderedField], blind: bool
) -> tuple[str, list[float], list[float]]:
    seconds, errors = [], []
    for field in frames:
        hints = SolveHints() if blind else hinted(field)
        started = time.perf_counter()
        try:
            cards = await solve(field, hints)
        except AstrometryError as exc:
            print(f"  {name}: no solution at ({field.true_ra_deg:.2f}, {field.true_dec_deg:.2f}): {exc}")
            seconds.append(time.perf_counter() - started)
            errors.append(math.inf)
            continue
        seconds.append(time.perf_counter() - started)
        rows, cols = field.shape
        ra, dec = WCS(cards).all_pix2world([(cols - 1) / 2.0], [(rows - 1) / 2.0], 0)
        errors.append(sky_distance_arcsec(float(ra[0]), float(dec[0]), field.true_ra_deg, field.true_dec_deg))
    return name, seconds, errors


async def bench(
    frames: list[RenderedField], url: str, index_dir: str
) -> list[tuple[str, list[float], list[float]]]:
    client, solve_field = (
        RemoteSolver(url, max_stars=200),
        SolveField(max_stars=200, timeout_s=60.0, cpu_limit_s=10.0, index_dir=index_dir),
    )

    async def service(field: RenderedField, hints: SolveHints) -> fits.Header:
        return await client.solve_stars(field.x, field.y, field.flux, shape=field.shape, hints=hints)

    async def local(field: RenderedField, hints: SolveHints) -> fits.Header:
        return await solve_field.solve_stars(field.x, field.y, field.flux, shape=field.shape, hints=hints)

    return [
        await run("service, position hint", service, frames, blind=False),
        await run("service, blind", service, frames, blind=True),
        await run("solve-field, position hint", local, frames, blind=False),
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--chip", type=int, default=1024, help="frame size in pixels (1024: the night's)")
    args = parser.parse_args()
    started = time.perf_counter()
    frames = fields(args.frames, args.chip)
    print(f"rendered {len(frames)} frames in {time.perf_counter() - started:.0f} s")
    started = time.perf_counter()
    width = args.chip * frames[0].pixel_scale_arcsec / 60.0
    index_dir = simulated_sky_indexes(
        [(f.true_ra_deg, f.true_dec_deg) for f in frames], width_arcmin=width, seed=SEED, depth=DEPTH
    )
    size = sum(path.stat().st_size for path in index_dir.glob("index-*.fits")) / 1e6
    print(f"sky index files ready in {time.perf_counter() - started:.0f} s: {index_dir} ({size:.0f} MB)")
    with running_solver(index_dir=index_dir) as url:
        results = asyncio.run(bench(frames, url, str(index_dir)))
    targets = {
        "service, position hint": "<= 0.5 s",
        "service, blind": "<= 2 s",
        "solve-field, position hint": "baseline",
    }
    baseline = statistics.median(results[2][1])
    header = ("case", "median s", "p90 s", "solved", "max err ''", "x faster")
    print(
        f"\n{header[0]:28}{header[1]:>10}{header[2]:>8}{header[3]:>9}{header[4]:>11}{header[5]:>10}  target"
    )
    for name, seconds, errors in results:
        p90 = float(np.percentile(seconds, 90))
        solved = sum(math.isfinite(e) for e in errors)
        worst = max((e for e in errors if math.isfinite(e)), default=math.inf)
        median = statistics.median(seconds)
        print(
            f"{name:28}{median:>10.3f}{p90:>8.3f}{solved:>6}/{len(errors):<3}{worst:>10.2f}"
            f"{baseline / median:>10.1f}  {targets[name]}"
        )
    print('targets: >= 5x faster than solve-field; max err <= 1" from the rendered truth')


if __name__ == "__main__":
    main()
