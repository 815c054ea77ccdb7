"""The science fields of the `make sim` night, rendered the way its camera renders them.

The night's camera (``nightcrew sim``): a 1024 x 1024 px window of the simulated CCD at 1.16"/px
(a 20' field), sky seed 42, stars to G = 16, seeing 1.5". Its science fields are the targets of
its tasks (:func:`nightcrew.night.engine.night_tasks`: the samples and the survey of famous
fields, on the default night 2026-11-10; a target within 10' of an earlier one is the same field),
each a 60 s exposure (the night's shortest science exposure) with a pointing error of up to 3'
like the simulated mount's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from datetime import date
from functools import cache

import numpy as np

from nightcrew.night.build import bundled_observatory, observatory_site
from nightcrew.night.engine import night_tasks
from nightcrew.night.sky_indexes import task_fields
from nightcrew.sim.catalog import StarCatalog

__all__ = ["NIGHT_CHIP_PX", "NIGHT_SKY", "NIGHT_WIDTH_ARCMIN", "NightField", "night_fields"]

NIGHT_CHIP_PX = 1024
NIGHT_WIDTH_ARCMIN = NIGHT_CHIP_PX * 1.16 / 60.0
NIGHT_SEED, NIGHT_DEPTH = 42, 16.0
NIGHT = date(2026, 11, 10)


@cache
def NIGHT_SKY() -> StarCatalog:
    """The night's sky (the camera's seed and depth), shared by every test in the process."""
    return StarCatalog(seed=NIGHT_SEED, depth=NIGHT_DEPTH)


@dataclass(frozen=True)
class NightField:
    """One science frame: true pointing (deg), the pointing its header gives (the target's)."""

    ra_deg: float
    dec_deg: float
    header_ra_deg: float
    header_dec_deg: float

    @property
    def name(self) -> str:
        return f"({self.header_ra_deg:.3f}, {self.header_dec_deg:.3f})"


def _distance_arcmin(ra1: float, dec1: float, ra2: float, dec2: float) -> float:
    d_ra = ((ra1 - ra2 + 180.0) % 360.0 - 180.0) * math.cos(math.radians(0.5 * (dec1 + dec2)))
    return 60.0 * math.hypot(d_ra, dec1 - dec2)


@cache
def night_fields() -> tuple[NightField, ...]:
    """One frame per distinct field of the night's tasks, in task order."""
    tasks = night_tasks(NIGHT, observatory_site(bundled_observatory()))
    rng = np.random.default_rng(2026)
    fields: list[NightField] = []
    for ra, dec in task_fields(tasks):
        if any(_distance_arcmin(ra, dec, f.header_ra_deg, f.header_dec_deg) < 10.0 for f in fields):
            continue
        error, angle = 3.0 * math.sqrt(rng.random()), rng.uniform(0.0, 2.0 * math.pi)
        true_ra = (ra + error * math.cos(angle) / 60.0 / math.cos(math.radians(dec))) % 360.0
        fields.append(NightField(true_ra, dec + error * math.sin(angle) / 60.0, ra, dec))
    return tuple(fields)
