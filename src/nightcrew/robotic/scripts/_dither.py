"""Dithering between science frames, pure: where the n-th dither position lies, and when to move.

A dither moves the telescope a little between frames, so that a stack rejects the detector's
fixed defects (hot pixels, columns) and the sky's gradients. Positions are offsets from the
target, east and north in arcsec on the sky (``d_east`` is along the RA axis times cos dec):

* ``spiral``: the target, then the eight points of a square around it ``amplitude`` apart, in a
  spiral (east, north, west, west, south, south, east, east), then from the start again. Each step
  moves by ``amplitude`` along one axis (only the return to the target is diagonal); no position
  is more than ``amplitude * sqrt(2)`` away.
* ``random``: a uniform position within ``amplitude`` of the target along each axis, drawn from
  a generator seeded with the task (the same task dithers the same way when it is resumed).
"""

from __future__ import annotations

import math
import random
from collections.abc import Iterable

from nightcrew.robotic.tasks import DitherConfig, DitherPattern, RequestGroup

__all__ = [
    "SPIRAL_STEPS",
    "dither_field_problems",
    "dither_offset",
    "dither_to_radec",
    "dithers_before",
]

#: The square spiral in units of the amplitude: the centre, then the ring of eight around it.
SPIRAL_STEPS: tuple[tuple[int, int], ...] = (
    (0, 0),
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
    (-1, -1),
    (0, -1),
    (1, -1),
)


def dither_offset(config: DitherConfig, index: int, *, seed: str = "") -> tuple[float, float]:
    """The ``index``-th dither position (0: the target itself), (east, north) arcsec."""
    if index < 0:
        raise ValueError(f"index must be >= 0, got {index}")
    if index == 0 or config.amplitude == 0:
        return 0.0, 0.0
    if config.pattern is DitherPattern.SPIRAL:
        east, north = SPIRAL_STEPS[index % len(SPIRAL_STEPS)]
        return east * config.amplitude, north * config.amplitude
    rng = random.Random(f"{seed}:{index}")  # one draw per position: any index alone is reproducible
    return rng.uniform(-1.0, 1.0) * config.amplitude, rng.uniform(-1.0, 1.0) * config.amplitude


def dithers_before(config: DitherConfig, frames_taken: int) -> int:
    """How many dithers have happened once ``frames_taken`` frames are done: one after every
    ``every`` frames; the dither position of the next frame has this index."""
    if config.amplitude == 0 or frames_taken <= 0:
        return 0
    return frames_taken // config.every


def dither_to_radec(offset: tuple[float, float], dec: float) -> tuple[float, float]:
    """(east, north) arcsec as telescope offsets along the RA and Dec axes, degrees (RA not
    scaled by cos dec, as :class:`~nightcrew.interfaces.IOffsetsRaDec` takes them)."""
    east, north = offset
    cos_dec = max(math.cos(math.radians(dec)), 1e-6)  # at the pole a step in RA is no step at all
    return east / 3600.0 / cos_dec, north / 3600.0


def dither_field_problems(
    groups: Iterable[tuple[str, RequestGroup]], field_arcmin: float | None
) -> list[str]:
    """A line per configuration whose dither amplitude is larger than the camera's field (the
    target would leave the frame): ``groups`` as (where, group), ``field_arcmin`` the smallest
    field of the observatory's cameras (None: not known, nothing to say)."""
    if field_arcmin is None:
        return []
    problems = []
    for where, group in groups:
        for r, request in enumerate(group.requests):
            for c, configuration in enumerate(request.configurations):
                amplitude = configuration.dither_config.amplitude
                if amplitude > field_arcmin * 60.0:
                    problems.append(
                        f"{where}requests[{r}].configurations[{c}].dither_config.amplitude: "
                        f'{amplitude:g}" is larger than the camera\'s {field_arcmin * 60.0:.0f}" field'
                    )
    return problems
