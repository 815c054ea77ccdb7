"""An array of times (and positions) gives what single calls give, to 1e-10 degrees, in one call.

The scalar path computes with ``math``, the array path with numpy ufuncs: the same formula, whose
results may differ in the last bits, never by more.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from nightcrew.astro import (
    altaz_to_radec,
    angular_separation,
    moon_altitude,
    moon_illumination,
    moon_radec,
    radec_to_altaz,
    sun_altaz,
    sun_altitude,
    sun_radec,
)
from nightcrew.site import Site

SITE = Site(latitude=-29.26, longitude=-70.73)
RNG = np.random.default_rng(11)
TIMES = RNG.uniform(946684800.0, 2082758400.0, 200)  # 2000 .. 2036
A, B = RNG.uniform(0.0, 360.0, 200), np.degrees(np.arcsin(RNG.uniform(-1.0, 1.0, 200)))
LAT, LON = SITE.latitude, SITE.longitude

#: Each takes a time, or arrays of one shape (times, and the positions of the same index).
CASES: dict[str, Callable[[Any, Any, Any], Any]] = {
    "sun_radec": lambda t, a, b: sun_radec(t),
    "sun_altitude": lambda t, a, b: sun_altitude(LAT, LON, t),
    "sun_altaz": lambda t, a, b: sun_altaz(SITE, t),
    "moon_radec": lambda t, a, b: moon_radec(t),
    "moon_altitude": lambda t, a, b: moon_altitude(LAT, LON, t),
    "moon_illumination": lambda t, a, b: moon_illumination(t),
    "radec_to_altaz": lambda t, a, b: radec_to_altaz(a, b, LAT, LON, t),
    "altaz_to_radec": lambda t, a, b: altaz_to_radec(b, a, LAT, LON, t),
    "angular_separation": lambda t, a, b: angular_separation(a, b, t % 360.0, b / 2.0),
}


def _rows(values: Any) -> np.ndarray[Any, np.dtype[np.float64]]:
    return np.array(values if isinstance(values, tuple) else (values,), dtype=np.float64)


@pytest.mark.parametrize("name", CASES)
def test_an_array_call_gives_the_single_calls(name: str) -> None:
    function = CASES[name]
    together = _rows(function(TIMES, A, B))
    single = np.array(
        [_rows(function(float(t), float(a), float(b))) for t, a, b in zip(TIMES, A, B, strict=True)]
    ).T
    assert together.shape == single.shape == (together.shape[0], len(TIMES))
    difference = np.abs(together - single)
    assert np.minimum(difference, 360.0 - difference).max() < 1e-10  # longitudes wrap at 360


@pytest.mark.parametrize("name", CASES)
def test_a_single_call_gives_floats(name: str) -> None:
    result = CASES[name](float(TIMES[0]), float(A[0]), float(B[0]))
    assert all(type(value) is float for value in (result if isinstance(result, tuple) else (result,)))
