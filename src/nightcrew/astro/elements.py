"""Orbits of moving targets as plain values, and the text formats they come in.

Three kinds of body, each a frozen dataclass that :mod:`.ephemeris` turns into positions:

- :class:`MajorBody`: a planet or the Moon, by name, from the JPL DE421 kernel.
- :class:`KeplerElements`: a heliocentric two-body orbit (minor planet or comet) in perihelion
  form, referred to the ecliptic and equinox J2000, as the MPC publishes them.
- :class:`TwoLineElements`: an Earth satellite from a NORAD two-line element set.

Parsers read the MPC's one-line formats (``MPCORB.DAT`` for minor planets, ``CometEls.txt`` for
comets) and check TLEs (line numbers, column layout, the modulo-10 checksum). Every parser raises
:class:`ElementsError` naming the field at fault, so a task's validation can say what is wrong.
Times are Julian dates in TT (the MPC's convention); the few-second TT-UTC difference is far below
what two-body elements are good for.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "GAUSS_K",
    "MAJOR_BODIES",
    "ElementsError",
    "KeplerElements",
    "MajorBody",
    "TwoLineElements",
    "elements_from_mean_anomaly",
    "parse_mpc_comet_line",
    "parse_mpc_line",
    "parse_mpc_minor_planet_line",
    "tle_checksum",
]

#: The Gaussian gravitational constant: mean motion in radians per day at a = 1 au.
GAUSS_K = 0.01720209895

#: Names accepted for :class:`MajorBody`, and their segment in the DE421 kernel (the giant planets
#: only as barycentres: DE421 has no segment for their centres, and the moons move them by < 0.1″).
MAJOR_BODIES: dict[str, str] = {
    "mercury": "mercury",
    "venus": "venus",
    "moon": "moon",
    "mars": "mars",
    "jupiter": "jupiter barycenter",
    "saturn": "saturn barycenter",
    "uranus": "uranus barycenter",
    "neptune": "neptune barycenter",
    "pluto": "pluto barycenter",
}


class ElementsError(ValueError):
    """Orbital elements or a TLE that cannot be used.

    Args:
        field: Which field (or column range) is wrong, e.g. ``eccentricity``, ``line2``.
        message: What is wrong with it.
    """

    def __init__(self, field: str, message: str) -> None:
        super().__init__(f"{field}: {message}")
        self.field = field
        self.message = message


@dataclass(frozen=True)
class MajorBody:
    """A planet or the Moon; ``name`` is a key of :data:`MAJOR_BODIES` (lower case)."""

    name: str

    def __post_init__(self) -> None:
        if self.name not in MAJOR_BODIES:
            raise ElementsError("name", f"must be one of {', '.join(MAJOR_BODIES)}, got {self.name!r}")


@dataclass(frozen=True)
class KeplerElements:
    """A heliocentric two-body orbit in perihelion form (ecliptic and equinox J2000).

    Args:
        name: For people and headers.
        perihelion_distance_au: q > 0.
        eccentricity: e >= 0 (1 is parabolic, above hyperbolic).
        inclination: i in degrees, 0..180.
        longitude_of_ascending_node: Omega in degrees.
        argument_of_perihelion: omega in degrees.
        perihelion_time_jd: T, Julian date (TT) of the perihelion passage.
        epoch_jd: Julian date (TT) at which the elements osculate: the further the night is from it,
            the less a two-body orbit can be trusted.
    """

    name: str
    perihelion_distance_au: float
    eccentricity: float
    inclination: float
    longitude_of_ascending_node: float
    argument_of_perihelion: float
    perihelion_time_jd: float
    epoch_jd: float

    def __post_init__(self) -> None:
        values = (
            ("perihelion_distance_au", self.perihelion_distance_au),
            ("eccentricity", self.eccentricity),
            ("inclination", self.inclination),
            ("longitude_of_ascending_node", self.longitude_of_ascending_node),
            ("argument_of_perihelion", self.argument_of_perihelion),
            ("perihelion_time_jd", self.perihelion_time_jd),
            ("epoch_jd", self.epoch_jd),
        )
        for field, value in values:
            if not math.isfinite(value):
                raise ElementsError(field, f"must be a finite number, got {value}")
        if not self.perihelion_distance_au > 0:
            raise ElementsError("perihelion_distance_au", f"must be > 0, got {self.perihelion_distance_au}")
        if not self.eccentricity >= 0:
            raise ElementsError("eccentricity", f"must be >= 0, got {self.eccentricity}")
        if not 0 <= self.inclination <= 180:
            raise ElementsError("inclination", f"must be within 0..180 degrees, got {self.inclination}")


@dataclass(frozen=True)
class TwoLineElements:
    """An Earth satellite's NORAD two-line element set (checked when built).

    Args:
        name: For people and headers.
        line1: The line starting with ``1 ``.
        line2: The line starting with ``2 ``.
    """

    name: str
    line1: str
    line2: str

    def __post_init__(self) -> None:
        for field, line, number in (("line1", self.line1, "1"), ("line2", self.line2, "2")):
            if len(line.rstrip()) != 69:
                raise ElementsError(field, f"a TLE line has 69 characters, got {len(line.rstrip())}")
            if line[0] != number or line[1] != " ":
                raise ElementsError(field, f"must start with {number!r} and a space")
            expected = tle_checksum(line)
            if line[68] != str(expected):
                raise ElementsError(field, f"checksum is {line[68]!r}, the line's digits give {expected}")
        if self.line1[2:7] != self.line2[2:7]:
            raise ElementsError("line2", "satellite number differs from line1's")

    @property
    def epoch_jd(self) -> float:
        """Julian date (UTC) of the element set's epoch (line 1, columns 19-32)."""
        text = self.line1[18:32]
        try:
            two_digit_year, day_of_year = int(text[:2]), float(text[2:])
        except ValueError:
            raise ElementsError("line1", f"epoch (columns 19-32) is not a number: {text!r}") from None
        year = 1900 + two_digit_year if two_digit_year >= 57 else 2000 + two_digit_year
        return _julian_date(year, 1, 0.0) + day_of_year


def tle_checksum(line: str) -> int:
    """The modulo-10 checksum of a TLE line's first 68 columns (digits count, each '-' counts 1)."""
    return sum(int(c) if c.isdigit() else 1 if c == "-" else 0 for c in line[:68]) % 10


def elements_from_mean_anomaly(
    name: str,
    *,
    semimajor_axis_au: float,
    eccentricity: float,
    inclination: float,
    longitude_of_ascending_node: float,
    argument_of_perihelion: float,
    mean_anomaly: float,
    epoch_jd: float,
    daily_motion: float | None = None,
) -> KeplerElements:
    """Elliptical elements given by mean anomaly at an epoch, in perihelion form.

    ``daily_motion`` (degrees per day) defaults to the two-body value for the Sun's mass.
    """
    if not 0 <= eccentricity < 1:
        raise ElementsError(
            "eccentricity", f"must be >= 0 and < 1 for elliptical elements, got {eccentricity}"
        )
    if not semimajor_axis_au > 0:
        raise ElementsError("semimajor_axis_au", f"must be > 0, got {semimajor_axis_au}")
    motion = daily_motion if daily_motion is not None else math.degrees(GAUSS_K / semimajor_axis_au**1.5)
    if not motion > 0:
        raise ElementsError("daily_motion", f"must be > 0, got {motion}")
    # The perihelion passage nearest the epoch: M in (-180, 180].
    anomaly = (mean_anomaly + 180.0) % 360.0 - 180.0
    return KeplerElements(
        name=name,
        perihelion_distance_au=semimajor_axis_au * (1.0 - eccentricity),
        eccentricity=eccentricity,
        inclination=inclination,
        longitude_of_ascending_node=longitude_of_ascending_node,
        argument_of_perihelion=argument_of_perihelion,
        perihelion_time_jd=epoch_jd - anomaly / motion,
        epoch_jd=epoch_jd,
    )


def parse_mpc_line(line: str) -> KeplerElements:
    """Elements from one line of ``MPCORB.DAT`` or ``CometEls.txt`` (told apart by their layout)."""
    if _looks_like_comet(line):
        return parse_mpc_comet_line(line)
    return parse_mpc_minor_planet_line(line)


def _looks_like_comet(line: str) -> bool:
    # CometEls.txt: orbit type in column 5, perihelion year in columns 15-18.
    return len(line) > 18 and line[4] in "PCDXIA" and line[14:18].strip().isdigit()


def parse_mpc_minor_planet_line(line: str) -> KeplerElements:
    """Elements from one line of the MPC's ``MPCORB.DAT`` format (columns as the MPC documents)."""
    if len(line.rstrip()) < 103:
        raise ElementsError("line", f"an MPCORB line has at least 103 characters, got {len(line.rstrip())}")
    name = line[166:194].strip() or line[0:7].strip()
    return elements_from_mean_anomaly(
        name,
        epoch_jd=_packed_date(line[20:25]),
        mean_anomaly=_column(line, 26, 35, "mean anomaly"),
        argument_of_perihelion=_column(line, 37, 46, "argument of perihelion"),
        longitude_of_ascending_node=_column(line, 48, 57, "longitude of the ascending node"),
        inclination=_column(line, 59, 68, "inclination"),
        eccentricity=_column(line, 70, 79, "eccentricity"),
        daily_motion=_column(line, 80, 91, "mean daily motion"),
        semimajor_axis_au=_column(line, 92, 103, "semimajor axis"),
    )


def parse_mpc_comet_line(line: str) -> KeplerElements:
    """Elements from one line of the MPC's ``CometEls.txt`` format."""
    if len(line.rstrip()) < 79:
        raise ElementsError(
            "line", f"a comet elements line has at least 79 characters, got {len(line.rstrip())}"
        )
    year = int(_column(line, 14, 18, "perihelion year"))
    month = int(_column(line, 19, 21, "perihelion month"))
    day = _column(line, 22, 29, "perihelion day")
    perihelion_jd = _julian_date(year, month, day)
    epoch_text = line[81:89].strip()
    epoch_jd = perihelion_jd
    if epoch_text:
        if not epoch_text.isdigit() or len(epoch_text) != 8:
            raise ElementsError("line", f"epoch (columns 82-89) must be YYYYMMDD, got {epoch_text!r}")
        epoch_jd = _julian_date(int(epoch_text[:4]), int(epoch_text[4:6]), float(epoch_text[6:]))
    name = line[102:158].strip() or line[0:12].strip()
    return KeplerElements(
        name=name,
        perihelion_distance_au=_column(line, 30, 39, "perihelion distance"),
        eccentricity=_column(line, 41, 49, "eccentricity"),
        argument_of_perihelion=_column(line, 51, 59, "argument of perihelion"),
        longitude_of_ascending_node=_column(line, 61, 69, "longitude of the ascending node"),
        inclination=_column(line, 71, 79, "inclination"),
        perihelion_time_jd=perihelion_jd,
        epoch_jd=epoch_jd,
    )


def _column(line: str, start: int, end: int, what: str) -> float:
    text = line[start:end].strip()
    try:
        return float(text)
    except ValueError:
        raise ElementsError("line", f"{what} (columns {start + 1}-{end}) is not a number: {text!r}") from None


def _packed_digit(char: str) -> int:
    # MPC packing: 1-9, then A=10 .. V=31 (months and days); I, J, K = 18, 19, 20 for centuries.
    return ord(char) - (48 if char.isdigit() else 55)


def _packed_date(text: str) -> float:
    """Julian date (TT, 0h) of an MPC packed date such as ``K2555`` (2025 May 5)."""
    if len(text) != 5 or text[0] not in "IJK" or not text[1:3].isdigit():
        raise ElementsError("line", f"epoch (columns 21-25) is not an MPC packed date: {text!r}")
    year = 100 * _packed_digit(text[0]) + int(text[1:3])
    month, day = _packed_digit(text[3]), _packed_digit(text[4])
    if not (1 <= month <= 12 and 1 <= day <= 31):
        raise ElementsError("line", f"epoch (columns 21-25) is not an MPC packed date: {text!r}")
    return _julian_date(year, month, float(day))


def _julian_date(year: int, month: int, day: float) -> float:
    """Julian date of a Gregorian calendar date (``day`` may have a fraction; day 0 is the day before 1)."""
    if month <= 2:
        year, month = year - 1, month + 12
    century = year // 100
    gregorian = 2 - century + century // 4
    return math.floor(365.25 * (year + 4716)) + math.floor(30.6001 * (month + 1)) + day + gregorian - 1524.5
