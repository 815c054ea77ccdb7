"""Units and ranges of interface parameters, declared in the type hint.

A parameter's hint may carry its unit and bounds with :data:`typing.Annotated`::

    async def move_radec(self, ra: RightAscension, dec: Declination) -> None: ...
    async def set_exposure_time(self, exposure_time: Annotated[float, Ge(0), Unit("s")]) -> None: ...

Bounds are the ``annotated-types`` markers (``Ge``, ``Gt``, ``Le``, ``Lt``, ``Interval``), the
standard vocabulary pydantic also reads. The codec enforces them when a call arrives, before the
call's timeout is announced, so an out-of-range argument is refused at once; the catalogue
publishes them as JSON Schema ``minimum``/``maximum`` and the unit as ``x-unit``. Implementations
may keep plain ``float`` hints: the interface's declaration is what calls are checked against.

Configuration keys carry bounds the same way (the config validator reads them), and so do the
fields of a task's configuration: :func:`bound_problem` is the one check all three use. Besides
the bounds, :class:`Valid` declares a test a value must pass (e.g. :data:`TimeZoneName`).
"""

from __future__ import annotations

import math
import zoneinfo
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Annotated, Any

import annotated_types
from annotated_types import Ge, Interval

__all__ = [
    "MAX_EXPOSURE_TIME",
    "MIN_PERIOD",
    "Altitude",
    "Angle",
    "Azimuth",
    "Declination",
    "Degrees",
    "ExposureTime",
    "FocusCount",
    "FocusStep",
    "Gain",
    "GainOffset",
    "Period",
    "PeriodOrOff",
    "RightAscension",
    "Seconds",
    "SwitchIndex",
    "Temperature",
    "TimeZoneName",
    "Timeout",
    "Unit",
    "Valid",
    "bound_problem",
    "is_time_zone",
]


@dataclass(frozen=True)
class Unit:
    """The unit of a value, as a symbol: ``deg``, ``s``, ``degC``, ``%``, ``adu``."""

    symbol: str

    def __get_pydantic_json_schema__(self, core_schema: Any, handler: Any) -> dict[str, Any]:
        # pydantic builds the catalogue's JSON Schema; JSON Schema has no unit keyword.
        schema: dict[str, Any] = handler(core_schema)
        schema["x-unit"] = self.symbol
        return schema


@dataclass(frozen=True)
class Valid:
    """A test a value must pass, with what it then is (``an IANA time zone name``) for messages."""

    test: Callable[[Any], bool]
    expected: str


def is_time_zone(name: object) -> bool:
    """Whether ``name`` names a time zone of the IANA database (``Europe/Berlin``, ``UTC``)."""
    if not isinstance(name, str) or not name:
        return False
    try:
        zoneinfo.ZoneInfo(name)
    except (zoneinfo.ZoneInfoNotFoundError, ValueError, OSError):
        return False
    return True


# annotated-types bounds: (marker, attribute, symbol, holds). NaN holds none of them.
_BOUNDS: tuple[tuple[type[Any], str, str, Callable[[Any, Any], bool]], ...] = (
    (annotated_types.Ge, "ge", ">=", lambda v, b: v >= b),
    (annotated_types.Gt, "gt", ">", lambda v, b: v > b),
    (annotated_types.Le, "le", "<=", lambda v, b: v <= b),
    (annotated_types.Lt, "lt", "<", lambda v, b: v < b),
)


def bound_problem(value: Any, metadata: Iterable[Any]) -> str | None:
    """Why ``value`` breaks what ``metadata`` (an ``Annotated`` hint's extras) declares, else None.

    The answer completes a sentence about the value: ``is out of range (must be >= 0.01 s)``,
    ``is not an IANA time zone name``. ``None`` (an optional value left out) breaks nothing.
    """
    if value is None:
        return None
    items = list(metadata)
    unit = next((f" {item.symbol}" for item in items if isinstance(item, Unit)), "")
    for item in items:
        parts = list(item) if isinstance(item, annotated_types.GroupedMetadata) else [item]
        for part in parts:
            if isinstance(part, Valid):
                if not part.test(value):
                    return f"is not {part.expected}"
                continue
            for kind, attribute, symbol, holds in _BOUNDS:
                if isinstance(part, kind):
                    bound = getattr(part, attribute)
                    if not _holds(holds, value, bound):
                        return f"is out of range (must be {symbol} {bound!r}{unit})"
    return None


def _holds(holds: Callable[[Any, Any], bool], value: Any, bound: Any) -> bool:
    if isinstance(value, float) and math.isnan(value):
        return False
    try:
        return holds(value, bound)
    except TypeError:  # a value of another type: the type check, not the bound, refuses it
        return True


Degrees = Annotated[float, Unit("deg")]
RightAscension = Annotated[float, Interval(ge=0.0, lt=360.0), Unit("deg")]
Declination = Annotated[float, Interval(ge=-90.0, le=90.0), Unit("deg")]
Altitude = Annotated[float, Interval(ge=-90.0, le=90.0), Unit("deg")]
#: An angle of a full turn or less either way (a position angle, a move by): more is a typo.
Angle = Annotated[float, Interval(ge=-360.0, le=360.0), Unit("deg")]
#: East of north; implementations wrap it into 0..360.
Azimuth = Angle
Seconds = Annotated[float, Ge(0.0), Unit("s")]

#: The longest exposure any camera takes: a day (a camera's ``max_exposure_time`` is lower).
MAX_EXPOSURE_TIME = 86_400.0
ExposureTime = Annotated[float, Interval(ge=0.0, le=MAX_EXPOSURE_TIME), Unit("s")]
#: The shortest period of a loop (polling, sweeping, sampling): shorter only burns a core.
MIN_PERIOD = 0.01
#: The period of a loop, a day at most (longer is a typo, and a timer that never fires).
Period = Annotated[float, Interval(ge=MIN_PERIOD, le=86_400.0), Unit("s")]


def _off_or_period(seconds: float) -> bool:
    return seconds == 0 or MIN_PERIOD <= seconds <= 86_400.0


#: How long to wait for an answer or a connection: a day at most (longer is a typo, and a wait
#: that never ends).
Timeout = Annotated[float, Interval(ge=MIN_PERIOD, le=86_400.0), Unit("s")]
#: A period where 0 turns the loop off (an archive that is not polled).
PeriodOrOff = Annotated[float, Valid(_off_or_period, "0 (off) or a period of 0.01..86400 s"), Unit("s")]
#: A temperature on Earth or in a cooled camera (the absolute zero and boiling water bound it).
Temperature = Annotated[float, Interval(ge=-273.15, le=100.0), Unit("degC")]
#: How many frames a focus series takes (a thousand would take all night).
FocusCount = Annotated[int, Interval(ge=1, le=1000)]
#: The distance between two frames of a focus series: a focuser's whole travel is well under 100 mm.
FocusStep = Annotated[float, Interval(gt=0.0, le=100.0), Unit("mm")]
#: A detector's gain in the camera's own units (ASCOM's are small integers; a million is no camera's).
Gain = Annotated[float, Interval(ge=0.0, le=1_000_000.0)]
#: A detector's offset (bias level) in the camera's own units, either way.
GainOffset = Annotated[float, Interval(ge=-1_000_000.0, le=1_000_000.0)]
#: The number of a switch (ASCOM's Id) or another device channel.
SwitchIndex = Annotated[int, Interval(ge=0, le=1_000_000)]
TimeZoneName = Annotated[str, Valid(is_time_zone, "an IANA time zone name such as 'Europe/Berlin'")]
