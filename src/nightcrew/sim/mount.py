"""A simulated mount's imperfections, as pure functions of the slew and the clock time.

After every slew the mount misses its target by a random *pointing error* (Gaussian, per axis);
while tracking it *drifts* linearly in a direction drawn per slew, and its worm gear adds a
*periodic error* in RA that depends on absolute time (so it continues across slews, as in a real
gear). Offsets are on-sky degrees (east, north); :func:`apply_sky_offset` turns them into RA/Dec.
Injected *pointing terms* (:func:`pointing_terms_model`, the truth a fitted pointing model should
recover) move where the mount really points as a function of the commanded hour angle and
declination (:meth:`PointingModel.to_sky_icrs`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nightcrew.astro.pointing import PointingModel
from nightcrew.interfaces.enums import PierSide

__all__ = [
    "MountErrorModel",
    "PierCollision",
    "SlewError",
    "apply_sky_offset",
    "axes_slew_time",
    "pointing_terms_model",
    "slew_time",
]


def slew_time(distance: float, rate: float, settle_time: float = 0.0) -> float:
    """Seconds a slew of ``distance`` degrees takes at ``rate`` deg/s, plus settling (0 if no move)."""
    if rate <= 0:
        raise ValueError(f"slew rate must be > 0 deg/s, got {rate}")
    if distance <= 0:
        return 0.0
    return distance / rate + settle_time


def axes_slew_time(
    start: tuple[float, float], end: tuple[float, float], rate: float, settle_time: float = 0.0
) -> float:
    """Seconds a mount whose two axes turn at once at ``rate`` deg/s takes between axis angles
    ``start`` and ``end`` (degrees; see :func:`nightcrew.astro.pier.mechanical_axes`)."""
    return slew_time(max(abs(end[0] - start[0]), abs(end[1] - start[1])), rate, settle_time)


@dataclass(frozen=True)
class PierCollision:
    """A German-equatorial mount passed one of its limits (on a real one, the tube met the pier).

    Attributes:
        time: Unix time the limit was passed.
        hour_angle: Hour angle of the pointing then, degrees.
        side: Side of the pier the mount was on.
        reason: Which limit, in words.
    """

    time: float
    hour_angle: float
    side: PierSide
    reason: str


@dataclass(frozen=True)
class SlewError:
    """What went wrong in one slew: the miss (on-sky degrees) and the drift direction (radians)."""

    east: float
    north: float
    drift_angle: float


@dataclass(frozen=True)
class MountErrorModel:
    """How imperfect the mount is.

    Attributes:
        pointing_error: RMS miss per axis after a slew, arcminutes.
        drift_rate: Tracking drift, arcseconds per minute.
        periodic_amplitude: Amplitude of the RA periodic error, arcseconds.
        periodic_period: Worm period, seconds.
    """

    pointing_error: float = 1.0
    drift_rate: float = 1.0
    periodic_amplitude: float = 5.0
    periodic_period: float = 480.0

    def __post_init__(self) -> None:
        for name in ("pointing_error", "drift_rate", "periodic_amplitude"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if not self.periodic_period > 0:
            raise ValueError(f"periodic_period must be > 0 s, got {self.periodic_period}")

    def draw_slew_error(self, rng: np.random.Generator) -> SlewError:
        """The miss of one slew (call once per slew, with the mount's seeded generator)."""
        east, north = rng.normal(0.0, self.pointing_error / 60.0, size=2)
        return SlewError(float(east), float(north), float(rng.uniform(0.0, 2.0 * math.pi)))

    def offset(self, error: SlewError, tracked_seconds: float, unix_time: float) -> tuple[float, float]:
        """On-sky (east, north) degrees between true and reported pointing."""
        drift = self.drift_rate / 3600.0 * max(0.0, tracked_seconds) / 60.0
        periodic = (
            self.periodic_amplitude / 3600.0 * math.sin(2.0 * math.pi * unix_time / self.periodic_period)
        )
        east = error.east + drift * math.cos(error.drift_angle) + periodic
        north = error.north + drift * math.sin(error.drift_angle)
        return east, north


def apply_sky_offset(ra: float, dec: float, east: float, north: float) -> tuple[float, float]:
    """(ra, dec) moved by small on-sky offsets in degrees (east scaled by 1/cos dec)."""
    new_dec = max(-90.0, min(90.0, dec + north))
    cos_dec = max(math.cos(math.radians(new_dec)), 1e-6)
    return (ra + east / cos_dec) % 360.0, new_dec


def pointing_terms_model(mount: str, latitude: float, terms: dict[str, float]) -> PointingModel:
    """The injected pointing terms (arcsec, by TPoint name) as a model; PointingModelError for an
    unknown name."""
    return PointingModel(mount, latitude, {str(name): float(value) for name, value in terms.items()})
