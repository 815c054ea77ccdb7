"""Which master calibrates which frame: header keys, the selection rule and a bounded cache.

A frame is described by a :class:`FrameKey` read from its header (binning, filter, exposure time
and the night it belongs to). A master fits a frame when the binning is the same and, for a flat,
the filter too; among those the closest exposure time wins for darks (scaled linearly) and the
closest night for everything.
"""

from __future__ import annotations

import datetime as dt
import math
from collections import OrderedDict
from collections.abc import Hashable, Iterable, Mapping
from dataclasses import dataclass
from enum import StrEnum
from typing import Any, Generic, TypeVar

from astropy.io import fits  # type: ignore[import-untyped]

__all__ = [
    "TEMPERATURE_MARGIN",
    "CalibrationCache",
    "FrameKey",
    "MasterInfo",
    "MasterKind",
    "frame_key",
    "off_set_point",
    "select_master",
]

V = TypeVar("V")

#: °C a frame's CCD-TEMP may differ from its SET-TEMP and still calibrate or be calibrated.
TEMPERATURE_MARGIN = 0.5


class MasterKind(StrEnum):
    """Kinds of master calibration frames; ``IMAGETYP`` of a master is ``master_<kind>``."""

    BIAS = "bias"
    DARK = "dark"
    FLAT = "flat"

    @property
    def image_type(self) -> str:
        return f"master_{self.value}"


@dataclass(frozen=True)
class FrameKey:
    """How a frame was taken, as far as calibration cares."""

    binning: str
    filter: str | None
    exposure_s: float
    night: dt.date | None

    def for_kind(self, kind: MasterKind) -> FrameKey:
        """The part of the key that decides the master of ``kind`` (the cache key)."""
        return FrameKey(
            binning=self.binning,
            filter=self.filter if kind is MasterKind.FLAT else None,
            exposure_s=self.exposure_s if kind is MasterKind.DARK else 0.0,
            night=self.night,
        )


def frame_key(header: fits.Header) -> FrameKey:
    """The key of a frame from its header: XBINNING/YBINNING, FILTER, EXPTIME and DATE-OBS.

    The night is the date at the start of the night: DATE-OBS minus 12 hours (UTC), so a frame
    taken after midnight belongs to the same night as one taken before.
    """
    binning = (
        f"{_int(header.get('XBINNING'), 1)}x{_int(header.get('YBINNING'), _int(header.get('XBINNING'), 1))}"
    )
    name = header.get("FILTER")
    exposure = header.get("EXPTIME", 0.0)
    exposure_s = float(exposure) if isinstance(exposure, int | float) and math.isfinite(exposure) else 0.0
    return FrameKey(
        binning=binning,
        filter=str(name).strip() if name not in (None, "") else None,
        exposure_s=exposure_s,
        night=_night(header.get("DATE-OBS")),
    )


def off_set_point(header: Mapping[str, Any], margin: float = TEMPERATURE_MARGIN) -> bool:
    """Whether a frame was taken more than ``margin`` °C off its cooling set point.

    ``TEMP-OK = F`` (the camera's verdict) or CCD-TEMP and SET-TEMP further apart than ``margin``;
    a frame without a set point (an uncooled camera) is never off it.
    """
    if header.get("TEMP-OK") is False:
        return True
    temperature, setpoint = header.get("CCD-TEMP"), header.get("SET-TEMP")
    if not (isinstance(temperature, int | float) and isinstance(setpoint, int | float)):
        return False
    return not abs(float(temperature) - float(setpoint)) <= margin


@dataclass(frozen=True)
class MasterInfo:
    """A master available for calibration: where it is, what it is and how it was taken."""

    path: str
    kind: MasterKind
    key: FrameKey


def select_master(masters: Iterable[MasterInfo], kind: MasterKind, key: FrameKey) -> MasterInfo | None:
    """The best master of ``kind`` for a frame of ``key`` (see the module docstring), or None."""
    fitting = [
        m
        for m in masters
        if m.kind is kind
        and m.key.binning == key.binning
        and (kind is not MasterKind.FLAT or m.key.filter == key.filter)
    ]

    def distance(m: MasterInfo) -> tuple[float, float, str]:
        exposure = abs(m.key.exposure_s - key.exposure_s) if kind is MasterKind.DARK else 0.0
        nights = abs((m.key.night - key.night).days) if m.key.night and key.night else math.inf
        return exposure, nights, m.path

    return min(fitting, key=distance, default=None)


class CalibrationCache(Generic[V]):
    """A least-recently-used cache of at most ``max_entries`` values (masters are large)."""

    def __init__(self, max_entries: int = 8) -> None:
        if max_entries < 1:
            raise ValueError(f"max_entries must be >= 1, got {max_entries}")
        self.max_entries = max_entries
        self._entries: OrderedDict[Hashable, V] = OrderedDict()

    def __len__(self) -> int:
        return len(self._entries)

    def get(self, key: Hashable) -> V | None:
        value = self._entries.get(key)
        if value is not None:
            self._entries.move_to_end(key)
        return value

    def put(self, key: Hashable, value: V) -> None:
        self._entries[key] = value
        self._entries.move_to_end(key)
        while len(self._entries) > self.max_entries:
            self._entries.popitem(last=False)

    def clear(self) -> None:
        self._entries.clear()


def _int(value: Any, default: int) -> int:
    return (
        int(value)
        if isinstance(value, int | float) and not isinstance(value, bool) and value >= 1
        else default
    )


def _night(value: Any) -> dt.date | None:
    if not isinstance(value, str):
        return None
    try:
        start = dt.datetime.fromisoformat(value.strip().replace("Z", ""))
    except ValueError:
        return None
    return (start - dt.timedelta(hours=12)).date()
