"""Sample tasks moved to another night get windows in which they can be observed, or are left out.

The checks recompute target and Sun altitudes minute by minute with ``coords.radec_to_altaz`` and
the simulator's Sun, not with the scheduler's sky grid that :mod:`nightcrew.robotic.tasks.visibility`
uses, so they are independent of it (tolerance 0.5° for precession and refraction left out).
"""

from __future__ import annotations

import logging
from datetime import date, datetime, timedelta

import pytest

from nightcrew.astro import radec_to_altaz, sun_altitude
from nightcrew.night.plan import SAMPLE_NIGHT, night_span, samples_for_night, shifted_group
from nightcrew.robotic.samples import load_samples
from nightcrew.robotic.scheduler.constraints import altitude_for_airmass
from nightcrew.robotic.tasks import ConfigurationType, Request, Target, estimate_duration, parse_request_group
from nightcrew.robotic.tasks.visibility import fit_to_night
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")  # the sim's site
HALF_A_YEAR_LATER = date(2027, 5, 10)
TOLERANCE = 0.5  # degrees


def observable_at(request: Request, when: datetime) -> bool:
    """Sun and airmass limits of every configuration hold at ``when`` (the Moon is not checked)."""
    t = when.timestamp()
    sun = sun_altitude(SITE.latitude, SITE.longitude, t)
    for configuration in request.configurations:
        limits = configuration.constraints
        if sun > limits.max_sun_altitude + TOLERANCE:
            return False
        if limits.min_sun_altitude is not None and sun < limits.min_sun_altitude - TOLERANCE:
            return False
        if isinstance(configuration.target, Target):
            altitude, _ = radec_to_altaz(
                configuration.target.ra, configuration.target.dec, SITE.latitude, SITE.longitude, t
            )
            if altitude < altitude_for_airmass(limits.max_airmass) - TOLERANCE:
                return False
    return True


def longest_run(request: Request, start: datetime, end: datetime) -> float:
    """Seconds of the longest stretch within ``[start, end]`` observable at every minute."""
    best = run = 0.0
    when = start
    while when <= end:
        run = run + 60.0 if observable_at(request, when) else 0.0
        best = max(best, run - 60.0)
        when += timedelta(minutes=1)
    return best


def test_on_the_sample_night_the_samples_are_left_as_written() -> None:
    samples = load_samples()
    assert samples_for_night(samples, SAMPLE_NIGHT, SITE) == list(samples.values())


def test_half_a_year_later_every_window_left_is_observable_and_the_rest_is_reported(
    caplog: pytest.LogCaptureFixture,
) -> None:
    samples = load_samples()
    start, end = night_span(HALF_A_YEAR_LATER, SITE)

    # Merely shifting the dates leaves windows in which the targets never rise high enough.
    shifted = [r for g in samples.values() for r in shifted_group(g, HALF_A_YEAR_LATER).requests]
    needed = {id(r): estimate_duration(r).total_s for r in shifted}
    unobservable = [
        r for r in shifted if all(longest_run(r, w.start, w.end) < needed[id(r)] for w in r.windows)
    ]
    assert len(unobservable) >= 3

    with caplog.at_level(logging.WARNING, logger="nightcrew"):
        fitted = samples_for_night(samples, HALF_A_YEAR_LATER, SITE)

    kept = {g.name for g in fitted}
    left_out = sorted(g.name for g in samples.values() if g.name not in kept)
    assert left_out  # autumn targets are not up in a May night
    for group in fitted:
        for request in group.requests:
            seconds = estimate_duration(request).total_s
            assert any(longest_run(request, w.start, w.end) >= seconds for w in request.windows), group.name
    for name in left_out:
        (group,) = [g for g in samples.values() if g.name == name]
        assert all(longest_run(r, start, end) < estimate_duration(r).total_s for r in group.requests), name
    stems = {g.name: stem for stem, g in samples.items()}
    warned = " ".join(r.getMessage() for r in caplog.records if r.levelno == logging.WARNING)
    assert all(f"sample {stems[name]}: not observable" in warned for name in left_out), warned

    # Flats and calibrations stay, in the twilight and the night of that date.
    flats = [
        g for g in fitted if any(c.type is ConfigurationType.SKY_FLAT for c in g.requests[0].configurations)
    ]
    (flat_request,) = flats[0].requests
    assert len(flat_request.windows) == 2  # dusk and dawn
    for window in flat_request.windows:
        assert start <= window.start < window.end <= end
        assert (
            longest_run(flat_request, window.start, window.end)
            >= (window.end - window.start).total_seconds() - 120
        )


def request(target: dict[str, object], start: str, end: str) -> dict[str, object]:
    return {
        "location": {"telescope_class": "0m4"},
        "windows": [{"start": start, "end": end}],
        "configurations": [
            {
                "type": "EXPOSE",
                "target": target,
                "constraints": {"max_airmass": 2.0},
                "instrument_configs": [{"exposure_time": 60, "exposure_count": 10}],
            }
        ],
    }


def test_windows_are_kept_refitted_or_the_request_dropped() -> None:
    m31 = {"name": "M31", "ra": 10.68, "dec": 41.27}
    group = parse_request_group(
        {
            "name": "three",
            "proposal": "tests",
            "requests": [
                request(m31, "2026-11-10T18:00:00Z", "2026-11-10T23:00:00Z"),  # up: kept
                request(
                    {"name": "south", "ra": 10.0, "dec": -70.0},
                    "2026-11-10T18:00:00Z",
                    "2026-11-11T05:00:00Z",
                ),
                request(m31, "2026-11-10T10:00:00Z", "2026-11-10T14:00:00Z"),  # daylight: refitted
            ],
        }
    )
    start, end = night_span(SAMPLE_NIGHT, SITE)
    fit = fit_to_night(group, SITE, start, end)
    assert fit.dropped == (1,) and fit.refitted == (
        1,
    )  # indexes: dropped in the group, refitted in fit.group
    assert fit.group is not None
    kept, refitted = fit.group.requests
    assert kept == group.requests[0]
    (window,) = refitted.windows  # M31: from nautical dusk until it sinks below airmass 2
    assert start <= window.start and window.end <= end
    assert window.end - window.start > timedelta(hours=8)
    assert (
        longest_run(refitted, window.start, window.end) >= (window.end - window.start).total_seconds() - 120
    )
    # A quarter of an hour from Sun -3°: the Sun is not yet at -12° for any of them.
    short = fit_to_night(group, SITE, start, start + timedelta(minutes=15))
    assert short.group is None and short.dropped == (0, 1, 2)
