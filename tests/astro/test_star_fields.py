"""choose_star_fields: the nearest field with enough stars of the right brightness, none too bright."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from nightcrew.astro import altaz_to_radec, angular_separation, radec_to_altaz
from nightcrew.astro.star_fields import StarFieldRules, StarMap, choose_star_fields
from nightcrew.errors import ConfigError
from nightcrew.testing import SITE

T = 1_794_000_000.0  # a fixed night
ZENITH = altaz_to_radec(90.0, 0.0, SITE.latitude, SITE.longitude, T)


def cluster(
    ra: float, dec: float, mags: list[float], spread: float = 0.1
) -> list[tuple[float, float, float]]:
    """Stars around (ra, dec) within ``spread`` degrees (a fixed pattern, no randomness)."""
    angles = np.linspace(0.0, 2.0 * np.pi, len(mags), endpoint=False)
    return [
        (ra + spread * np.cos(a) / np.cos(np.radians(dec)), dec + spread * np.sin(a), m)
        for a, m in zip(angles, mags, strict=True)
    ]


def star_map(*clusters: list[tuple[float, float, float]]) -> StarMap:
    rows = np.array([row for c in clusters for row in c], dtype=np.float64)
    return StarMap(rows[:, 0], rows[:, 1], rows[:, 2])


def choose(stars: StarMap, near: tuple[float, float] = ZENITH, **rules: Any) -> list[tuple[float, float]]:
    fields = choose_star_fields(
        stars, near, StarFieldRules(**rules), latitude=SITE.latitude, longitude=SITE.longitude, unix_time=T
    )
    return [(f.ra, f.dec) for f in fields]


def offset(dec_offset: float) -> tuple[float, float]:
    return ZENITH[0], ZENITH[1] + dec_offset


def test_the_nearest_field_with_enough_stars_comes_first() -> None:
    near, far = offset(3.0), offset(-8.0)
    stars = star_map(cluster(*near, [8.0] * 5), cluster(*far, [8.0] * 6))
    fields = choose(stars)
    assert len(fields) == 2
    assert angular_separation(*fields[0], *near) < 0.3
    assert angular_separation(*fields[1], *far) < 0.3


def test_too_few_stars_too_faint_or_a_too_bright_one_rule_a_field_out() -> None:
    few, faint, glaring = offset(2.0), offset(-2.0), offset(5.0)
    stars = star_map(
        cluster(*few, [8.0] * 3),
        cluster(*faint, [11.0] * 8),  # fainter than the camera needs (rules: 6..10)
        [*cluster(*glaring, [8.0] * 6, spread=0.03), (*glaring, 2.0)],  # a 2nd-magnitude star
    )
    assert choose(stars) == []
    assert len(choose(stars, magnitudes=(6.0, 12.0))) == 1  # a deeper camera takes the faint one
    assert len(choose(stars, min_stars=3)) == 1


def test_fields_below_the_altitude_limit_or_too_far_are_left_out() -> None:
    low = altaz_to_radec(40.0, 180.0, SITE.latitude, SITE.longitude, T)
    far = offset(-25.0)
    stars = star_map(cluster(*low, [8.0] * 6), cluster(*far, [8.0] * 6))
    assert choose(stars, max_distance=20.0) == []
    (field,) = choose(stars)  # 25° away is within the default 30°; the low one stays out
    assert angular_separation(*field, *far) < 0.3
    field = choose(stars, near=low, min_altitude=30.0, max_distance=60.0)[0]
    alt, _ = radec_to_altaz(*field, SITE.latitude, SITE.longitude, T)
    assert alt == pytest.approx(40.0, abs=0.5)


def test_a_failed_field_is_avoided_and_fields_do_not_overlap() -> None:
    first, second = offset(1.0), offset(4.0)
    stars = star_map(cluster(*first, [8.0] * 30, spread=0.2), cluster(*second, [8.0] * 6))
    fields = choose_star_fields(
        stars, ZENITH, StarFieldRules(), latitude=SITE.latitude, longitude=SITE.longitude, unix_time=T
    )
    assert all(
        angular_separation(a.ra, a.dec, b.ra, b.dec) >= 0.6 - 1e-9
        for a in fields
        for b in fields
        if a is not b
    )
    again = choose_star_fields(
        stars,
        ZENITH,
        StarFieldRules(),
        latitude=SITE.latitude,
        longitude=SITE.longitude,
        unix_time=T,
        avoid=[(fields[0].ra, fields[0].dec)],
    )
    assert all(angular_separation(f.ra, f.dec, fields[0].ra, fields[0].dec) >= 0.6 for f in again)
    assert any(angular_separation(f.ra, f.dec, *second) < 0.3 for f in again)


@pytest.mark.parametrize(
    ("config", "message"),
    [
        ({"magnitudes": [10, 6]}, r"key 'focus_field.magnitudes': must be \[bright, faint\]"),
        ({"magnitudes": "bright"}, r"key 'focus_field.magnitudes': must be \[bright, faint\] magnitudes"),
        ({"radius": 0}, r"key 'focus_field.radius': must be within \(0, 5\] degrees, got 0"),
        ({"min_stars": 0}, r"key 'focus_field.min_stars': must be at least 1, got 0"),
        ({"max_distance": "far"}, r"key 'focus_field.max_distance': must be a number, got 'far'"),
        ({"size": 1}, r"key 'focus_field': unknown keys \['size'\]"),
    ],
)
def test_bad_rules_name_the_key(config: dict[str, object], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        StarFieldRules.from_config(config, "focus_field")
