"""Where a dome's slit must be so that a telescope off the dome's centre can see out. Pure geometry.

The telescope's optical axis starts at a pivot point (where the mount's axes cross) that is offset
from the centre of the dome's hemisphere; the slit must face the point where that axis meets the
dome, which is not straight along the telescope's azimuth unless the pivot is at the centre.
Coordinates are metres east, north and up from the dome centre; azimuths in degrees east of north.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nightcrew.errors import ConfigError

__all__ = ["DomeGeometry", "slit_azimuth"]


@dataclass(frozen=True)
class DomeGeometry:
    """A dome of ``radius`` metres with the telescope's pivot at (``east``, ``north``, ``up``) metres."""

    radius: float
    east: float = 0.0
    north: float = 0.0
    up: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.radius) and self.radius > 0):
            raise ConfigError(f"must be a positive number of metres, got {self.radius}", key="dome_radius")
        offset = math.hypot(self.east, self.north, self.up)
        if not offset < self.radius:
            raise ConfigError(
                f"the telescope pivot ({self.east}, {self.north}, {self.up}) m east/north/up is "
                f"{offset:.3f} m from the dome centre, not inside the {self.radius} m dome",
                key="mount_offset",
            )


def slit_azimuth(geometry: DomeGeometry, alt: float, az: float) -> float:
    """Azimuth (0..360 degrees) the slit must face for a telescope pointing at (``alt``, ``az``) degrees."""
    alt_rad, az_rad = math.radians(alt), math.radians(az)
    direction = (
        math.cos(alt_rad) * math.sin(az_rad),
        math.cos(alt_rad) * math.cos(az_rad),
        math.sin(alt_rad),
    )
    pivot = (geometry.east, geometry.north, geometry.up)
    # The axis is pivot + t * direction; it meets the sphere |p| = radius at the positive root t of
    # t² + 2 (pivot·direction) t + |pivot|² - radius² = 0 (one positive root: the pivot is inside).
    along = sum(p * d for p, d in zip(pivot, direction, strict=True))
    inside = geometry.radius**2 - sum(p * p for p in pivot)
    t = -along + math.sqrt(along * along + inside)
    east, north = pivot[0] + t * direction[0], pivot[1] + t * direction[1]
    if math.hypot(east, north) < 1e-9 * geometry.radius:
        return az % 360.0  # straight up through the dome's top: any azimuth sees out, keep the telescope's
    return math.degrees(math.atan2(east, north)) % 360.0
