"""Where to point for twilight flats: high in the sky, opposite the Sun, never twice the same spot.

The twilight sky is most uniform about 80° high in the azimuth opposite the Sun (Chromey & Hasselbacher
1996); small dithers between the flats move the stars so that a median of the flats removes them.
"""

from __future__ import annotations

import math

__all__ = ["antisolar_position", "dither_offset"]

#: The golden angle spreads successive dithers evenly around the start.
_GOLDEN_ANGLE_DEG = 137.50776


def dither_offset(index: int, step_arcsec: float) -> tuple[float, float]:
    """The ``index``-th dither as (north-ish, east-ish) sky offsets in degrees; (0, 0) for index 0.

    Points of a sunflower spiral: radius ``step * sqrt(index)``, so every dither is about ``step``
    from its neighbours and the pattern stays compact.
    """
    if index <= 0 or step_arcsec <= 0:
        return 0.0, 0.0
    radius = step_arcsec / 3600.0 * math.sqrt(index)
    angle = math.radians(index * _GOLDEN_ANGLE_DEG)
    return radius * math.cos(angle), radius * math.sin(angle)


def antisolar_position(
    sun_azimuth: float, *, altitude: float = 80.0, index: int = 0, dither_arcsec: float = 0.0
) -> tuple[float, float]:
    """(alt, az) in degrees for the ``index``-th flat: ``altitude`` high, opposite the Sun, dithered.

    An azimuth offset shrinks on the sky by cos(alt), so it is divided by that to move the stars by
    the dither's full size.
    """
    dalt, dsky = dither_offset(index, dither_arcsec)
    alt = min(89.0, altitude + dalt)  # the zenith is a singularity of alt/az mounts
    az = (sun_azimuth + 180.0 + dsky / max(math.cos(math.radians(alt)), 0.05)) % 360.0
    return alt, az
