"""What a whole simulated night is, as pure functions: its span, its weather, its tasks' dates.

:func:`night_span` runs from the evening to the morning twilight (Sun at -3°, where the sky
flats may start), :func:`weather_scenario` gives the weather station's script for a named scenario
and :func:`shifted_group` moves the sample tasks (written for 2026-11-10) to another night.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from datetime import UTC, date, datetime, timedelta
from typing import Any

from nightcrew.astro import local_noon, sun_crossing
from nightcrew.robotic.tasks import RequestGroup, parse_request_group
from nightcrew.robotic.tasks.visibility import fit_to_night
from nightcrew.site import Site

log = logging.getLogger(__name__)

__all__ = [
    "SAMPLE_NIGHT",
    "WEATHER_SCENARIOS",
    "night_span",
    "samples_for_night",
    "shifted_group",
    "weather_scenario",
]

#: The night the bundled sample tasks are written for.
SAMPLE_NIGHT = date(2026, 11, 10)
#: Names of the weather scenarios ``nightcrew sim --weather`` knows.
WEATHER_SCENARIOS = ("clear", "interruption", "random")

_CLEAR: dict[str, Any] = {
    "temperature": 8.0,
    "humidity": 60.0,
    "wind_speed": 12.0,
    "clouds": 0.05,
    "rain": False,
}


def night_span(night: date, site: Site, sun_altitude_deg: float = -3.0) -> tuple[datetime, datetime]:
    """From the Sun sinking below ``sun_altitude_deg`` on the evening of ``night`` to it rising again.

    Raises:
        ValueError: the Sun does not set or rise through that altitude (polar day or night).
    """
    dusk = sun_crossing(site, local_noon(night, site.longitude), sun_altitude_deg, rising=False)
    dawn = sun_crossing(site, dusk, sun_altitude_deg, rising=True)
    return datetime.fromtimestamp(round(dusk), tz=UTC), datetime.fromtimestamp(round(dawn), tz=UTC)


def weather_scenario(name: str, duration: float) -> list[dict[str, Any]] | None:
    """The station's scenario (entries ``at`` seconds from the start) for ``name``; None: random.

    ``interruption`` clouds over towards the middle of the night, rains from there for an hour (a
    quarter of a short night) and clears 20 minutes later.

    Raises:
        ValueError: an unknown name.
    """
    if name == "clear":
        return [{"at": 0, **_CLEAR}, {"at": duration, "temperature": 4.0}]
    if name == "interruption":
        rain, wet = round(duration / 2.0), round(min(3600.0, duration / 4.0))
        return _increasing(
            [
                {"at": 0, **_CLEAR},
                {"at": rain - 900, "temperature": 6.0, "humidity": 75.0, "clouds": 0.3},
                {"at": rain - 300, "humidity": 92.0, "clouds": 0.9},
                {"at": rain, "rain": True, "humidity": 97.0},
                {"at": rain + wet, "rain": False, "humidity": 85.0, "clouds": 0.5},
                {"at": rain + wet + 1200, "humidity": 70.0, "clouds": 0.05},
                {"at": max(duration, rain + wet + 1260), "temperature": 4.0},
            ]
        )
    if name == "random":
        return None
    raise ValueError(f"unknown weather scenario {name!r} (known: {', '.join(WEATHER_SCENARIOS)})")


def one_window_each(group: RequestGroup) -> list[RequestGroup]:
    """``group`` once per window of its single request (twilight flats at dusk *and* at dawn).

    A task runs once, in one of its windows; a group whose request has several windows (the
    sample flats: evening and morning twilight) becomes one group per window, so both twilights
    get their flats. Other groups are returned as they are.
    """
    if len(group.requests) != 1 or len(group.requests[0].windows) < 2:
        return [group]
    request = group.requests[0]
    return [
        group.model_copy(update={"requests": (request.model_copy(update={"windows": (window,)}),)})
        for window in request.windows
    ]


def _increasing(entries: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """``entries`` without those not after the one before (a night too short for all of them)."""
    kept = [entries[0]]
    for entry in entries[1:]:
        if entry["at"] > kept[-1]["at"]:
            kept.append(entry)
    return kept


def shifted_group(group: RequestGroup, night: date) -> RequestGroup:
    """``group`` (written for :data:`SAMPLE_NIGHT`) with its windows moved to ``night``."""
    shift = timedelta(days=(night - SAMPLE_NIGHT).days)
    if not shift:
        return group
    requests = tuple(
        request.model_copy(
            update={
                "windows": tuple(
                    w.model_copy(update={"start": w.start + shift, "end": w.end + shift})
                    for w in request.windows
                )
            }
        )
        for request in group.requests
    )
    return group.model_copy(update={"requests": requests})


def samples_for_night(samples: Mapping[str, RequestGroup], night: date, site: Site) -> list[RequestGroup]:
    """``samples`` moved to ``night``, their windows refitted where their targets are not observable
    there (:func:`~nightcrew.robotic.tasks.visibility.fit_to_night`); what cannot be observed at all
    that night is left out with a warning."""
    start, end = night_span(night, site)
    groups: list[RequestGroup] = []
    for name, group in samples.items():
        fit = fit_to_night(shifted_group(group, night), site, start, end)
        if fit.dropped:
            which = "" if fit.group is None else f"requests {list(fit.dropped)} of "
            log.warning(
                "left out %ssample %s: not observable for long enough within its airmass and Sun "
                "limits on the night of %s",
                which, name, night,
            )  # fmt: skip
        if fit.refitted:
            log.info("sample %s: windows moved to where it is observable on %s", name, night)
        if fit.group is not None:
            groups.append(fit.group)
    return groups


def survey_groups(
    night: date, *, exposure_time: float = 300.0, count: int = 3, visits: int = 2
) -> list[RequestGroup]:
    """A low-priority survey of the well-known fields that fills the night between the samples.

    ``visits`` requests per field, any time of ``night``, each ``count`` exposures in V and in R,
    long enough that the shutter is open most of the time. The scheduler takes them where nothing
    better fits; visits of half an hour (not one of an hour per field) also fill the shorter gaps -
    after a task that ended early, before dawn - where the roof would otherwise close.
    """
    from nightcrew.night.fields import FAMOUS_FIELDS

    noon = datetime(night.year, night.month, night.day, 12, tzinfo=UTC)
    window = {"start": noon.isoformat(), "end": (noon + timedelta(days=1)).isoformat()}
    return [
        parse_request_group(
            {
                "name": f"Survey {field.name}" + (f" ({visit}/{visits})" if visits > 1 else ""),
                "proposal": "sim-survey",
                "priority": 0.5,
                "requests": [
                    {
                        "location": {"telescope_class": "0m4"},
                        "windows": [window],
                        "configurations": [
                            {
                                "type": "EXPOSE",
                                "target": {"name": field.name, "ra": field.ra, "dec": field.dec},
                                "constraints": {"max_airmass": 2.0},
                                "instrument_configs": [
                                    {
                                        "exposure_time": exposure_time,
                                        "exposure_count": count,
                                        "optical_elements": {"filter": name},
                                    }
                                    for name in ("V", "R")
                                ],
                            }
                        ],
                    }
                ],
            }
        )
        for field in FAMOUS_FIELDS
        for visit in range(1, visits + 1)
    ]
