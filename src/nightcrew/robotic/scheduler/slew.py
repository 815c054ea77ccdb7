"""How long the telescope takes from one block to the next: slew, dome, filter and instrument.

Pure and vectorised: positions in, seconds out. Both axes (hour angle and declination on an
equatorial mount, azimuth and altitude on an alt-az one) and the dome turn at once, each with a
trapezoidal speed profile (accelerate, cruise at its rate, decelerate; a short move never reaches
the rate); the slowest of them, then the settling, then a filter change where the filters differ
and an instrument set-up where the instruments differ. The scheduler prices transitions with it,
and the mastermind judges with it whether a block still fits before its constraints end, so both
count the same seconds.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from nightcrew.astro import local_sidereal_time, radec_to_altaz
from nightcrew.errors import InvalidArgumentError
from nightcrew.site import Site

__all__ = ["AxisMotion", "Pointing", "SlewModel"]

FloatArray = npt.NDArray[np.float64]
Mount = Literal["equatorial", "altaz"]


@dataclass(frozen=True)
class AxisMotion:
    """One axis: top ``rate`` (deg/s) reached with ``acceleration`` (deg/s², inf: at once)."""

    rate: float
    acceleration: float = math.inf

    def __post_init__(self) -> None:
        if not (math.isfinite(self.rate) and self.rate > 0):
            raise InvalidArgumentError(f"an axis rate must be > 0 deg/s, got {self.rate}")
        if not self.acceleration > 0:
            raise InvalidArgumentError(f"an axis acceleration must be > 0 deg/s², got {self.acceleration}")

    def seconds(self, distance: npt.ArrayLike) -> FloatArray:
        """Seconds to turn by ``distance`` degrees (any shape), from rest to rest."""
        d = np.abs(np.asarray(distance, dtype=np.float64))
        if math.isinf(self.acceleration):
            return d / self.rate
        ramp = self.rate * self.rate / self.acceleration  # degrees spent speeding up and slowing down
        short = 2.0 * np.sqrt(d / self.acceleration)
        return np.where(d < ramp, short, d / self.rate + self.rate / self.acceleration)


@dataclass(frozen=True)
class Pointing:
    """Where a block points and with what: J2000 (ra, dec), first and last filter, instrument."""

    ra: float
    dec: float
    first_filter: str = ""
    last_filter: str = ""
    instrument: str = ""


def _turn(a: npt.ArrayLike, b: npt.ArrayLike) -> FloatArray:
    """Shortest turn in degrees between angles (an axis that turns freely)."""
    return np.asarray(np.abs((np.asarray(b) - np.asarray(a) + 180.0) % 360.0 - 180.0), dtype=np.float64)


def _altaz(site: Site, ra: FloatArray, dec: FloatArray, unix_time: float) -> tuple[FloatArray, FloatArray]:
    """(alt, az) of J2000 positions of any shape at one time."""
    ra_b, dec_b = np.broadcast_arrays(ra, dec)
    shape = ra_b.shape
    times = np.full(ra_b.size, unix_time)
    alt, az = radec_to_altaz(
        ra_b.reshape(-1).astype(np.float64),
        dec_b.reshape(-1).astype(np.float64),
        site.latitude,
        site.longitude,
        times,
    )
    return alt.reshape(shape), az.reshape(shape)


@dataclass(frozen=True)
class SlewModel:
    """Seconds between two pointings at a site.

    Args:
        axis1: Hour angle (``mount: equatorial``) or azimuth (``altaz``).
        axis2: Declination or altitude.
        settle_s: Settling after every slew, seconds.
        mount: ``equatorial`` or ``altaz``.
        dome: The dome's rotation, None without a dome (a roll-off roof).
        filter_change_s: A change of filter between blocks (first filter of the next block
            differs from the last of the one before).
        instrument_setup_s: Setting up another instrument between blocks.
    """

    axis1: AxisMotion
    axis2: AxisMotion
    settle_s: float = 0.0
    mount: Mount = "equatorial"
    dome: AxisMotion | None = None
    filter_change_s: float = 0.0
    instrument_setup_s: float = 0.0

    def __post_init__(self) -> None:
        if self.mount not in ("equatorial", "altaz"):
            raise InvalidArgumentError(f"mount must be 'equatorial' or 'altaz', got {self.mount!r}")
        for name in ("settle_s", "filter_change_s", "instrument_setup_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise InvalidArgumentError(f"{name} must be >= 0 seconds, got {value}")

    @classmethod
    def from_config(cls, config: Mapping[str, Any]) -> SlewModel:
        """From a mount's configuration: ``slew_rate`` (deg/s, both axes) or ``axis_rates``
        ([axis1, axis2]), ``acceleration`` (deg/s², one or per axis), ``settle_time`` (s),
        ``mount``; optional ``dome_rate`` and ``dome_acceleration``, ``filter_change_s``,
        ``instrument_setup_s``. Unknown keys are refused (a misspelt rate must not pass silently).
        """
        known = {
            "slew_rate", "axis_rates", "acceleration", "settle_time", "mount", "dome_rate",
            "dome_acceleration", "filter_change_s", "instrument_setup_s",
        }  # fmt: skip
        unknown = sorted(set(config) - known)
        if unknown:
            raise InvalidArgumentError(
                f"slew model: unknown keys {', '.join(unknown)} (known: {sorted(known)})"
            )
        if "axis_rates" in config:
            rates = [float(r) for r in config["axis_rates"]]
        elif "slew_rate" in config:
            rates = [float(config["slew_rate"])] * 2
        else:
            raise InvalidArgumentError("slew model: give slew_rate or axis_rates (deg/s)")
        if len(rates) != 2:
            raise InvalidArgumentError(f"slew model: axis_rates needs two rates, got {rates}")
        acceleration = config.get("acceleration", math.inf)
        accelerations = (
            [float(a) for a in acceleration] if isinstance(acceleration, list) else [float(acceleration)] * 2
        )
        dome_rate = config.get("dome_rate")
        dome = (
            None
            if dome_rate is None
            else AxisMotion(float(dome_rate), float(config.get("dome_acceleration", math.inf)))
        )
        return cls(
            axis1=AxisMotion(rates[0], accelerations[0]),
            axis2=AxisMotion(rates[1], accelerations[1]),
            settle_s=float(config.get("settle_time", 0.0)),
            mount=config.get("mount", "equatorial"),
            dome=dome,
            filter_change_s=float(config.get("filter_change_s", 0.0)),
            instrument_setup_s=float(config.get("instrument_setup_s", 0.0)),
        )

    def slew_s(
        self,
        site: Site,
        start: tuple[npt.ArrayLike, npt.ArrayLike],
        end: tuple[npt.ArrayLike, npt.ArrayLike],
        unix_time: float,
    ) -> FloatArray:
        """Seconds to slew (and settle) from J2000 (ra, dec) ``start`` to ``end`` at ``unix_time``;
        arrays broadcast (e.g. a column of starts and a row of ends give every pair)."""
        ra0, dec0 = (np.asarray(v, dtype=np.float64) for v in start)
        ra1, dec1 = (np.asarray(v, dtype=np.float64) for v in end)
        need_altaz = self.mount == "altaz" or self.dome is not None
        if need_altaz:
            alt0, az0 = _altaz(site, ra0, dec0, unix_time)
            alt1, az1 = _altaz(site, ra1, dec1, unix_time)
        if self.mount == "equatorial":
            lst = float(local_sidereal_time(unix_time, site.longitude))
            # Hour angles within -180..180: the axis turns through the meridian, not round the back.
            ha0 = (lst - ra0 + 180.0) % 360.0 - 180.0
            ha1 = (lst - ra1 + 180.0) % 360.0 - 180.0
            first, second = np.abs(ha1 - ha0), np.abs(dec1 - dec0)
        else:
            first, second = _turn(az0, az1), np.abs(alt1 - alt0)
        seconds = np.maximum(self.axis1.seconds(first), self.axis2.seconds(second))
        if self.dome is not None:
            seconds = np.maximum(seconds, self.dome.seconds(_turn(az0, az1)))
        moved = (first > 0) | (second > 0)
        return np.where(moved, seconds + self.settle_s, 0.0)

    def transition_s(self, site: Site, before: Pointing, after: Pointing, unix_time: float) -> float:
        """Seconds from the end of a block at ``before`` to the start of one at ``after``."""
        slew = float(self.slew_s(site, (before.ra, before.dec), (after.ra, after.dec), unix_time))
        return slew + self.changes_s(before, after)

    def changes_s(self, before: Pointing, after: Pointing) -> float:
        """Seconds of filter change and instrument set-up between the two blocks."""
        seconds = 0.0
        if after.first_filter and before.last_filter and after.first_filter != before.last_filter:
            seconds += self.filter_change_s
        if after.instrument and before.instrument and after.instrument != before.instrument:
            seconds += self.instrument_setup_s
        return seconds
