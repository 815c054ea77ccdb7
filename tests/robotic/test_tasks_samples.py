"""The bundled sample tasks: valid, about ten, and observable on the simulated night."""

from __future__ import annotations

import math
from datetime import timedelta
from pathlib import Path

import yaml

from nightcrew.astro import local_sidereal_time, sun_altitude
from nightcrew.robotic.samples import load_samples, sample_paths
from nightcrew.robotic.tasks import ConfigurationType, Request, Target, estimate_duration
from nightcrew.site import Site

SITE_FILE = Path(__file__).parents[2] / "src/nightcrew/night/observatory/shared/site.yaml"


def _site() -> Site:
    return Site(**yaml.safe_load(SITE_FILE.read_text(encoding="utf-8")))


def _altitude(site: Site, ra: float, dec: float, unix: float) -> float:
    # J2000 position, no precession: a degree or less in 2026, plenty for "is it up".
    hour_angle = math.radians(local_sidereal_time(unix, site.longitude) - ra)
    lat, d = math.radians(site.latitude), math.radians(dec)
    return math.degrees(
        math.asin(math.sin(lat) * math.sin(d) + math.cos(lat) * math.cos(d) * math.cos(hour_angle))
    )


def _observable_minutes(site: Site, request: Request) -> int:
    """Longest run of minutes inside a window during which every configuration's constraints hold."""
    best = 0
    for window in request.windows:
        run, t = 0, window.start
        while t < window.end:
            unix = t.timestamp()
            good = True
            for configuration in request.configurations:
                limits = configuration.constraints
                sun = sun_altitude(site.latitude, site.longitude, unix)
                good &= sun <= limits.max_sun_altitude
                good &= limits.min_sun_altitude is None or sun >= limits.min_sun_altitude
                if isinstance(configuration.target, Target):
                    altitude = _altitude(site, configuration.target.ra, configuration.target.dec, unix)
                    good &= altitude > 0 and 1 / math.sin(math.radians(altitude)) <= limits.max_airmass
            run = run + 1 if good else 0
            best = max(best, run)
            t += timedelta(minutes=1)
    return best


def test_about_ten_valid_samples_with_the_promised_mix() -> None:
    samples = load_samples()
    assert len(sample_paths()) == len(samples) == 10
    types = {c.type for g in samples.values() for r in g.requests for c in r.configurations}
    # PANEL_FLAT needs a flat panel, which the bundled observatory has not (docs/tasks.md).
    assert types == set(ConfigurationType) - {ConfigurationType.SCRIPT, ConfigurationType.PANEL_FLAT}


def test_every_sample_request_fits_its_window_on_the_simulated_night() -> None:
    site = _site()
    for name, group in load_samples().items():
        for index, request in enumerate(group.requests):
            needed = math.ceil(estimate_duration(request).total_s / 60)
            available = _observable_minutes(site, request)
            assert available >= needed, f"{name} request {index}: {available} min observable, {needed} needed"
