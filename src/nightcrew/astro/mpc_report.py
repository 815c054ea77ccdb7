"""Measured positions of a minor planet or comet as lines of the MPC's 80-column observation format.

One line per position (columns as the MPC documents them, 1-based): 1-5 the packed minor-planet
number, 6-12 the packed provisional designation (or a temporary one), 15 the note ``C`` (CCD),
16-32 the UTC date with the day's fraction (``2026 11 10.916667``, 1e-6 day), 33-44 the right
ascension (``HH MM SS.sss``), 45-56 the declination (``sDD MM SS.ss``), 66-70 the magnitude and 71
its band, 78-80 the observatory code. Positions are astrometric (J2000/ICRS), at the exposure's
mid-time: what a plate solution of the frame measures.
"""

from __future__ import annotations

import math
from datetime import UTC, datetime

__all__ = ["mpc_observation_line"]


def mpc_observation_line(
    *,
    unix_time: float,
    ra: float,
    dec: float,
    observatory_code: str,
    number: str = "",
    designation: str = "",
    magnitude: float | None = None,
    band: str = "",
) -> str:
    """One 80-column line for a position measured at ``unix_time`` (mid-exposure, Unix seconds).

    Args:
        unix_time: Mid-time of the exposure.
        ra: Right ascension, degrees (ICRS).
        dec: Declination, degrees.
        observatory_code: The MPC's three-character code of the site (e.g. ``500`` geocentric).
        number: The packed minor-planet number (up to 5 characters), if numbered.
        designation: The packed provisional designation or a temporary one (up to 7 characters).
        magnitude: Measured magnitude, if any.
        band: Its band (one character, e.g. ``R``, ``G``).

    Raises:
        ValueError: A field that does not fit its columns.
    """
    if not number and not designation:
        raise ValueError("number or designation: one of them is needed")
    for name, value, width in (("number", number, 5), ("designation", designation, 7), ("band", band, 1)):
        if len(value) > width:
            raise ValueError(f"{name}: at most {width} characters, got {value!r}")
    if len(observatory_code) != 3:
        raise ValueError(f"observatory_code: three characters, got {observatory_code!r}")
    if not (math.isfinite(ra) and math.isfinite(dec) and -90.0 <= dec <= 90.0):
        raise ValueError(f"ra, dec: finite, dec within -90..90, got ({ra}, {dec})")
    line = (
        f"{number:>5}{designation:<7}  C{_date(unix_time)}{_ra(ra)}{_dec(dec)}{'':9}"
        f"{_magnitude(magnitude)}{band:1}{'':6}{observatory_code}"
    )
    assert len(line) == 80
    return line


def _date(unix_time: float) -> str:
    # Rounded to the format's 1e-6 day first, so that a carry moves to the next day (or month).
    microdays = round(unix_time / 0.0864)
    day_start = microdays // 1_000_000 * 86_400
    when = datetime.fromtimestamp(day_start, UTC)
    return f"{when.year:4d} {when.month:02d} {when.day:02d}.{microdays % 1_000_000:06d}"


def _ra(ra: float) -> str:
    milliseconds = round((ra % 360.0) / 15.0 * 3_600_000) % (24 * 3_600_000)
    hours, rest = divmod(milliseconds, 3_600_000)
    minutes, rest = divmod(rest, 60_000)
    return f"{hours:02d} {minutes:02d} {rest / 1000:06.3f}"


def _dec(dec: float) -> str:
    sign = "-" if dec < 0 else "+"
    centiarcsec = round(abs(dec) * 360_000)
    degrees, rest = divmod(centiarcsec, 360_000)
    minutes, rest = divmod(rest, 6_000)
    return f"{sign}{degrees:02d} {minutes:02d} {rest / 100:05.2f}"


def _magnitude(magnitude: float | None) -> str:
    return f"{magnitude:4.1f} " if magnitude is not None else " " * 5
