"""Blocks for tasks without a target (BIAS, DARK, SKY_FLAT, SCRIPT): placed by window and Sun.

The scheduler places blocks by sky position, so a task without a target gets a stand-in target
near the celestial pole with no airmass limit (the flat-field pointing or the script chooses the
real position), and the scheduler fits it in by its windows and Sun limit like any other block.
Its priority counts :data:`CALIBRATION_WEIGHT` times more: calibrations are short, but the night's
data need them.

Sky flats wait for the sky to reach the right brightness, so their block is not the sum of their
exposure times but part of the twilight (:data:`TWILIGHT_SHARE`), with the Sun between their
``min_sun_altitude`` and ``max_sun_altitude``. With a site known, their windows become those
twilights (within the request's windows) and the block is shortened until it fits the longest of
them on the scheduler's time grid: the twilight lasts ~23 min at the equator and hours near the
polar circle, and a block longer than the twilight would never be planned. Without a site they take
:data:`SKY_FLAT_SECONDS` within the request's windows.
"""

from __future__ import annotations

import functools
import math
from datetime import UTC, datetime, timedelta

import numpy as np

from nightcrew.astro import sun_altitude
from nightcrew.robotic.scheduler import Constraints, SchedulableBlock, Target
from nightcrew.robotic.scheduler.sky import GridFit
from nightcrew.robotic.tasks._configuration import Configuration, ConfigurationType
from nightcrew.robotic.tasks._duration import DEFAULT_OVERHEADS, OverheadModel, estimate_duration
from nightcrew.robotic.tasks._task import Task
from nightcrew.site import Site

__all__ = [
    "CALIBRATION_WEIGHT",
    "NOTHING_LEFT_S",
    "SKY_FLAT_SECONDS",
    "TWILIGHT_SHARE",
    "calibration_block",
    "twilights",
]

#: Duration of a task with every exposure taken that failed before it was marked done: it still
#: has to run once (the runner then just completes it), and a block needs some duration.
NOTHING_LEFT_S = 1.0
#: Where a task without a target is put for the scheduler: always high up in the north.
POLE = Target(ra=0.0, dec=89.0)
#: Calibrations are short but the night's data need them: their priority counts this much more.
CALIBRATION_WEIGHT = 10.0
#: Sky flats take this part of the twilight (the Sun between their limits) they are planned in.
TWILIGHT_SHARE = 0.75
#: Sky flats take this long when no site is known to compute the twilight.
SKY_FLAT_SECONDS = 1800.0

Interval = tuple[datetime, datetime]


def calibration_block(
    task: Task,
    site: Site | None = None,
    *,
    fit: GridFit | None = None,
    overheads: OverheadModel = DEFAULT_OVERHEADS,
) -> SchedulableBlock:
    """The block of a task without a target: near the pole, priority x :data:`CALIBRATION_WEIGHT`.

    A retried task's duration is what it has left, as for blocks with a target. Sky flats last
    :data:`TWILIGHT_SHARE` of their longest twilight at ``site`` (shortened to fit it on the grid of
    ``fit``), in the twilights only; without a site :data:`SKY_FLAT_SECONDS`.
    """
    estimate = estimate_duration(task.request, overheads, progress=task.status.progress)
    configurations = task.request.configurations
    duration = max(sum(estimate.configurations_s), NOTHING_LEFT_S)
    windows = tuple((window.start, window.end) for window in task.request.windows)
    flats = [c for c in configurations if c.type is ConfigurationType.SKY_FLAT]
    if flats and (site is None or flats[0].constraints.min_sun_altitude is None):
        duration = max(duration, SKY_FLAT_SECONDS)
    elif flats and site is not None:
        spans = [
            span for start, end in windows for span in twilights(site, start, end, *_sun_range(flats[0]))
        ]
        if spans:
            longest = max((end - start).total_seconds() for start, end in spans)
            room = (fit or GridFit()).longest_duration(longest, estimate.setup_s)
            duration = max(NOTHING_LEFT_S, min(TWILIGHT_SHARE * longest, room))
            windows = tuple(spans)
        else:
            duration = max(duration, SKY_FLAT_SECONDS)  # no twilight in its windows: never planned
    return SchedulableBlock(
        id=task.id,
        priority=task.effective_priority * CALIBRATION_WEIGHT,
        duration_s=duration,
        target=POLE,
        constraints=Constraints(
            max_airmass=math.inf, max_sun_altitude=min(c.constraints.max_sun_altitude for c in configurations)
        ),
        windows=windows,
        setup_s=estimate.setup_s,
    )


def _sun_range(flats: Configuration) -> tuple[float, float]:
    low = flats.constraints.min_sun_altitude
    assert low is not None  # checked by the caller
    return low, flats.constraints.max_sun_altitude


def twilights(site: Site, start: datetime, end: datetime, low: float, high: float) -> list[Interval]:
    """The intervals (to a minute) between ``start`` and ``end`` with the Sun between ``low`` and
    ``high`` degrees, each a whole minute inside the limits at both ends."""
    return [(_utc(a), _utc(b)) for a, b in _blocking_twilights(site, start, end, low, high)]


@functools.lru_cache(maxsize=256)
def _blocking_twilights(
    site: Site, start: datetime, end: datetime, low: float, high: float
) -> tuple[tuple[float, float], ...]:
    # Cached: the scheduler asks for the blocks on every poll; the Sun at every minute of a window is
    # one array call (about 0.3 ms a night).
    t0 = math.ceil(start.timestamp() / 60.0) * 60.0
    minutes = t0 + 60.0 * np.arange(max(0, math.floor((end.timestamp() - t0) / 60.0) + 1), dtype=np.float64)
    altitude = sun_altitude(site.latitude, site.longitude, minutes)
    inside = np.concatenate(([False], (low <= altitude) & (altitude <= high), [False])).astype(np.int8)
    edges = np.flatnonzero(np.diff(inside))
    runs = zip(edges[::2], edges[1::2] - 1, strict=True)  # first and last minute of each run
    return tuple((float(minutes[a]), float(minutes[b])) for a, b in runs if b > a)


def _utc(unix_time: float) -> datetime:
    return datetime(1970, 1, 1, tzinfo=UTC) + timedelta(seconds=unix_time)
