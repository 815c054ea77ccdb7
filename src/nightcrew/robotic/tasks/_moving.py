"""Targets that move on the sky: orbital elements, major bodies and Earth satellites.

A configuration's ``target`` is one of these kinds, told apart by its ``type`` (a target without
``type`` is the sidereal :class:`~._configuration.Target`):

==================  ==========================================================================
type                fields
==================  ==========================================================================
ORBITAL_ELEMENTS    ``scheme`` and the elements as the LCO portal names them (below)
MPC_ELEMENTS        ``line``: one line of the MPC's ``MPCORB.DAT`` or ``CometEls.txt``
MAJOR_BODY          ``name``: mercury, venus, moon, mars, jupiter, saturn, uranus, neptune, pluto
SATELLITE           ``tle_line1``, ``tle_line2``: a NORAD two-line element set
==================  ==========================================================================

ORBITAL_ELEMENTS schemes (angles in degrees, referred to the ecliptic and equinox J2000; epochs as
modified Julian dates, TT): all need ``epochofel``, ``orbinc``, ``longascnode``, ``argofperih``
and ``eccentricity``; ``MPC_MINOR_PLANET`` adds ``meandist`` (a, au) and ``meananom``;
``JPL_MAJOR_PLANET`` also ``dailymot`` (degrees per day); ``MPC_COMET`` adds ``perihdist`` (q, au)
and ``epochofperih``. The two elliptical schemes need ``eccentricity < 1``.

Each kind checks its data when built (a TLE's checksum, the elements' ranges), and a request checks
that its windows are near enough to the elements' epoch for them to be trusted
(:data:`MAX_ELEMENTS_AGE_DAYS`, :data:`MAX_TLE_AGE_DAYS`).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from datetime import datetime
from enum import StrEnum
from typing import TYPE_CHECKING, Any, Literal, Self

from pydantic import Field, model_validator

from nightcrew.astro.elements import (
    MAJOR_BODIES,
    ElementsError,
    KeplerElements,
    MajorBody,
    TwoLineElements,
    elements_from_mean_anomaly,
    parse_mpc_line,
)
from nightcrew.astro.ephemeris import position_at
from nightcrew.astro.time import julian_date
from nightcrew.robotic.tasks._base import Number, TaskModel, raise_problems
from nightcrew.site import Site

if TYPE_CHECKING:
    from nightcrew.robotic.tasks._configuration import Target

__all__ = [
    "MAX_ELEMENTS_AGE_DAYS",
    "MAX_TLE_AGE_DAYS",
    "TARGET_KINDS",
    "MajorBodyTarget",
    "MovingTarget",
    "MpcElementsTarget",
    "OrbitalElementsScheme",
    "OrbitalElementsTarget",
    "SatelliteTarget",
    "epoch_problems",
    "target_kind",
    "target_radec",
]

#: Days between the elements' epoch and a request's windows beyond which two-body elements are
#: not trusted (the MPC publishes osculating elements for a new epoch every 200 days).
MAX_ELEMENTS_AGE_DAYS = 200.0
#: The same for a TLE: a low orbit's drag moves a satellite by kilometres within days.
MAX_TLE_AGE_DAYS = 14.0
_MJD_TO_JD = 2_400_000.5


class OrbitalElementsScheme(StrEnum):
    """How a set of orbital elements is given (the LCO portal's schemes)."""

    MPC_MINOR_PLANET = "MPC_MINOR_PLANET"
    MPC_COMET = "MPC_COMET"
    JPL_MAJOR_PLANET = "JPL_MAJOR_PLANET"


#: Fields each scheme needs beyond those all need; any other scheme's field is an error.
_SCHEME_FIELDS = {
    OrbitalElementsScheme.MPC_MINOR_PLANET: ("meandist", "meananom"),
    OrbitalElementsScheme.JPL_MAJOR_PLANET: ("meandist", "meananom", "dailymot"),
    OrbitalElementsScheme.MPC_COMET: ("perihdist", "epochofperih"),
}
_OPTIONAL_FIELDS = ("meandist", "meananom", "dailymot", "perihdist", "epochofperih")
#: Field of :class:`KeplerElements` or of the parsers -> field of the task model.
_LCO_NAMES = {
    "semimajor_axis_au": "meandist",
    "daily_motion": "dailymot",
    "perihelion_distance_au": "perihdist",
    "inclination": "orbinc",
    "eccentricity": "eccentricity",
}


class OrbitalElementsTarget(TaskModel):
    """A minor planet, comet or planet by heliocentric orbital elements (LCO's ORBITAL_ELEMENTS).

    See the module docstring for the fields each ``scheme`` needs.
    """

    type: Literal["ORBITAL_ELEMENTS"]
    name: str = Field(min_length=1)
    scheme: OrbitalElementsScheme
    epochofel: Number = Field(ge=0.0)
    orbinc: Number = Field(ge=0.0, le=180.0)
    longascnode: Number
    argofperih: Number
    eccentricity: Number = Field(ge=0.0)
    meandist: Number | None = Field(default=None, gt=0.0)
    meananom: Number | None = None
    dailymot: Number | None = Field(default=None, gt=0.0)
    perihdist: Number | None = Field(default=None, gt=0.0)
    epochofperih: Number | None = Field(default=None, ge=0.0)

    @model_validator(mode="after")
    def _check_scheme(self) -> Self:
        raise_problems(self._scheme_problems())
        try:
            self.body()
        except ElementsError as exc:
            raise_problems([(_LCO_NAMES.get(exc.field, exc.field), exc.message)])
        return self

    def _scheme_problems(self) -> Iterator[tuple[str, str]]:
        needed = _SCHEME_FIELDS[self.scheme]
        for field in _OPTIONAL_FIELDS:
            given = getattr(self, field) is not None
            if field in needed and not given:
                yield field, f"required for the {self.scheme.value} scheme"
            elif field not in needed and given:
                yield field, f"not used by the {self.scheme.value} scheme"

    @property
    def epoch_jd(self) -> float:
        """Julian date (TT) at which the elements osculate."""
        return self.epochofel + _MJD_TO_JD

    def body(self) -> KeplerElements:
        """The orbit, in the form the ephemeris takes."""
        if self.scheme is OrbitalElementsScheme.MPC_COMET:
            assert self.perihdist is not None and self.epochofperih is not None  # by the scheme check
            return KeplerElements(
                name=self.name,
                perihelion_distance_au=self.perihdist,
                eccentricity=self.eccentricity,
                inclination=self.orbinc,
                longitude_of_ascending_node=self.longascnode,
                argument_of_perihelion=self.argofperih,
                perihelion_time_jd=self.epochofperih + _MJD_TO_JD,
                epoch_jd=self.epoch_jd,
            )
        assert self.meandist is not None and self.meananom is not None  # by the scheme check
        return elements_from_mean_anomaly(
            self.name,
            semimajor_axis_au=self.meandist,
            eccentricity=self.eccentricity,
            inclination=self.orbinc,
            longitude_of_ascending_node=self.longascnode,
            argument_of_perihelion=self.argofperih,
            mean_anomaly=self.meananom,
            epoch_jd=self.epoch_jd,
            daily_motion=self.dailymot,
        )


class MpcElementsTarget(TaskModel):
    """A minor planet or comet by one line of the MPC's orbit files; ``name`` defaults to the line's."""

    type: Literal["MPC_ELEMENTS"]
    line: str = Field(min_length=1)
    name: str = ""

    @model_validator(mode="after")
    def _check_line(self) -> Self:
        try:
            elements = parse_mpc_line(self.line)
        except ElementsError as exc:
            raise_problems([("line", exc.message)])
        if not self.name:
            object.__setattr__(self, "name", elements.name)  # frozen: filled once, while validating
        return self

    @property
    def epoch_jd(self) -> float:
        """Julian date (TT) at which the elements osculate."""
        return self.body().epoch_jd

    def body(self) -> KeplerElements:
        """The orbit, in the form the ephemeris takes."""
        return parse_mpc_line(self.line)


class MajorBodyTarget(TaskModel):
    """A planet or the Moon by name (upper or lower case), positions from JPL's DE421."""

    type: Literal["MAJOR_BODY"]
    name: str = Field(min_length=1)

    @model_validator(mode="after")
    def _check_name(self) -> Self:
        if self.name.lower() not in MAJOR_BODIES:
            raise_problems([("name", f"must be one of {', '.join(MAJOR_BODIES)}, got {self.name!r}")])
        return self

    def body(self) -> MajorBody:
        """The body, in the form the ephemeris takes."""
        return MajorBody(self.name.lower())


class SatelliteTarget(TaskModel):
    """An Earth satellite by its two-line elements (SGP4)."""

    type: Literal["SATELLITE"]
    name: str = Field(min_length=1)
    tle_line1: str
    tle_line2: str

    @model_validator(mode="after")
    def _check_tle(self) -> Self:
        try:
            self.body().epoch_jd  # noqa: B018 - reading the epoch checks its columns
        except ElementsError as exc:
            raise_problems([(f"tle_{exc.field}", exc.message)])
        return self

    @property
    def epoch_jd(self) -> float:
        """Julian date (UTC) of the element set's epoch."""
        return self.body().epoch_jd

    def body(self) -> TwoLineElements:
        """The satellite, in the form the ephemeris takes."""
        return TwoLineElements(self.name, self.tle_line1, self.tle_line2)


#: A target that moves: what :func:`~nightcrew.astro.ephemeris.ephemeris` can follow.
MovingTarget = OrbitalElementsTarget | MpcElementsTarget | MajorBodyTarget | SatelliteTarget
#: The ``type`` of each target kind; a target without ``type`` is sidereal.
TARGET_KINDS = ("SIDEREAL", "ORBITAL_ELEMENTS", "MPC_ELEMENTS", "MAJOR_BODY", "SATELLITE")


def target_kind(value: Any) -> str:
    """The kind of a target given as data or as a model (the discriminator of the target union)."""
    if isinstance(value, dict):
        kind = value.get("type", "SIDEREAL")
        return kind if isinstance(kind, str) else repr(kind)
    return str(getattr(value, "type", "SIDEREAL"))


def _epoch_field(target: MovingTarget) -> str:
    if isinstance(target, SatelliteTarget):
        return "tle_line1"
    return "line" if isinstance(target, MpcElementsTarget) else "epochofel"


def epoch_problems(
    targets: Sequence[tuple[str, object]], start: datetime, end: datetime
) -> Iterator[tuple[str, str]]:
    """Problems of targets whose elements' epoch is too far from ``[start, end]`` to be trusted.

    Args:
        targets: ``(path, target)`` pairs, e.g. ``("configurations[0].target", target)``.
        start: The first window's start.
        end: The last window's end.
    """
    first = julian_date(start.timestamp())
    last = julian_date(end.timestamp())
    for path, target in targets:
        if not isinstance(target, OrbitalElementsTarget | MpcElementsTarget | SatelliteTarget):
            continue  # sidereal targets and major bodies have no elements to age
        limit = MAX_TLE_AGE_DAYS if isinstance(target, SatelliteTarget) else MAX_ELEMENTS_AGE_DAYS
        epoch = target.epoch_jd
        days = max(first - epoch, epoch - last, 0.0)
        if days > limit:
            yield (
                f"{path}.{_epoch_field(target)}",
                f"the elements' epoch is {days:.0f} days from the request's windows (at most {limit:g}"
                " days): give elements for an epoch near the night",
            )


def target_radec(target: Target | MovingTarget, site: Site | None, unix_time: float) -> tuple[float, float]:
    """Where to point for ``target`` at ``unix_time``: ICRS (ra, dec) in degrees, astrometric and
    topocentric for a moving target (which needs the ``site``), the catalogue position otherwise."""
    if isinstance(target, OrbitalElementsTarget | MpcElementsTarget | MajorBodyTarget | SatelliteTarget):
        if site is None:
            raise ValueError(
                f"the moving target {target.name!r} needs the observatory's site for its position"
            )
        return position_at(target.body(), site, unix_time)
    return target.ra, target.dec
