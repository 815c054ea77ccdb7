"""When on one night a request can be observed, and a request group's windows fitted to that night.

Request groups written for one night (the sample tasks) and moved to another date keep their
clock times, so their windows may fall where the target is below its airmass limit or the Sun is
too high. :func:`fit_to_night` keeps a request's windows when each of them still holds a stretch
in which the request can be done (as long as its estimated duration); otherwise the windows become
the night's stretches where it can, and a request with none is dropped (:class:`NightFit` says
which, so the caller can report it).

"Can be observed" is what the scheduler checks — its sky (:class:`~nightcrew.robotic.scheduler.sky.SkyGrid`)
and constraints (airmass, Moon, Sun) on the same five-minute slices — plus ``min_sun_altitude``
(twilight flats). A request without a target needs only its Sun limits.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime

import numpy as np
import numpy.typing as npt

from nightcrew.robotic.scheduler.constraints import (
    AirmassConstraint,
    MoonDistanceConstraint,
    MoonIlluminationConstraint,
    visibility,
)
from nightcrew.robotic.scheduler.sky import SkyGrid, TimeGrid
from nightcrew.robotic.tasks._duration import estimate_duration
from nightcrew.robotic.tasks._request import Request, RequestGroup, Window
from nightcrew.robotic.tasks._task import tasks_of_group
from nightcrew.robotic.tasks.blocks import block_of
from nightcrew.site import Site

__all__ = ["STEP", "NightFit", "fit_to_night", "observable_stretches"]

#: Seconds per slice of the night (the scheduler's resolution).
STEP = 300.0

Stretch = tuple[datetime, datetime]
_TARGET_CONSTRAINTS = (AirmassConstraint(), MoonIlluminationConstraint(), MoonDistanceConstraint())


@dataclass(frozen=True)
class NightFit:
    """A request group fitted to one night.

    Attributes:
        group: The group with the requests that can be observed (windows replaced where needed);
            None when none can.
        refitted: Indexes of the requests whose windows were replaced.
        dropped: Indexes of the requests that cannot be observed that night.
    """

    group: RequestGroup | None
    refitted: tuple[int, ...] = ()
    dropped: tuple[int, ...] = ()


def observable_stretches(
    request: Request, site: Site, start: datetime, end: datetime, *, step: float = STEP
) -> list[Stretch]:
    """The stretches of ``[start, end]`` (to ``step`` seconds) in which ``request`` may be observed.

    Its windows are not looked at: this is where they could be.
    """
    grid = TimeGrid.covering(start.timestamp(), end.timestamp(), step)
    task = tasks_of_group(_alone(request), "visibility", ["0"])[0]
    block = block_of(task, site=site)
    sky = SkyGrid(grid, site, [] if block is None else [block])
    ok = _sun_allows(request, sky.sun_altitude)
    if block is not None:
        ok &= visibility(sky, _TARGET_CONSTRAINTS)[0]
    return _runs(ok, grid)


def fit_to_night(
    group: RequestGroup, site: Site, start: datetime, end: datetime, *, step: float = STEP
) -> NightFit:
    """``group`` with windows in which its requests can be done between ``start`` and ``end``."""
    kept: list[Request] = []
    refitted: list[int] = []
    dropped: list[int] = []
    for index, request in enumerate(group.requests):
        needed = estimate_duration(request).total_s
        stretches = [
            s for s in observable_stretches(request, site, start, end, step=step) if _length(s) >= needed
        ]
        if all(_fits(window, stretches, needed) for window in request.windows):
            kept.append(request)
        elif stretches:
            windows = tuple(Window(start=a, end=b) for a, b in stretches)
            kept.append(request.model_copy(update={"windows": windows}))
            refitted.append(len(kept) - 1)
        else:
            dropped.append(index)
    fitted = group.model_copy(update={"requests": tuple(kept)}) if kept else None
    return NightFit(fitted, tuple(refitted), tuple(dropped))


def _alone(request: Request) -> RequestGroup:
    return RequestGroup(name="visibility", proposal="visibility", requests=(request,))


def _sun_allows(request: Request, sun_altitude: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
    """Slices with the Sun within every configuration's limits at both edges."""
    limits = [c.constraints for c in request.configurations]
    high = min(c.max_sun_altitude for c in limits)
    lows = [c.min_sun_altitude for c in limits if c.min_sun_altitude is not None]
    at_edges = sun_altitude <= high
    if lows:
        at_edges &= sun_altitude >= max(lows)
    return np.asarray(at_edges[:-1] & at_edges[1:], dtype=np.bool_)


def _runs(ok: npt.NDArray[np.bool_], grid: TimeGrid) -> list[Stretch]:
    """Consecutive True slices as (start, end) datetimes."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], ok.astype(np.int8), [0]))))
    return [
        (_utc(grid.start + a * grid.step), _utc(grid.start + b * grid.step)) for a, b in edges.reshape(-1, 2)
    ]


def _fits(window: Window, stretches: Sequence[Stretch], needed: float) -> bool:
    """Whether ``window`` holds ``needed`` seconds of one stretch."""
    return any(_length((max(a, window.start), min(b, window.end))) >= needed for a, b in stretches)


def _length(stretch: Stretch) -> float:
    return (stretch[1] - stretch[0]).total_seconds()


def _utc(unix_time: float) -> datetime:
    return datetime.fromtimestamp(unix_time, tz=UTC)
