"""Benchmark: render a 2048x2048 frame with ~1000 stars; baseline = the noise frame alone.

Run: ``.venv/bin/python bench/render.py [runs]``. Prints median/min milliseconds and the ratio of
the full render to the baseline (drawing one float32 Gaussian per pixel and digitising it).
"""

from __future__ import annotations

import statistics
import sys
import time
from collections.abc import Callable

import numpy as np

from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.detector import digitize
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


def timed(run: Callable[[int], object], runs: int) -> list[float]:
    times = []
    for i in range(runs):
        start = time.perf_counter()
        run(i)
        times.append((time.perf_counter() - start) * 1e3)
    return times


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    camera, optics, conditions, exposure = CameraModel(), Optics(), Conditions(), Exposure(30.0)
    pointing = Pointing(100.0, 30.0, 10.0)
    geometry = frame_geometry(camera, optics, exposure)
    stars = StarCatalog(depth=15.3).query(pointing.ra_deg, pointing.dec_deg, field_radius_deg(geometry))

    def render(i: int) -> object:
        return render_frame(
            stars,
            pointing=pointing,
            focus=0.0,
            camera=camera,
            optics=optics,
            conditions=conditions,
            exposure=exposure,
            rng=np.random.default_rng(i),
        )

    def baseline(i: int) -> object:
        rng = np.random.default_rng(i)
        noise = rng.standard_normal(geometry.shape, dtype=np.float32)
        return digitize(noise * np.float32(8.0), gain_e_per_adu=1.5, bias_adu=1000.0)

    frame = render_frame(
        stars,
        pointing=pointing,
        focus=0.0,
        camera=camera,
        optics=optics,
        conditions=conditions,
        exposure=exposure,
        rng=np.random.default_rng(0),
    )
    full, base = timed(render, runs), timed(baseline, runs)
    rows, cols = geometry.shape
    print(
        f"frame {cols}x{rows}, {len(frame.stars.x)} stars on frame, FWHM {frame.fwhm_px:.2f} px, {runs} runs"
    )
    print(f"{'case':<28}{'median ms':>10}{'min ms':>10}")
    print(f"{'render_frame':<28}{statistics.median(full):>10.1f}{min(full):>10.1f}")
    print(f"{'baseline: noise + digitize':<28}{statistics.median(base):>10.1f}{min(base):>10.1f}")
    print(f"{'ratio render / baseline':<28}{statistics.median(full) / statistics.median(base):>10.2f}")


if __name__ == "__main__":
    main()
