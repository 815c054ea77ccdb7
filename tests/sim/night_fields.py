"""The science fields of the `make sim` night, rendered the way its camera renders them.

The night's camera (``nightcrew sim``): a 1024 x 1024 px window of the simulated CCD at 1.16"/px
(a 20' field), sky seed 42, stars to G = 16, seeing 1.5". Its science targets are the sample
tasks' (:mod:`nightcrew.robotic.samples`: nine distinct fields), each taken with its first
exposure time and a pointing error of up to 3' like the simulated mount's; three more fields 20'
beside M31, M15 and the Pleiades (a mosaic's neighbours) make twelve.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from nightcrew.robotic.samples import load_samples
from nightcrew.sim.catalog import StarCatalog

__all__ = ["NIGHT_CHIP_PX", "NIGHT_SKY", "NIGHT_WIDTH_ARCMIN", "NightField", "night_fields"]

NIGHT_CHIP_PX = 1024
NIGHT_WIDTH_ARCMIN = NIGHT_CHIP_PX * 1.16 / 60.0
NIGHT_SEED, NIGHT_DEPTH = 42, 16.0


@cache
def NIGHT_SKY() -> StarCatalog:
    """The night's sky (the camera's seed and depth), shared by every test in the process."""
    return StarCatalog(seed=NIGHT_SEED, depth=NIGHT_DEPTH)


@dataclass(frozen=True)
class NightField:
    """One science frame: true pointing (deg), the pointing the header would give, exposure (s)."""

    name: str
    ra_deg: float
    dec_deg: float
    header_ra_deg: float
    header_dec_deg: float
    exposure_s: float


def _offset(ra: float, dec: float, east_arcmin: float, north_arcmin: float) -> tuple[float, float]:
    return (ra + east_arcmin / 60.0 / math.cos(math.radians(dec))) % 360.0, dec + north_arcmin / 60.0


@cache
def night_fields() -> tuple[NightField, ...]:
    """The twelve science fields (see the module docstring), in a fixed order."""
    targets: dict[str, tuple[float, float, float]] = {}
    for group in load_samples().values():
        for request in group.requests:
            for configuration in request.configurations:
                target = configuration.target
                ra, dec = getattr(target, "ra", None), getattr(target, "dec", None)
                science = configuration.type in ("EXPOSE", "REPEAT_EXPOSE")
                if science and target is not None and isinstance(ra, float) and isinstance(dec, float):
                    exposure = configuration.instrument_configs[0].exposure_time
                    targets.setdefault(str(target.name), (ra, dec, float(exposure)))
    for name, east, north in (("M31", 20.0, 0.0), ("M15", 0.0, 20.0), ("Alcyone (M45)", -20.0, 0.0)):
        ra, dec, exposure = targets[name]
        targets[f"{name} +20'"] = (*_offset(ra, dec, east, north), exposure)
    rng = np.random.default_rng(2026)
    fields = []
    for name, (ra, dec, exposure) in targets.items():
        error, angle = 3.0 * math.sqrt(rng.random()), rng.uniform(0.0, 2.0 * math.pi)
        true_ra, true_dec = _offset(ra, dec, error * math.cos(angle), error * math.sin(angle))
        fields.append(NightField(name, true_ra, true_dec, ra, dec, exposure))
    return tuple(fields)
