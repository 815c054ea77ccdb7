"""Photometry of the simulated sky: star fluxes, twilight, moon and dark-sky background.

Units: magnitudes on the catalog's (Gaia G ~ V-like) scale; fluxes in photo-electrons per second
detected by the camera; sky brightness in mag/arcsec^2.

Zero point: a star of magnitude ``zero_point_mag`` above the atmosphere gives 1 e-/s through an
unfiltered system (throughput 1). For a 40 cm telescope with ~50 % total efficiency this is ~21.5.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = [
    "moon_sky_brightness_mag",
    "sky_brightness_mag",
    "sky_electrons_per_pixel_per_second",
    "star_electrons_per_second",
    "twilight_sky_brightness_mag",
]

FloatArray = npt.NDArray[np.float64]

DAYLIGHT_SUN_ALTITUDE_DEG = 0.0
"""Above this sun altitude the sky is held at its sunset brightness (frames saturate anyway)."""


def star_electrons_per_second(
    mag: npt.ArrayLike,
    *,
    zero_point_mag: float,
    throughput: float = 1.0,
    airmass: float = 1.0,
    extinction_mag_per_airmass: float = 0.2,
    transmission: float = 1.0,
) -> FloatArray:
    """Detected e-/s of stars: ``throughput * transmission * 10**(-0.4 (mag + k X - zp))``.

    ``throughput`` is the filter's (0..1), ``transmission`` the clouds' (0..1), ``k X`` the
    atmospheric extinction at airmass ``X``.
    """
    m = np.asarray(mag, dtype=np.float64) + extinction_mag_per_airmass * airmass
    return np.asarray(throughput * transmission * 10.0 ** (-0.4 * (m - zero_point_mag)), dtype=np.float64)


def twilight_sky_brightness_mag(
    sun_altitude_deg: float, *, mag_at_minus6: float = 12.0, fade_mag_per_deg: float = 1.0
) -> float:
    """Zenith brightness (mag/arcsec^2) of scattered sunlight alone.

    Model: linear in magnitudes with sun depression, ``m = mag_at_minus6 + fade * (-6 - h)``, i.e.
    ~12 mag/arcsec^2 at the end of civil twilight (sun at -6 deg) fading ~1 mag per degree through
    nautical twilight, so that by -18 deg it is ~3 mag below a dark sky and negligible. Held
    constant above the horizon. Added to the dark sky flux by :func:`sky_brightness_mag`.
    """
    h = min(sun_altitude_deg, DAYLIGHT_SUN_ALTITUDE_DEG)
    return mag_at_minus6 + fade_mag_per_deg * (-6.0 - h)


def moon_sky_brightness_mag(
    moon_altitude_deg: float, illumination: float, *, full_moon_zenith_mag: float = 18.0
) -> float:
    """Sky brightness (mag/arcsec^2) added by scattered moonlight; +inf when the moon is down.

    Simple model: flux ∝ illumination^1.5 * sin(moon altitude); a full moon at the zenith gives
    ``full_moon_zenith_mag`` (~18 in V). No dependence on the moon-target distance.
    """
    if moon_altitude_deg <= 0.0 or illumination <= 0.0:
        return math.inf
    factor = min(illumination, 1.0) ** 1.5 * math.sin(math.radians(moon_altitude_deg))
    return full_moon_zenith_mag - 2.5 * math.log10(factor)


def sky_brightness_mag(
    sun_altitude_deg: float,
    *,
    moon_altitude_deg: float = -90.0,
    moon_illumination: float = 0.0,
    dark_sky_mag: float = 21.0,
) -> float:
    """Total sky brightness (mag/arcsec^2): dark sky + twilight + moon, added as fluxes."""
    parts = [
        dark_sky_mag,
        twilight_sky_brightness_mag(sun_altitude_deg),
        moon_sky_brightness_mag(moon_altitude_deg, moon_illumination),
    ]
    flux = sum(10.0 ** (-0.4 * m) for m in parts if math.isfinite(m))
    return -2.5 * math.log10(flux)


def sky_electrons_per_pixel_per_second(
    sky_mag_arcsec2: float, *, zero_point_mag: float, pixel_area_arcsec2: float, throughput: float = 1.0
) -> float:
    """Detected sky e-/s in one pixel of ``pixel_area_arcsec2`` for a sky of the given brightness."""
    return float(throughput * pixel_area_arcsec2 * 10.0 ** (-0.4 * (sky_mag_arcsec2 - zero_point_mag)))
