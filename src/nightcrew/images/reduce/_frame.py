"""One science frame reduced: calibrated with given masters, stars detected, plate-solved and
measured (and a followed moving body's position, :mod:`nightcrew.images.processors.moving`), with
the reduction headers set. ``nightcrew reduce`` and the online
:class:`~nightcrew.modules.image.pipeline.Pipeline` module both reduce through :func:`reduce_frame`.

Headers of a reduced frame (LCO's convention): ``RLEVEL`` = 91 (raw frames are 0), ``RAWFILE`` =
the raw frame's file name, ``BIASFILE``/``DARKFILE``/``FLATFILE`` = file names of the masters used
(absent when none was used).
"""

from __future__ import annotations

import asyncio
import time
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

from nightcrew.images.astrometry import (
    AstrometryError,
    CatalogAstrometry,
    FirstSolution,
    RemoteAstrometry,
    RemoteSolver,
    SolveField,
    SolveFieldAstrometry,
)
from nightcrew.images.calibration import calibrate_image
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.images.processors.moving import MeasureMovingBody
from nightcrew.images.processors.photometry import SepPhotometry

__all__ = ["REDUCED_LEVEL", "Master", "ReductionSteps", "StageTimes", "reduce_frame"]

REDUCED_LEVEL = 91
"""``RLEVEL`` of a reduced frame (LCO: 0 raw, 91 reduced)."""


@dataclass(frozen=True)
class Master:
    """A master frame and the file name it goes by in the reduced frame's header."""

    name: str
    image: Image


@dataclass
class StageTimes:
    """Seconds spent per stage of the reduction (summed over frames), for benchmarks and logs."""

    seconds: dict[str, float] = field(default_factory=lambda: defaultdict(float))

    def add(self, stage: str, started: float) -> None:
        self.seconds[stage] += time.perf_counter() - started


@dataclass(frozen=True)
class ReductionSteps:
    """Detection, plate solving (its failure is noted, not fatal), aperture photometry and the
    moving body's position (on frames that carry its ephemeris; None: not measured)."""

    detection: ImageProcessor
    astrometry: ImageProcessor
    photometry: ImageProcessor
    moving: ImageProcessor | None = None

    @classmethod
    def default(
        cls,
        *,
        pixel_scale_arcsec: float | None = None,
        index_dir: str | None = None,
        solver_url: str | None = None,
        solve_field: bool = True,
        solve_timeout_s: float = 60.0,
        detection_threshold: float = 4.0,
    ) -> ReductionSteps:
        """The catalog matcher first, then the solve service at ``solver_url``, then solve-field.

        The matcher and solve-field use the index files of ``index_dir`` (None: the system's).
        """
        matcher = (
            CatalogAstrometry(pixel_scale_arcsec=pixel_scale_arcsec)
            if index_dir is None
            else CatalogAstrometry(index_dir=index_dir, pixel_scale_arcsec=pixel_scale_arcsec)
        )
        solvers: list[ImageProcessor] = [matcher]
        if solver_url is not None:
            solvers.append(
                RemoteAstrometry(solver=RemoteSolver(solver_url), pixel_scale_arcsec=pixel_scale_arcsec)
            )
        if solve_field:
            solvers.append(
                SolveFieldAstrometry(
                    pixel_scale_arcsec=pixel_scale_arcsec,
                    solver=SolveField(timeout_s=solve_timeout_s, index_dir=index_dir),
                )
            )
        return cls(
            detection=SepSourceDetection(threshold=detection_threshold),
            astrometry=FirstSolution(solvers),
            photometry=SepPhotometry(radii=(3.0, 6.0)),
            moving=MeasureMovingBody(),
        )


async def reduce_frame(
    raw: Image,
    *,
    raw_name: str,
    steps: ReductionSteps,
    bias: Master | None,
    dark: Master | None = None,
    flat: Master | None = None,
    times: StageTimes | None = None,
) -> tuple[Image, list[str]]:
    """The reduced frame and notes on what was missing (no masters, no astrometric solution).

    Without a master bias the frame is not calibrated but still detected, solved and measured.
    """
    times = times or StageTimes()
    notes: list[str] = []
    image = raw
    started = time.perf_counter()
    if bias is None:
        notes.append("not calibrated: no master bias")
    else:
        missing = [kind for kind, master in (("dark", dark), ("flat", flat)) if master is None]
        if missing:
            notes.append(f"no master {', '.join(missing)}")
        image = await asyncio.to_thread(
            calibrate_image,
            image,
            bias=bias.image,
            dark=None if dark is None else dark.image,
            flat=None if flat is None else flat.image,
        )
    times.add("calibrate", started)
    started = time.perf_counter()
    image = await steps.detection(image)
    times.add("detect", started)
    started = time.perf_counter()
    try:
        image = await steps.astrometry(image)
    except AstrometryError as exc:
        notes.append(f"no astrometric solution: {exc.message.splitlines()[0]}")
    times.add("solve", started)
    started = time.perf_counter()
    image = await steps.photometry(image)
    times.add("photometry", started)
    if steps.moving is not None:
        started = time.perf_counter()
        image = await steps.moving(image)
        times.add("moving", started)
        if "MOV-NOTE" in image.header:
            notes.append(f"moving body: {image.header['MOV-NOTE']}")
    header = image.header.copy()
    cards: dict[str, Any] = {
        "RLEVEL": (REDUCED_LEVEL, "Reduction level (0 raw)"),
        "RAWFILE": (raw_name, "Raw frame"),
    }
    for keyword, master in (("BIASFILE", bias), ("DARKFILE", dark), ("FLATFILE", flat)):
        if master is not None:
            cards[keyword] = (master.name, "Master used")
        elif keyword in header:
            del header[keyword]
    for keyword, card in cards.items():
        header[keyword] = card
    return image.replace(header=header), notes
