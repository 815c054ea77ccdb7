"""The plate-solving service for tests and benchmarks: run it, and frames to solve with it.

:func:`running_solver` starts ``nightcrew solver`` as a child process on a loopback port (the real
service, as a user runs it) and stops it by its PID; :func:`rendered_field` renders a frame of the
simulated sky at a known pointing and detects its stars, so a solution can be checked against the
truth.
"""

from __future__ import annotations

import asyncio
import math
import os
import subprocess
import sys
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor
from nightcrew.testing.processes import free_port, wait_until_listening

if TYPE_CHECKING:
    from nightcrew.sim.catalog import StarCatalog

__all__ = [
    "RenderedField",
    "rendered_field",
    "running_solver",
    "simulated_sky_indexes",
    "sky_distance_arcsec",
]

FloatArray = npt.NDArray[np.float64]


@contextmanager
def running_solver(*, index_dir: Path | None = None, sip_order: int = 2) -> Iterator[str]:
    """``nightcrew solver`` on 127.0.0.1 for the block; yields its base URL."""
    port = free_port()
    with tempfile.TemporaryDirectory(prefix="nightcrew-solver-") as workdir:
        log_path = Path(workdir) / "solver.log"
        command = [
            sys.executable,
            "-m",
            "nightcrew",
            "solver",
            "--port",
            str(port),
            "--sip-order",
            str(sip_order),
        ]
        if index_dir is not None:
            command += ["--index-dir", str(index_dir)]
        with log_path.open("wb") as log:
            process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=dict(os.environ))
        try:
            wait_until_listening(process, port, what="nightcrew solver", log=log_path)
            yield f"http://127.0.0.1:{port}"
        finally:
            process.terminate()
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


@dataclass(frozen=True)
class RenderedField:
    """A rendered frame's pixels, its detected stars (0-based, brightest first) and true pointing."""

    data: npt.NDArray[np.uint16]
    x: FloatArray
    y: FloatArray
    flux: FloatArray
    shape: tuple[int, int]
    pixel_scale_arcsec: float
    true_ra_deg: float
    true_dec_deg: float


def rendered_field(
    ra_deg: float,
    dec_deg: float,
    *,
    rotation_deg: float = 0.0,
    seed: int = 0,
    exposure_s: float = 30.0,
    chip_px: int = 2048,
    catalog: StarCatalog | None = None,
    seeing_arcsec: float = 2.0,
) -> RenderedField:
    """A frame (``chip_px`` square, 1.16"/px, the simulated camera) of the simulated sky, its stars detected.

    The sky is ``catalog`` (default: seed ``seed``, depth 16); ``seed`` also seeds the noise.
    """
    from nightcrew.images.processors.detection import detect_sources_sep
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

    camera, optics = CameraModel(chip_width=chip_px, chip_height=chip_px), Optics()
    exposure = Exposure(exposure_s)
    geometry = frame_geometry(camera, optics, exposure)
    pointing = Pointing(ra_deg, dec_deg, rotation_deg)
    stars = (catalog or StarCatalog(seed=seed)).query(
        ra_deg, dec_deg, field_radius_deg(geometry), epoch=2026.0
    )
    frame = render_frame(
        stars,
        pointing=pointing,
        focus=0.0,
        camera=camera,
        optics=optics,
        conditions=Conditions(seeing_arcsec=seeing_arcsec),
        exposure=exposure,
        rng=np.random.default_rng(seed),
    )
    detected = detect_sources_sep(np.array(frame.data, dtype=np.float64))
    order = np.argsort(-np.asarray(detected["flux"], dtype=np.float64), kind="stable")
    return RenderedField(
        data=np.asarray(frame.data, dtype=np.uint16),
        x=np.asarray(detected["x"], dtype=np.float64)[order],
        y=np.asarray(detected["y"], dtype=np.float64)[order],
        flux=np.asarray(detected["flux"], dtype=np.float64)[order],
        shape=geometry.shape,
        pixel_scale_arcsec=geometry.pixel_scale_arcsec,
        true_ra_deg=ra_deg,
        true_dec_deg=dec_deg,
    )


def simulated_sky_indexes(
    fields: Iterable[tuple[float, float]], *, width_arcmin: float, seed: int = 0, depth: float = 16.0
) -> Path:
    """The simulated sky's index directory, with the files that frames ``width_arcmin`` wide centred
    at ``fields`` (ra, dec deg) need built (kept in the user's cache, see :mod:`nightcrew.sim.sky_index`)."""
    from nightcrew.sim.catalog import StarCatalog
    from nightcrew.sim.sky_index import SkyIndexBuilder

    builder = SkyIndexBuilder(StarCatalog(seed=seed, depth=depth))
    return builder.blocking_build(fields, width_arcmin=[width_arcmin])


def sky_distance_arcsec(ra1: float, dec1: float, ra2: float, dec2: float) -> float:
    """Angular distance of two positions (degrees in, arcsec out), good for small distances."""
    d_ra = (ra1 - ra2 + 180.0) % 360.0 - 180.0
    return 3600.0 * math.hypot(d_ra * math.cos(math.radians(0.5 * (dec1 + dec2))), dec1 - dec2)


class SimulatedSkyIndexes(ImageProcessor):
    """A pipeline step for tests: builds the simulated sky's index files for the frame's field.

    Put it before an astrometry processor whose ``index_dir`` is :attr:`directory`, in tests
    whose fields are not known in advance (a pointing series): it reads the header's ``RA``/``DEC``
    and pixel scale, as the solvers do, and builds what is missing (cached, see
    :mod:`nightcrew.sim.sky_index`). The image passes unchanged.

    Args:
        seed, depth: The simulated camera's sky.
    """

    def __init__(self, *, seed: int = 0, depth: float = 16.0, **kwargs: Any) -> None:
        from nightcrew.sim.catalog import StarCatalog
        from nightcrew.sim.sky_index import SkyIndexBuilder

        super().__init__(**kwargs)
        self._builder = SkyIndexBuilder(StarCatalog(seed=seed, depth=depth))
        self.directory = str(self._builder.directory)

    async def __call__(self, image: Image) -> Image:
        ra, dec, scale = image.header.get("RA"), image.header.get("DEC"), image.pixel_scale
        if isinstance(ra, float | int) and isinstance(dec, float | int) and scale is not None:
            width = max(image.shape) * scale / 60.0
            await asyncio.to_thread(
                self._builder.blocking_build, [(float(ra), float(dec))], width_arcmin=[width]
            )
        return image
