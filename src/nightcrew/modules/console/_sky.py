"""Sky facts for the pages: the Sun's altitude along the night, where the Sun and Moon are now."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from typing import Any

import numpy as np

from nightcrew.astro.coords import radec_to_altaz
from nightcrew.astro.moon import moon_illumination, moon_radec
from nightcrew.astro.sun import sun_altaz, sun_altitude
from nightcrew.site import Site

__all__ = ["SUN_CURVE_STEP", "sky_now", "sun_curve"]

SUN_CURVE_STEP = timedelta(minutes=5)


def sun_curve(
    site: Site, start: datetime, end: datetime, step: timedelta = SUN_CURVE_STEP
) -> list[dict[str, Any]]:
    """The Sun's altitude (degrees) every ``step`` from ``start`` to ``end`` (both included)."""
    if end < start:
        return []
    count = int((end - start) / step) + 1
    times = start.timestamp() + np.arange(count, dtype=np.float64) * step.total_seconds()
    altitudes = sun_altitude(site.latitude, site.longitude, times)
    return [
        {"time": datetime.fromtimestamp(float(t), UTC).isoformat(), "altitude": round(float(a), 3)}
        for t, a in zip(times, np.asarray(altitudes), strict=True)
    ]


def sky_now(site: Site, now: datetime) -> dict[str, Any]:
    """Where the Sun and the Moon are at ``now`` (alt/az in degrees, az east of north)."""
    t = now.timestamp()
    sun_alt, sun_az = sun_altaz(site, t)
    moon_alt, moon_az = radec_to_altaz(*moon_radec(t), site.latitude, site.longitude, t)
    return {
        "time": now.isoformat(),
        "sun": {"alt": float(sun_alt), "az": float(sun_az)},
        "moon": {"alt": float(moon_alt), "az": float(moon_az), "illumination": float(moon_illumination(t))},
    }
