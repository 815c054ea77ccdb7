"""What a simulated night does, as pure functions: when it starts, which fields, which steps.

:func:`night_start` finds the end of astronomical twilight, :func:`choose_targets` picks the
highest of some well-known star fields at that time, and :func:`plan_night` lays out the steps
that :mod:`nightcrew.night.build` then runs against the simulated devices.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import UTC, date, datetime, timedelta
from typing import Literal

from nightcrew.astro import astronomical_dusk, local_noon, radec_to_altaz
from nightcrew.interfaces import ImageType
from nightcrew.site import Site

__all__ = ["FAMOUS_FIELDS", "Step", "Target", "choose_targets", "night_start", "plan_night"]


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

StepAction = Literal["prepare", "focus", "slew", "expose", "shutdown"]


@dataclass(frozen=True)
class Step:
    """One step of the night; ``target``/``filter_name``/``exposure_time``/``image_type`` where
    they apply (a bias or dark is an ``expose`` step without a target)."""

    action: StepAction
    target: Target | None = None
    filter_name: str | None = None
    exposure_time: float = 0.0
    image_type: ImageType = ImageType.OBJECT

    def describe(self) -> str:
        """A short text for progress lines."""
        if self.action == "prepare":
            return "open roof, initialise devices"
        if self.action == "focus":
            return "focus"
        if self.action == "shutdown":
            return "park telescope, close roof"
        if self.image_type is ImageType.BIAS:
            return "bias"
        if self.image_type is ImageType.DARK:
            return f"dark {self.exposure_time:g} s"
        name = self.target.name if self.target is not None else "?"
        if self.action == "slew":
            return f"slew to {name}"
        return f"{name}: {self.exposure_time:g} s in {self.filter_name or 'no filter'}"


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


def plan_night(
    targets: list[Target], filters: list[str | None], exposure_time: float, calibration_frames: int = 0
) -> list[Step]:
    """Calibration frames, prepare, focus, per target a slew and an exposure per filter, shut down.

    ``calibration_frames`` biases and as many darks of ``exposure_time`` come first, while the
    roof is still closed (as observers take them), so that the night can be reduced.
    """
    steps = [Step("expose", image_type=ImageType.BIAS) for _ in range(calibration_frames)]
    steps += [
        Step("expose", exposure_time=exposure_time, image_type=ImageType.DARK)
        for _ in range(calibration_frames)
    ]
    steps += [Step("prepare"), Step("focus")]
    for target in targets:
        steps.append(Step("slew", target))
        steps.extend(Step("expose", target, name, exposure_time) for name in filters)
    steps.append(Step("shutdown"))
    return steps
