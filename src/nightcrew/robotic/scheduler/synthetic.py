"""Seeded synthetic request lists, for the benchmark and the tests.

Targets are spread over the part of the sky that passes through the meridian during the night
(a uniform declination band above the airmass horizon, right ascensions around the night's local
sidereal times), so most can be observed some time; priorities, durations, windows and
constraints vary as in a real queue.
"""

from __future__ import annotations

import math
from datetime import datetime, timedelta

import numpy as np

from nightcrew.astro import local_sidereal_time
from nightcrew.robotic.scheduler.blocks import Constraints, Night, SchedulableBlock, Target

__all__ = ["synthetic_blocks"]


def synthetic_blocks(
    night: Night,
    count: int,
    *,
    seed: int,
    min_duration_s: float = 300.0,
    max_duration_s: float = 3600.0,
    setup_s: float = 60.0,
    window_fraction: float = 0.2,
    constrained_fraction: float = 0.3,
) -> list[SchedulableBlock]:
    """``count`` random blocks observable in ``night`` (seeded: the same seed, the same blocks).

    Args:
        window_fraction: Share of blocks with one observation window of 1-4 h inside the night.
        constrained_fraction: Share with a stricter airmass, a Moon distance or a Moon brightness limit.
    """
    rng = np.random.default_rng(seed)
    start, end = night.start.timestamp(), night.end.timestamp()
    lst_start = local_sidereal_time(start, night.site.longitude)
    night_degrees = (end - start) / 86164.1 * 360.0  # sidereal day
    lat = night.site.latitude
    # Declinations that rise above airmass 2 (altitude 30°) at transit, away from the pole's crowding.
    dec_low, dec_high = max(-89.0, lat - 60.0), min(89.0, lat + 60.0)
    blocks = []
    for index in range(count):
        ra = (lst_start - 30.0 + rng.uniform(0.0, night_degrees + 60.0)) % 360.0
        sin_dec = rng.uniform(math.sin(math.radians(dec_low)), math.sin(math.radians(dec_high)))
        dec = math.degrees(math.asin(sin_dec))
        windows: tuple[tuple[datetime, datetime], ...] = ()
        if rng.uniform() < window_fraction:
            length = rng.uniform(3600.0, 4 * 3600.0)
            opens = night.start + timedelta(seconds=rng.uniform(0.0, max(0.0, end - start - length)))
            windows = ((opens, opens + timedelta(seconds=length)),)
        constraints = Constraints()
        if rng.uniform() < constrained_fraction:
            constraints = Constraints(
                max_airmass=float(rng.choice([1.3, 1.5, 1.8])),
                min_moon_distance=float(rng.choice([0.0, 30.0, 60.0])),
                max_moon_illumination=float(rng.choice([0.5, 1.0])),
            )
        blocks.append(
            SchedulableBlock(
                id=f"req{index:04d}",
                priority=float(rng.uniform(1.0, 10.0)),
                duration_s=float(round(rng.uniform(min_duration_s, max_duration_s))),
                target=Target(ra, dec),
                constraints=constraints,
                windows=windows,
                setup_s=setup_s,
            )
        )
    return blocks
