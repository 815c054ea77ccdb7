"""The observatory's place on Earth."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Site"]


@dataclass(frozen=True)
class Site:
    """Where the observatory stands.

    Args:
        latitude: Geodetic latitude in degrees, north positive.
        longitude: Longitude in degrees, east positive.
        elevation: Height above sea level in metres, -500..9000 (the Dead Sea shore to Everest).
        name: Optional name of the site.
    """

    latitude: float
    longitude: float
    elevation: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        if not -90.0 <= self.latitude <= 90.0:
            raise ValueError(f"latitude must be within -90..90 degrees, got {self.latitude}")
        if not -180.0 <= self.longitude <= 360.0:
            raise ValueError(f"longitude must be within -180..360 degrees, got {self.longitude}")
        if not -500.0 <= self.elevation <= 9000.0:
            raise ValueError(f"elevation must be within -500..9000 metres, got {self.elevation}")
