"""Seeded synthetic request lists, for the benchmark and the tests.

Targets are spread over the part of the sky that passes through the meridian during the night
(a uniform declination band above the airmass horizon, right ascensions around the night's local
sidereal times), so most can be observed some time; priorities, durations, windows and
constraints vary as in a real queue.
"""

from __future__ import annotations

import math
from datetime import UTC, datetime, timedelta

import numpy as np

from nightcrew.astro import local_sidereal_time
from nightcrew.robotic.scheduler.blocks import Constraints, Night, SchedulableBlock, Target

__all__ = ["cadence_blocks", "narrow_window_blocks", "synthetic_blocks"]


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


def _sky_position(night: Night, rng: np.random.Generator) -> Target:
    """A random target that passes the meridian during the night (as :func:`synthetic_blocks`)."""
    start, end = night.start.timestamp(), night.end.timestamp()
    lst_start = local_sidereal_time(start, night.site.longitude)
    ra = (lst_start - 30.0 + rng.uniform(0.0, (end - start) / 86164.1 * 360.0 + 60.0)) % 360.0
    lat = night.site.latitude
    low, high = math.sin(math.radians(max(-89.0, lat - 60.0))), math.sin(math.radians(min(89.0, lat + 60.0)))
    return Target(ra, math.degrees(math.asin(rng.uniform(low, high))))


def narrow_window_blocks(
    night: Night, count: int, *, seed: int, setup_s: float = 60.0
) -> list[SchedulableBlock]:
    """``count`` time-critical blocks: one window of 15-45 min opening at any second of the night,
    an observation of 5-20 min that fits it with its set-up, priorities 5-20."""
    rng = np.random.default_rng(seed)
    start, end = night.start.timestamp(), night.end.timestamp()
    blocks = []
    for index in range(count):
        length = float(rng.uniform(15 * 60.0, 45 * 60.0))
        opens = night.start + timedelta(seconds=float(rng.uniform(0.0, end - start - length)))
        duration = float(round(rng.uniform(300.0, min(1200.0, length - setup_s - 240.0))))
        blocks.append(
            SchedulableBlock(
                id=f"tc{index:04d}",
                priority=float(rng.uniform(5.0, 20.0)),
                duration_s=duration,
                target=_sky_position(night, rng),
                windows=((opens, opens + timedelta(seconds=length)),),
                setup_s=setup_s,
            )
        )
    return blocks


def cadence_blocks(
    night: Night, count: int, *, seed: int, visits: int = 10, setup_s: float = 60.0
) -> list[SchedulableBlock]:
    """``count`` blocks of monitoring: ``count / visits`` targets, each visited every 40-90 min
    (the period) within +-10 min (the jitter) for 3-8 min, the first visit anywhere in the night."""
    rng = np.random.default_rng(seed)
    start, end = night.start.timestamp(), night.end.timestamp()
    blocks: list[SchedulableBlock] = []
    series = 0
    while len(blocks) < count:
        target = _sky_position(night, rng)
        period, jitter = float(rng.uniform(2400.0, 5400.0)), 600.0
        duration = float(round(rng.uniform(180.0, 480.0)))
        first = float(rng.uniform(start + jitter, start + 3 * 3600.0))
        priority = float(rng.uniform(2.0, 12.0))
        for visit in range(visits):
            middle = first + visit * period
            if middle + jitter > end or len(blocks) >= count:
                break
            window = (_utc(middle - jitter), _utc(middle + jitter))
            blocks.append(
                SchedulableBlock(
                    id=f"cad{series:03d}-{visit:02d}",
                    priority=priority,
                    duration_s=duration,
                    target=target,
                    windows=(window,),
                    setup_s=setup_s,
                )
            )
        series += 1
    return blocks


def _utc(unix_time: float) -> datetime:
    return datetime.fromtimestamp(unix_time, tz=UTC)
