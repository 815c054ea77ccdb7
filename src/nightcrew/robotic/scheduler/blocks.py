"""The scheduler's own input and output values: what to observe, in which night, and when.

These are deliberately small and free of the task model: a block source turns requests into
:class:`SchedulableBlock` values, so the scheduler can be tested (and benchmarked) on its own. A
placed block is a :class:`~nightcrew.robotic.planning.PlannedSlot`, the one shape of a planned task.
Every value is checked when it is built; a bad one raises :class:`InvalidArgumentError` naming the
block and the field. Times are aware ``datetime`` values (UTC or any other zone).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from datetime import datetime

from nightcrew.astro import julian_year
from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.site import Site

__all__ = ["Constraints", "Night", "SchedulableBlock", "Schedule", "Target"]


def _check_aware(value: datetime, what: str) -> None:
    if value.tzinfo is None or value.utcoffset() is None:
        raise InvalidArgumentError(f"{what} must be an aware datetime (with a time zone), got {value}")


@dataclass(frozen=True)
class Target:
    """A fixed sky position (ICRS) with optional proper motion.

    Args:
        ra: Right ascension in degrees at ``epoch``.
        dec: Declination in degrees at ``epoch``.
        pm_ra_cosdec: Proper motion in RA times cos(dec), milliarcseconds per year.
        pm_dec: Proper motion in Dec, milliarcseconds per year.
        epoch: Julian epoch of the position (e.g. 2000.0, 2016.0 for Gaia DR3).
    """

    ra: float
    dec: float
    pm_ra_cosdec: float = 0.0
    pm_dec: float = 0.0
    epoch: float = 2000.0

    def position_at(self, unix_time: float) -> tuple[float, float]:
        """(ra, dec) in degrees at ``unix_time``, moved along the proper motion (linear)."""
        years = julian_year(unix_time) - self.epoch
        dec = self.dec + self.pm_dec * years / 3.6e6
        cos_dec = max(math.cos(math.radians(self.dec)), 1e-9)
        ra = self.ra + self.pm_ra_cosdec * years / 3.6e6 / cos_dec
        return ra % 360.0, max(-90.0, min(90.0, dec))


@dataclass(frozen=True)
class Constraints:
    """Observing conditions a block needs; every slice of its observation must satisfy all.

    Args:
        max_airmass: Highest airmass (Kasten & Young) allowed, >= 1; ``math.inf``: no limit at all
            (for a stand-in target, e.g. of a calibration).
        max_sun_altitude: Highest altitude of the Sun in degrees (-12: nautical twilight).
        min_moon_distance: Smallest separation from the Moon in degrees.
        max_moon_illumination: Largest illuminated fraction of the Moon, 0..1.
    """

    max_airmass: float = 2.0
    max_sun_altitude: float = -12.0
    min_moon_distance: float = 0.0
    max_moon_illumination: float = 1.0

    def check(self, owner: str) -> None:
        """Raise InvalidArgumentError naming ``owner`` and the field if a limit is impossible."""
        if not self.max_airmass >= 1.0:
            raise InvalidArgumentError(f"{owner}: max_airmass must be >= 1, got {self.max_airmass}")
        if not -90.0 <= self.max_sun_altitude <= 90.0:
            raise InvalidArgumentError(
                f"{owner}: max_sun_altitude must be within -90..90, got {self.max_sun_altitude}"
            )
        if not 0.0 <= self.min_moon_distance <= 180.0:
            raise InvalidArgumentError(
                f"{owner}: min_moon_distance must be within 0..180, got {self.min_moon_distance}"
            )
        if not 0.0 <= self.max_moon_illumination <= 1.0:
            raise InvalidArgumentError(
                f"{owner}: max_moon_illumination must be within 0..1, got {self.max_moon_illumination}"
            )


@dataclass(frozen=True)
class SchedulableBlock:
    """One thing to observe in one go: the scheduler places it whole or not at all.

    Args:
        id: Unique name of the block (the task archive's id).
        priority: Weight > 0; the scheduler maximises the sum of priority x duration observed.
        duration_s: Time on target in seconds (exposures and read-outs), > 0.
        target: Where to point.
        constraints: Conditions that must hold during the whole block.
        windows: (start, end) intervals the block must lie within; empty: any time of the night.
        setup_s: Fixed overhead before the block (instrument set-up, acquisition), >= 0.
        first_filter: The filter its first exposure uses ("" unknown): a slew model charges a
            filter change when it differs from the block before's ``last_filter``.
        last_filter: The filter its last exposure uses.
        instrument: The instrument it uses ("" unknown): another one costs an instrument set-up.
        early_start_weight: 0..1: how much an early start is worth, as a fraction of the block's
            value gained by starting at the night's first moment rather than its last (for
            time-critical requests); 0: the start time does not matter.
    """

    id: str
    priority: float
    duration_s: float
    target: Target
    constraints: Constraints = field(default_factory=Constraints)
    windows: tuple[tuple[datetime, datetime], ...] = ()
    setup_s: float = 0.0
    first_filter: str = ""
    last_filter: str = ""
    instrument: str = ""
    early_start_weight: float = 0.0

    def __post_init__(self) -> None:
        owner = f"block {self.id!r}"
        if not 0.0 <= self.early_start_weight <= 1.0:
            raise InvalidArgumentError(
                f"{owner}: early_start_weight must be within 0..1, got {self.early_start_weight}"
            )
        if not self.id:
            raise InvalidArgumentError("a block needs a non-empty id")
        if not (math.isfinite(self.priority) and self.priority > 0):
            raise InvalidArgumentError(f"{owner}: priority must be > 0, got {self.priority}")
        if not (math.isfinite(self.duration_s) and self.duration_s > 0):
            raise InvalidArgumentError(f"{owner}: duration_s must be > 0, got {self.duration_s}")
        if not (math.isfinite(self.setup_s) and self.setup_s >= 0):
            raise InvalidArgumentError(f"{owner}: setup_s must be >= 0, got {self.setup_s}")
        if not -90.0 <= self.target.dec <= 90.0:
            raise InvalidArgumentError(f"{owner}: target dec must be within -90..90, got {self.target.dec}")
        if not math.isfinite(self.target.ra):
            raise InvalidArgumentError(f"{owner}: target ra must be finite, got {self.target.ra}")
        self.constraints.check(owner)
        object.__setattr__(self, "windows", tuple(tuple(w) for w in self.windows))
        for start, end in self.windows:
            _check_aware(start, f"{owner}: window start")
            _check_aware(end, f"{owner}: window end")
            if not start < end:
                raise InvalidArgumentError(f"{owner}: window start {start} is not before its end {end}")


@dataclass(frozen=True)
class Night:
    """The interval to schedule, and where.

    Args:
        start: First moment a block may start (e.g. the evening's sun set below the limit).
        end: Last moment a block may end.
        site: The observatory.
    """

    start: datetime
    end: datetime
    site: Site

    def __post_init__(self) -> None:
        _check_aware(self.start, "night start")
        _check_aware(self.end, "night end")
        if not self.start < self.end:
            raise InvalidArgumentError(f"night start {self.start} is not before its end {self.end}")


@dataclass(frozen=True)
class Schedule:
    """A solver's answer.

    Args:
        slots: Placed blocks (the block id is the task id), ordered by start.
        objective: Sum of priority x duration_s (hours) over placed blocks.
        bound: Upper bound on the objective the solver proved (MIP dual bound); None if it has none.
        solver: Which solver produced it ("mip", "priority").
        wall_time_s: Time the solver took, wall clock seconds.
        status: The solver's word on the result ("optimal", "time limit", ...).
    """

    slots: tuple[PlannedSlot, ...]
    objective: float
    bound: float | None
    solver: str
    wall_time_s: float
    status: str = "optimal"

    @property
    def gap(self) -> float | None:
        """(bound - objective) / bound, or None without a bound."""
        if self.bound is None:
            return None
        return 0.0 if self.bound <= 0 else max(0.0, (self.bound - self.objective) / self.bound)
