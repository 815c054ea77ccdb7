"""Benchmark of nightcrew.astro: single positions, and loops over times against one array call.

Run: ``.venv/bin/python bench/astro.py [--repeat 7]``.

Every function of time takes one time (a float: computed with ``math``) or a numpy array of times
(one vectorised call). Each row of the first table times an old way and the new way in the same
run (best of ``--repeat``) and gives their ratio and the largest difference of the results:

- single calls: the formula through numpy on a lone value (a 0-d array: what every call cost while
  the package computed with numpy only) against the float path;
- loops over times: one scalar call per time, as the sky flats' twilight (every minute of a window)
  and ``SkyGrid`` (Sun and Moon at every edge of the scheduler's grid) did, against one array call.

The second table times the users whole, in the new way only: the scheduler's ``night_around``, its
``SkyGrid`` for 500 blocks over a 13-hour night in 5-min slices (157 edges), and the sky-flat block's
twilight of a 13-hour window. Targets (the code before the package was unified, on the event loop
of the simulated night): radec_to_altaz 7.5 us, sun_altitude 8 us, 780 minutes of Sun 6-10 ms,
night_around 1.9-3 ms, SkyGrid 7.6-11 ms.
"""

from __future__ import annotations

import argparse
import timeit
from collections.abc import Callable
from datetime import UTC, datetime
from typing import Any

import numpy as np
import numpy.typing as npt

from nightcrew.astro import (
    altaz_to_radec,
    moon_illumination,
    moon_radec,
    radec_to_altaz,
    sun_altitude,
)
from nightcrew.robotic.scheduler import Night
from nightcrew.robotic.scheduler.ports import night_around
from nightcrew.robotic.scheduler.sky import SkyGrid, TimeGrid
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks
from nightcrew.robotic.tasks.calibration import _blocking_twilights
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0)
LAT, LON = SITE.latitude, SITE.longitude
NIGHT = Night(datetime(2024, 1, 15, 17, 0, tzinfo=UTC), datetime(2024, 1, 16, 6, 0, tzinfo=UTC), SITE)
T = NIGHT.start.timestamp()
MINUTES = T + 60.0 * np.arange(780.0)  # the 13-hour night minute by minute
EDGES = TimeGrid.covering(T, NIGHT.end.timestamp(), 300.0).edges

Case = Callable[[], Any]
FloatArray = npt.NDArray[np.float64]


def _single(function: Callable[[Any], Any]) -> tuple[Case, Case, int]:
    """Old: the numpy path on a 0-d array; new: the float path."""
    zero_d = np.asarray(T)
    return (lambda: function(zero_d)), (lambda: function(T)), 1


def _loop(
    function: Callable[[Any], Any], times: np.ndarray[Any, np.dtype[np.float64]]
) -> tuple[Case, Case, int]:
    """Old: one call per time; new: one call for the array."""
    return (lambda: [function(float(t)) for t in times]), (lambda: function(times)), len(times)


COMPARED: dict[str, tuple[Case, Case, int]] = {
    "radec_to_altaz": _single(lambda t: radec_to_altaz(83.6, 22.0, LAT, LON, t)),
    "altaz_to_radec": _single(lambda t: altaz_to_radec(40.0, 120.0, LAT, LON, t)),
    "sun_altitude": _single(lambda t: sun_altitude(LAT, LON, t)),
    "moon_radec": _single(moon_radec),
    "moon_illumination": _single(moon_illumination),
    "sun_altitude, 780 minutes": _loop(lambda t: sun_altitude(LAT, LON, t), MINUTES),
    "Sun+Moon at 157 edges": _loop(
        lambda t: (sun_altitude(LAT, LON, t), moon_radec(t), moon_illumination(t)), EDGES
    ),
}

BLOCKS = synthetic_blocks(NIGHT, 500, seed=1)
GRID = TimeGrid.covering(T, NIGHT.end.timestamp(), 300.0)
WHOLE: dict[str, Case] = {
    "night_around (scheduler)": lambda: night_around(SITE, datetime(2024, 1, 15, 12, tzinfo=UTC)),
    "SkyGrid 500 blocks x 157": lambda: SkyGrid(GRID, SITE, BLOCKS),
    "twilights 13 h (sky flats)": lambda: _blocking_twilights.__wrapped__(
        SITE, NIGHT.start, NIGHT.end, -12.0, -3.0
    ),
}


def best_seconds(case: Case, repeat: int) -> float:
    """Best time of one call, over ``repeat`` rounds of enough calls for ~20 ms each."""
    number = max(1, int(0.02 / max(timeit.timeit(case, number=1), 1e-7)))
    return min(timeit.repeat(case, number=number, repeat=repeat)) / number


def _values(result: Any) -> FloatArray:
    """The numbers of a result in one order: leaf by leaf (a list holds one result per time)."""
    if isinstance(result, list):
        return np.array([_values(r) for r in result]).T.reshape(-1)
    if isinstance(result, tuple):
        return np.concatenate([_values(r) for r in result])
    return np.asarray(result, dtype=np.float64).reshape(-1)


def _largest_difference(old: Any, new: Any) -> float:
    """Largest |old - new| of the results (angles in degrees: wrapped at 360)."""
    difference = np.abs(_values(old) - _values(new))
    return float(np.minimum(difference, 360.0 - difference).max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="rounds per case (the best counts)")
    args = parser.parse_args()
    print(f"{'case':<28} {'old':>10} {'new':>10} {'old/new':>8} {'new/time':>9} {'max |diff|':>11}")
    for name, (old, new, times) in COMPARED.items():
        old_s, new_s = best_seconds(old, args.repeat), best_seconds(new, args.repeat)
        unit, scale = ("us", 1e6) if old_s < 1e-3 else ("ms", 1e3)
        print(
            f"{name:<28} {old_s * scale:>7.2f} {unit} {new_s * scale:>7.2f} {unit} {old_s / new_s:>7.1f}x "
            f"{new_s / times * 1e6:>6.2f} us {_largest_difference(old(), new()):>11.1e}"
        )
    print(f"\n{'whole (new)':<28} {'ms':>10}")
    for name, case in WHOLE.items():
        print(f"{name:<28} {best_seconds(case, args.repeat) * 1e3:>10.2f}")


if __name__ == "__main__":
    main()
