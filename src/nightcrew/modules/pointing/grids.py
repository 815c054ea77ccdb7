"""The points of a pointing series: rows of an alt/az grid, or points spread evenly over the sky."""

from __future__ import annotations

import math

__all__ = ["pointing_grid", "sky_grid"]


def pointing_grid(
    alt_range: tuple[float, float], alt_steps: int, az_steps: int, min_altitude: float = 0.0
) -> list[tuple[float, float]]:
    """The (alt, az) points of a series, in the order to visit them (degrees).

    ``alt_steps`` rows evenly from ``alt_range[0]`` to ``alt_range[1]`` (both included), each with
    ``az_steps`` azimuths evenly around the horizon; every other row is shifted by half an azimuth
    step (the rows interleave instead of lining up) and run backwards (shorter slews between rows).
    Points below ``min_altitude`` are left out.
    """
    low, high = alt_range
    alts = [low] if alt_steps == 1 else [low + (high - low) * i / (alt_steps - 1) for i in range(alt_steps)]
    step = 360.0 / az_steps
    points: list[tuple[float, float]] = []
    for row, alt in enumerate(alts):
        azimuths = [(step * (i + 0.5 * (row % 2))) % 360.0 for i in range(az_steps)]
        if row % 2:
            azimuths.reverse()
        points.extend((alt, az) for az in azimuths if alt >= min_altitude)
    return points


def sky_grid(count: int, min_altitude: float, max_altitude: float = 85.0) -> list[tuple[float, float]]:
    """``count`` (alt, az) points spread evenly over the sky between the altitudes (degrees).

    Equal-area (a Fibonacci spiral: sin(alt) evenly spaced, azimuths a golden angle apart), then
    visited in altitude bands, every other band backwards (short slews).
    """
    golden = 180.0 * (3.0 - math.sqrt(5.0))
    low, high = math.sin(math.radians(min_altitude)), math.sin(math.radians(max_altitude))
    points = [
        (math.degrees(math.asin(low + (high - low) * (i + 0.5) / count)), (golden * i) % 360.0)
        for i in range(count)
    ]
    bands = max(1, round(math.sqrt(count / 4.0)))
    size = -(-count // bands)
    ordered: list[tuple[float, float]] = []
    for band in range(bands):
        row = sorted(points[band * size : (band + 1) * size], key=lambda p: p[1], reverse=band % 2 == 1)
        ordered.extend((round(alt, 4), round(az, 4)) for alt, az in row)
    return ordered
