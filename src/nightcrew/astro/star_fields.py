"""Choosing a star field for focusing: near the pointing, high up, with enough stars of the right brightness.

A focus series needs a handful of stars that neither vanish in the noise nor saturate, and no very
bright star (whose blended halo swamps the detection). :func:`choose_star_fields` looks at the
catalogue stars around a pointing and returns the fields that qualify under :class:`StarFieldRules`,
nearest first (a short slew), each at least a field's diameter from the others (so the next is a
different field when one fails). Pure: catalogue arrays in, positions out; the caller loads the
catalogue.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.spatial import cKDTree  # type: ignore[import-untyped]

from nightcrew.astro.coords import radec_to_altaz
from nightcrew.errors import ConfigError

__all__ = ["BRIGHT_MARGIN", "StarField", "StarFieldRules", "StarMap", "choose_star_fields"]

FloatArray = npt.NDArray[np.float64]

BRIGHT_MARGIN = 1.5
"""A star brighter than the counted range rules out a field out to this many radii."""


@dataclass(frozen=True)
class StarFieldRules:
    """What makes a good focus field.

    Attributes:
        radius: Radius of the field, degrees (about half the camera's field of view).
        magnitudes: (brightest, faintest) catalogue magnitude of the stars that count; a star
            brighter than the brightest within :data:`BRIGHT_MARGIN` radii rules the field out.
        min_stars: Fewest counted stars in the field.
        min_altitude: Lowest altitude of the field's centre, degrees.
        max_distance: Farthest a field's centre may be from the pointing, degrees.
    """

    radius: float = 0.3
    magnitudes: tuple[float, float] = (6.0, 10.0)
    min_stars: int = 4
    min_altitude: float = 50.0
    max_distance: float = 30.0

    def __post_init__(self) -> None:
        bright, faint = self.magnitudes
        for key, good, text in (
            ("radius", 0.0 < self.radius <= 5.0, "within (0, 5] degrees"),
            (
                "magnitudes",
                math.isfinite(bright) and math.isfinite(faint) and bright < faint,
                "[bright, faint]",
            ),
            ("min_stars", self.min_stars >= 1, "at least 1"),
            ("min_altitude", 0.0 <= self.min_altitude < 90.0, "within [0, 90) degrees"),
            ("max_distance", self.radius <= self.max_distance <= 180.0, "within [radius, 180] degrees"),
        ):
            if not good:
                raise ConfigError(f"must be {text}, got {getattr(self, key)}", key=key)

    @classmethod
    def from_config(cls, config: Mapping[str, Any], key: str) -> StarFieldRules:
        """Rules from a YAML mapping; ConfigError naming ``key.<option>`` for a bad one."""
        known = {"radius", "magnitudes", "min_stars", "min_altitude", "max_distance"}
        unknown = sorted(set(config) - known)
        if unknown:
            raise ConfigError(f"unknown keys {unknown}; known: {', '.join(sorted(known))}", key=key)
        values = dict(config)
        if "magnitudes" in values:
            mags = values["magnitudes"]
            if not (isinstance(mags, Sequence) and len(mags) == 2 and all(_number(m) for m in mags)):
                raise ConfigError(
                    f"must be [bright, faint] magnitudes, got {mags!r}", key=f"{key}.magnitudes"
                )
            values["magnitudes"] = (float(mags[0]), float(mags[1]))
        for name in known - {"magnitudes"}:
            if name in values and not _number(values[name]):
                raise ConfigError(f"must be a number, got {values[name]!r}", key=f"{key}.{name}")
        try:
            return cls(**values)
        except ConfigError as exc:
            raise ConfigError(exc.message, key=f"{key}.{exc.key}") from None

    def describe(self) -> str:
        bright, faint = self.magnitudes
        return (
            f"{self.min_stars} stars of mag {bright:g}..{faint:g} (none brighter) within {self.radius:g}°, "
            f"above {self.min_altitude:g}° altitude, within {self.max_distance:g}° of the pointing"
        )


def _number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


@dataclass(frozen=True)
class StarField:
    """A field that qualifies: centre (ICRS, degrees), altitude, counted stars, distance from the pointing."""

    ra: float
    dec: float
    altitude: float
    stars: int
    distance: float


class StarMap:
    """Catalogue stars (ICRS degrees and magnitudes) as unit vectors, for counting stars in cones."""

    def __init__(self, ra: FloatArray, dec: FloatArray, mag: npt.NDArray[np.floating[Any]]) -> None:
        self.xyz = _unit(np.asarray(ra, np.float64), np.asarray(dec, np.float64))
        self.mag = np.asarray(mag, np.float64)


def _unit(ra: FloatArray, dec: FloatArray) -> FloatArray:
    r, d = np.radians(ra), np.radians(dec)
    return np.stack([np.cos(d) * np.cos(r), np.cos(d) * np.sin(r), np.sin(d)], axis=-1)


def _chord(angle_deg: float) -> float:
    return 2.0 * math.sin(math.radians(angle_deg) / 2.0)


def choose_star_fields(
    stars: StarMap,
    near: tuple[float, float],
    rules: StarFieldRules,
    *,
    latitude: float,
    longitude: float,
    unix_time: float,
    avoid: Sequence[tuple[float, float]] = (),
    limit: int = 5,
) -> list[StarField]:
    """Up to ``limit`` fields that qualify under ``rules``, nearest to ``near`` (ra, dec) first.

    Candidate centres lie on a grid one field radius apart around ``near``; fields within a
    diameter of a position in ``avoid`` (fields that failed) are left out, and every field returned
    is at least a diameter from the ones before it.
    """
    centre = _unit(np.array([near[0]]), np.array([near[1]]))[0]
    east = np.cross([0.0, 0.0, 1.0], centre)
    east = east / np.linalg.norm(east) if np.linalg.norm(east) > 1e-9 else np.array([0.0, 1.0, 0.0])
    north = np.cross(centre, east)
    half = math.tan(math.radians(min(rules.max_distance, 80.0)))
    steps = np.arange(-half, half + 1e-12, math.radians(rules.radius))
    gx, gy = np.meshgrid(steps, steps)
    points = centre + gx.reshape(-1, 1) * east + gy.reshape(-1, 1) * north  # gnomonic grid
    points /= np.linalg.norm(points, axis=1, keepdims=True)
    distance = np.degrees(np.arccos(np.clip(points @ centre, -1.0, 1.0)))
    points, distance = points[distance <= rules.max_distance], distance[distance <= rules.max_distance]
    ra = np.degrees(np.arctan2(points[:, 1], points[:, 0])) % 360.0
    dec = np.degrees(np.arcsin(np.clip(points[:, 2], -1.0, 1.0)))
    altitude, _ = radec_to_altaz(ra, dec, latitude, longitude, np.full(len(ra), unix_time))
    high = np.asarray(altitude) >= rules.min_altitude
    points, distance, ra, dec, altitude = points[high], distance[high], ra[high], dec[high], altitude[high]
    if avoid:
        failed = _unit(np.array([a[0] for a in avoid]), np.array([a[1] for a in avoid]))
        clear = cKDTree(failed).query(points, distance_upper_bound=_chord(2.0 * rules.radius))[0]
        keep = ~np.isfinite(clear)
        points, distance, ra, dec, altitude = (
            points[keep],
            distance[keep],
            ra[keep],
            dec[keep],
            altitude[keep],
        )
    if not len(points):
        return []
    # Only the stars of the searched cap, so the trees stay small.
    nearby = stars.xyz @ centre >= math.cos(math.radians(min(rules.max_distance + rules.radius, 180.0)))
    bright, faint = rules.magnitudes
    mag = stars.mag[nearby]
    counted, too_bright = stars.xyz[nearby][(mag >= bright) & (mag <= faint)], stars.xyz[nearby][mag < bright]
    reach = _chord(rules.radius)
    count = _count_within(counted, points, reach)
    # A too bright star just outside the field still sends its halo in (and the pointing errs).
    glare = _count_within(too_bright, points, _chord(BRIGHT_MARGIN * rules.radius))
    good = (count >= rules.min_stars) & (glare == 0)
    order = np.lexsort((-count, distance))
    chosen: list[StarField] = []
    for index in order[good[order]]:
        if any(_separation(points[index], (f.ra, f.dec)) < 2.0 * rules.radius for f in chosen):
            continue
        chosen.append(
            StarField(
                float(ra[index]),
                float(dec[index]),
                float(altitude[index]),
                int(count[index]),
                float(distance[index]),
            )
        )
        if len(chosen) >= limit:
            break
    return chosen


def _count_within(xyz: FloatArray, points: FloatArray, reach: float) -> npt.NDArray[np.int64]:
    if not len(xyz):
        return np.zeros(len(points), np.int64)
    return np.asarray(cKDTree(xyz).query_ball_point(points, reach, return_length=True), np.int64)


def _separation(point: FloatArray, radec: tuple[float, float]) -> float:
    other = _unit(np.array([radec[0]]), np.array([radec[1]]))[0]
    return math.degrees(math.acos(max(-1.0, min(1.0, float(point @ other)))))
