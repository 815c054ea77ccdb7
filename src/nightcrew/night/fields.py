"""Where a simulated night looks, as pure functions: when it starts, which fields, the quick preset.

:func:`night_start` finds the end of astronomical twilight, :func:`choose_targets` picks the
highest of some well-known star fields at that time, and :func:`quick_groups` makes the short task
list of ``nightcrew sim --quick``: the same scheduler and mastermind run it as the whole night.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import UTC, date, datetime, timedelta
from typing import Any

from nightcrew.astro import astronomical_dusk, local_noon, radec_to_altaz
from nightcrew.robotic.tasks import RequestGroup, parse_request_group
from nightcrew.site import Site

__all__ = ["FAMOUS_FIELDS", "Target", "choose_targets", "night_start", "quick_groups"]


@dataclass(frozen=True)
class Target:
    """A field to observe: a name and the ICRS centre in degrees."""

    name: str
    ra: float
    dec: float


#: Well-known fields, most of them star clusters in the Milky Way: rich enough in real (catalog)
#: stars for a plate solver, spread over the year so that some are high on any night.
FAMOUS_FIELDS: tuple[Target, ...] = (
    Target("M39", 322.95, 48.43),
    Target("Sadr", 305.56, 40.26),
    Target("M52", 351.20, 61.59),
    Target("Double Cluster", 34.75, 57.13),
    Target("M103", 23.34, 60.66),
    Target("Pleiades", 56.75, 24.12),
    Target("M37", 88.07, 32.55),
    Target("M35", 92.25, 24.33),
    Target("Praesepe", 130.10, 19.67),
    Target("M67", 132.85, 11.81),
    Target("M13", 250.42, 36.46),
    Target("Albireo", 292.68, 27.96),
    Target("M27", 299.90, 22.72),
    Target("M11", 282.77, -6.27),
)


def night_start(night: date, site: Site, after_dusk: timedelta = timedelta(minutes=15)) -> datetime:
    """A start time on the evening of ``night``: astronomical dusk plus ``after_dusk``, whole minutes.

    Where the Sun never sinks below -18° (summer at high latitudes) the night starts at local solar
    midnight, the darkest it gets.
    """
    try:
        dusk = astronomical_dusk(night, site)
        start = datetime.fromtimestamp(dusk, tz=UTC) + after_dusk
    except ValueError:
        start = datetime.fromtimestamp(local_noon(night, site.longitude), tz=UTC) + timedelta(hours=12)
    return start.replace(second=0, microsecond=0) + timedelta(minutes=1)


def choose_targets(
    site: Site,
    unix_time: float,
    count: int,
    *,
    min_altitude: float = 35.0,
    candidates: tuple[Target, ...] = FAMOUS_FIELDS,
) -> list[Target]:
    """The ``count`` highest candidates above ``min_altitude``, in order of azimuth (short slews).

    Raises:
        ValueError: no candidate is that high at that time.
    """
    altaz = [(radec_to_altaz(t.ra, t.dec, site.latitude, site.longitude, unix_time), t) for t in candidates]
    up = sorted(((alt, az, t) for (alt, az), t in altaz if alt >= min_altitude), key=lambda x: -x[0])
    if not up:
        raise ValueError(f"none of the {len(candidates)} fields is above {min_altitude}° at that time")
    chosen = up[:count]
    return [t for _, _, t in sorted(chosen, key=lambda x: x[1])]


def quick_groups(
    targets: list[Target],
    filters: list[str],
    exposure_time: float,
    *,
    start: datetime,
    end: datetime,
    calibration_frames: int = 0,
) -> list[RequestGroup]:
    """The ``--quick`` task list: biases and darks (``calibration_frames`` each), then one exposure
    per filter of each target, all to be done between ``start`` and ``end``.

    The calibration frames come first in priority, so that the night can be reduced; the scheduler
    decides when each task runs, as on any night.
    """
    window = [{"start": start.isoformat(), "end": end.isoformat()}]
    groups: list[dict[str, Any]] = []
    if calibration_frames > 0:
        groups.append(
            {
                "name": "Quick bias and darks",
                "proposal": "sim-quick",
                "priority": 10.0,
                "requests": [
                    {
                        "location": {"telescope_class": "0m4"},
                        "windows": window,
                        "configurations": [
                            {
                                "type": kind,
                                "constraints": {"max_sun_altitude": 90},
                                "instrument_configs": [
                                    {"exposure_time": seconds, "exposure_count": calibration_frames}
                                ],
                            }
                            for kind, seconds in (("BIAS", 0.0), ("DARK", exposure_time))
                        ],
                    }
                ],
            }
        )
    for target in targets:
        groups.append(
            {
                "name": f"Quick {target.name}",
                "proposal": "sim-quick",
                "priority": 5.0,
                "requests": [
                    {
                        "location": {"telescope_class": "0m4"},
                        "windows": window,
                        "configurations": [
                            {
                                "type": "EXPOSE",
                                "target": {"name": target.name, "ra": target.ra, "dec": target.dec},
                                "constraints": {"max_airmass": 3.0},
                                "instrument_configs": [
                                    {
                                        "exposure_time": exposure_time,
                                        "exposure_count": 1,
                                        "optical_elements": {"filter": name},
                                    }
                                    for name in filters
                                ],
                            }
                        ],
                    }
                ],
            }
        )
    return [parse_request_group(group) for group in groups]
