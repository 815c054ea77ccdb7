"""German-equatorial mount geometry: pier side, limits and the meridian flip, as pure functions.

Hour angles are in degrees, in (-180, 180], negative east of the meridian. The pier side follows
ASCOM's ``SideOfPier`` (:class:`~nightcrew.interfaces.PierSide`): EAST looks west of the meridian
with the counterweight down, WEST looks east. A mount keeps its side while it tracks, so a target
that crosses the meridian raises the counterweight: by ``+hour_angle`` on the west side, by
``-hour_angle`` on the east side. Beyond :attr:`GemLimits.counterweight_up` the tube meets the
pier; the mount must flip to the other side first (where the same target has its counterweight
down).

Mechanical axes (for slew times): the hour axis turns the dec axis; on the east side the hour
axis stands at ``hour_angle - 90`` and the dec axis at ``dec``; on the west side at
``hour_angle + 90`` and ``180 - dec`` (the dec axis has gone through the pole; ``-180 - dec`` for a
mount in the south, through the south pole). A flip to the same
target turns the hour axis by 180° and the dec axis through the pole.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nightcrew.astro.coords import j2000_to_of_date
from nightcrew.astro.time import local_sidereal_time
from nightcrew.interfaces.enums import PierSide

__all__ = [
    "SIDEREAL_RATE",
    "GemLimits",
    "counterweight_up",
    "destination_side",
    "hour_angle",
    "limit_edge",
    "limit_violation",
    "mechanical_axes",
    "seconds_until_limit",
]

#: How fast the hour angle of a fixed star grows, degrees per (SI) second.
SIDEREAL_RATE = 360.98564736629 / 86400.0


def hour_angle(ra: float, dec: float, longitude: float, unix_time: float) -> float:
    """Hour angle in (-180, 180] degrees of ICRS (ra, dec) at east ``longitude`` and the time."""
    ra_date, _ = j2000_to_of_date(ra, dec, unix_time)
    return _wrap(local_sidereal_time(unix_time, longitude) - ra_date)


def _wrap(angle: float) -> float:
    wrapped = -((-angle + 180.0) % 360.0 - 180.0)
    return 180.0 if wrapped == -180.0 else wrapped


@dataclass(frozen=True)
class GemLimits:
    """Where a German-equatorial mount may point.

    Attributes:
        east: Hour angle (degrees, negative) east of which the mount may not point, on either side.
        west: Hour angle (degrees, positive) west of which the mount may not point, on either side.
        counterweight_up: Degrees past the meridian the mount may track with its counterweight up
            (0..90) before the tube meets the pier.
    """

    east: float = -180.0
    west: float = 180.0
    counterweight_up: float = 15.0

    def __post_init__(self) -> None:
        for name in ("east", "west", "counterweight_up"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be a finite number of degrees, got {getattr(self, name)}")
        if self.east >= self.west:
            raise ValueError(
                f"east must be east of (less than) west, got east {self.east:g}° and west {self.west:g}°"
            )
        if not -180.0 <= self.east < 0.0:
            raise ValueError(f"east must be an hour angle east of the meridian (-180..0), got {self.east:g}°")
        if not 0.0 < self.west <= 180.0:
            raise ValueError(f"west must be an hour angle west of the meridian (0..180), got {self.west:g}°")
        if not 0.0 <= self.counterweight_up < 90.0:
            raise ValueError(f"counterweight_up must be within 0..90 degrees, got {self.counterweight_up:g}°")


def counterweight_up(ha: float, side: PierSide) -> float:
    """Degrees the counterweight is raised above horizontal's meridian position (<= 0: down)."""
    if side is PierSide.WEST:
        return ha
    if side is PierSide.EAST:
        return -ha
    raise ValueError(f"a mount on side {side} has no counterweight position")


def destination_side(ha: float) -> PierSide:
    """The side a slew to hour angle ``ha`` ends on: the one with the counterweight down."""
    return PierSide.EAST if ha >= 0.0 else PierSide.WEST


def limit_violation(ha: float, side: PierSide, limits: GemLimits) -> str | None:
    """Why pointing at hour angle ``ha`` on ``side`` breaks the limits, or None when it does not."""
    if ha < limits.east:
        return f"hour angle {ha:.2f}° is east of the limit {limits.east:g}°"
    if ha > limits.west:
        return f"hour angle {ha:.2f}° is west of the limit {limits.west:g}°"
    raised = counterweight_up(ha, side)
    if raised > limits.counterweight_up:
        return (
            f"counterweight {raised:.2f}° up on the {side} side of the pier, "
            f"beyond the limit of {limits.counterweight_up:g}°"
        )
    return None


def limit_edge(side: PierSide, limits: GemLimits) -> float:
    """The hour angle at which tracking on ``side`` passes a limit (hour angles only grow)."""
    return min(limits.west, limits.counterweight_up if side is PierSide.WEST else 180.0)


def seconds_until_limit(ha: float, side: PierSide, limits: GemLimits) -> float:
    """Seconds of sidereal tracking from hour angle ``ha`` on ``side`` until a limit is passed
    (0 if it is passed already)."""
    if limit_violation(ha, side, limits) is not None:
        return 0.0
    return (limit_edge(side, limits) - ha) / SIDEREAL_RATE


def mechanical_axes(ha: float, dec: float, side: PierSide, *, south: bool = False) -> tuple[float, float]:
    """(hour axis, dec axis) angles in degrees of a mount pointing at (ha, dec) from ``side``; a
    mount in the south (``south``) passes the south pole on the through-the-pole side."""
    if side is PierSide.EAST:
        return ha - 90.0, dec
    if side is PierSide.WEST:
        return ha + 90.0, (-180.0 if south else 180.0) - dec
    raise ValueError(f"a mount on side {side} has no axis angles")
