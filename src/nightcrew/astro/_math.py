"""One formula for one time and for an array of times: the elementary functions, chosen by type.

Every formula of :mod:`nightcrew.astro` is written once, over :data:`Real` (a float, or a numpy
array of float64 that broadcasts), and takes its sine, cosine ... from an :class:`Elementary`:
:data:`SCALAR` (``math``) for a float, :data:`ARRAY` (numpy ufuncs) for an array. numpy on a lone
float costs about a microsecond a call, ~20x ``math``: single positions (the telescope, the
mastermind, the simulator at every step) take the scalar path, grids of times one array call.
Both give the same results to a few units in the last place.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np
import numpy.typing as npt

__all__ = ["ARRAY", "DEG", "SCALAR", "Elementary", "FloatArray", "Real", "elementary"]

FloatArray = npt.NDArray[np.float64]
#: A number, or an array of numbers: what every formula of the package computes with.
Real = TypeVar("Real", float, FloatArray)

#: Radians in a degree (a multiplication is cheaper than ``math.radians`` and works on arrays).
DEG = math.pi / 180.0


@dataclass(frozen=True)
class Elementary(Generic[Real]):
    """The elementary functions for one kind of :data:`Real`; ``asin`` clips its argument to ±1
    (rounding takes the sine of a pole or the zenith a bit beyond)."""

    sin: Callable[[Real | float], Real]
    cos: Callable[[Real | float], Real]
    asin: Callable[[Real], Real]
    atan2: Callable[[Real, Real], Real]
    hypot: Callable[[Real, Real], Real]


def _asin_float(x: float) -> float:
    return math.asin(min(1.0, max(-1.0, x)))


def _asin_array(x: FloatArray) -> FloatArray:
    # np.minimum/np.maximum: np.clip costs twice as much on small arrays.
    return np.arcsin(np.minimum(1.0, np.maximum(-1.0, x)))


SCALAR = Elementary[float](math.sin, math.cos, _asin_float, math.atan2, math.hypot)
ARRAY = Elementary[FloatArray](np.sin, np.cos, _asin_array, np.arctan2, np.hypot)


def elementary(x: Real) -> Elementary[Real]:
    """:data:`ARRAY` for a numpy array (also 0-d), else :data:`SCALAR` (float, int, numpy scalar)."""
    return ARRAY if isinstance(x, np.ndarray) else SCALAR
