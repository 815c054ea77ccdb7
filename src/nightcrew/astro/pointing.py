"""A TPoint-style pointing model of an equatorial mount: terms, least-squares fit, application.

A mount sent to hour angle and declination (h, δ) (of date, degrees) really points at
(h + ΔH, δ + Δδ), where ΔH and Δδ are sums of *terms*, each a coefficient (arcsec) times a function
of (h, δ) and the site's latitude φ. The terms (TPoint's names and geometry):

====  ========================================  ====================================
IH    index error in hour angle                  ΔH = IH
ID    index error in declination                 Δδ = ID
CH    collimation (east-west)                    ΔH = CH sec δ
NP    hour/dec axes not perpendicular            ΔH = NP tan δ
MA    polar axis misaligned in azimuth           ΔH = -MA cos h tan δ, Δδ = MA sin h
ME    polar axis misaligned in elevation         ΔH = ME sin h tan δ, Δδ = ME cos h
TF    tube flexure (sin of zenith distance)      ΔH = TF cos φ sin h sec δ,
                                                 Δδ = TF (cos φ cos h sin δ - sin φ cos δ)
FO    fork flexure                               Δδ = FO cos h
====  ========================================  ====================================

Harmonic terms are named ``H{result}{S|C}{argument}{n}``: result ``H`` (ΔH) or ``D`` (Δδ), S/C
the sine or cosine, argument ``H`` (h) or ``D`` (δ), n the multiple (1 when left out): ``HHSH``
is ΔH = HHSH sin h, ``HDCD2`` is Δδ = HDCD2 cos 2δ.

The fit (:func:`fit_pointing_model`) is linear least squares of the on-sky offsets
(ΔH cos δ, Δδ) of solved from commanded positions, so every point weighs the same on the sky; term
uncertainties come from the covariance scaled by the residual variance, and points off by more
than ``clip`` times the RMS are rejected in rounds. :meth:`PointingModel.to_mount` turns a requested
position into the one to command; :meth:`PointingModel.to_sky` the other way round.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from nightcrew.astro.coords import j2000_to_of_date, of_date_to_j2000
from nightcrew.astro.time import local_sidereal_time

__all__ = [
    "BASIC_TERMS",
    "DEFAULT_TERMS",
    "FitStatistics",
    "PointingModel",
    "PointingModelError",
    "PointingPair",
    "check_term_names",
    "fit_pointing_model",
    "from_hadec",
    "icrs_pair",
    "term_offsets",
    "to_hadec",
]

FloatArray = npt.NDArray[np.float64]
ARCSEC = 3600.0

#: The eight geometric terms.
BASIC_TERMS = ("IH", "ID", "CH", "NP", "MA", "ME", "TF", "FO")
#: The terms fitted unless told otherwise: the geometric ones and the first hour-angle harmonics.
DEFAULT_TERMS = (*BASIC_TERMS, "HHSH", "HHCH")

_HARMONIC = re.compile(r"^H([HD])([SC])([HD])([1-9]?)$")


class PointingModelError(ValueError):
    """A pointing model or its data is not usable (unknown term, other mount, too few points)."""


def check_term_names(names: Sequence[str]) -> tuple[str, ...]:
    """The names as a tuple, or PointingModelError naming the unknown or repeated ones."""
    unknown = [name for name in names if name not in BASIC_TERMS and not _HARMONIC.match(name)]
    if unknown:
        raise PointingModelError(
            f"unknown pointing term(s) {', '.join(map(str, unknown))}; known: {', '.join(BASIC_TERMS)} "
            "and harmonics H[H|D][S|C][H|D][n] (e.g. HHSH, HDCD2)"
        )
    repeated = sorted({name for name in names if list(names).count(name) > 1})
    if repeated:
        raise PointingModelError(f"pointing term(s) given twice: {', '.join(repeated)}")
    return tuple(names)


def term_offsets(
    name: str, ha: FloatArray, dec: FloatArray, latitude: float
) -> tuple[FloatArray, FloatArray]:
    """On-sky offsets (ΔH cos δ, Δδ) of one arcsec of term ``name`` at (ha, dec) degrees, arcsec."""
    h, d, phi = np.radians(ha), np.radians(dec), math.radians(latitude)
    zero, one = np.zeros_like(h), np.ones_like(h)
    cos_d, sin_d, cos_h, sin_h = np.cos(d), np.sin(d), np.cos(h), np.sin(h)
    match name:
        case "IH":
            return cos_d, zero
        case "ID":
            return zero, one
        case "CH":
            return one, zero
        case "NP":
            return sin_d, zero
        case "MA":
            return -cos_h * sin_d, sin_h
        case "ME":
            return sin_h * sin_d, cos_h
        case "TF":
            return math.cos(phi) * sin_h, math.cos(phi) * cos_h * sin_d - math.sin(phi) * cos_d
        case "FO":
            return zero, cos_h
    found = _HARMONIC.match(name)
    if found is None:
        raise PointingModelError(f"unknown pointing term {name!r}")
    result, function, argument, multiple = found.groups()
    angle = (h if argument == "H" else d) * int(multiple or 1)
    value = np.sin(angle) if function == "S" else np.cos(angle)
    return (value * cos_d, zero) if result == "H" else (zero, value)


def to_hadec(ra: float, dec: float, longitude: float, unix_time: float) -> tuple[float, float]:
    """Hour angle (-180..180) and declination of date of ICRS (ra, dec), degrees."""
    ra_date, dec_date = j2000_to_of_date(ra, dec, unix_time)
    return float(_wrap(local_sidereal_time(unix_time, longitude) - ra_date)), dec_date


def from_hadec(ha: float, dec: float, longitude: float, unix_time: float) -> tuple[float, float]:
    """ICRS (ra, dec) of hour angle and declination of date, degrees."""
    ra, dec_j2000 = of_date_to_j2000((local_sidereal_time(unix_time, longitude) - ha) % 360.0, dec, unix_time)
    return ra % 360.0, dec_j2000


def icrs_pair(
    commanded: tuple[float, float], solved: tuple[float, float], longitude: float, unix_time: float
) -> PointingPair:
    """The pair of a commanded and a solved ICRS (ra, dec) at the time, in hour angle and dec of date."""
    ha_c, dec_c = to_hadec(*commanded, longitude, unix_time)
    ha_s, dec_s = to_hadec(*solved, longitude, unix_time)
    return PointingPair(ha_c, dec_c, ha_s, dec_s)


def _wrap(angle: float | FloatArray) -> Any:
    return (np.asarray(angle) + 180.0) % 360.0 - 180.0


@dataclass(frozen=True)
class PointingPair:
    """One measurement: where the mount was sent and where it pointed (of date, degrees)."""

    ha_commanded: float
    dec_commanded: float
    ha_solved: float
    dec_solved: float


@dataclass(frozen=True)
class FitStatistics:
    """How a model was fitted; RMS are on-sky radial offsets in arcsec."""

    points: int
    rejected: int
    rms_before: float
    rms_after: float

    def to_dict(self) -> dict[str, float | int]:
        return {
            "points": self.points,
            "rejected": self.rejected,
            "rms_before": round(self.rms_before, 3),
            "rms_after": round(self.rms_after, 3),
        }


@dataclass(frozen=True)
class PointingModel:
    """A fitted (or written) pointing model of one mount.

    Attributes:
        mount: Name of the mount (module) the model belongs to.
        latitude: Site latitude, degrees (TF depends on it).
        terms: Coefficient of each term, arcsec.
        sigmas: Standard error of each term, arcsec (empty when not fitted).
        statistics: The fit's statistics, None when not fitted.
    """

    mount: str
    latitude: float
    terms: Mapping[str, float]
    sigmas: Mapping[str, float] = field(default_factory=dict)
    statistics: FitStatistics | None = None

    def __post_init__(self) -> None:
        check_term_names(list(self.terms))
        if not self.mount:
            raise PointingModelError("a pointing model needs the name of its mount")
        if not -90.0 <= self.latitude <= 90.0:
            raise PointingModelError(f"latitude must be within -90..90 degrees, got {self.latitude}")

    def offsets(self, ha: float, dec: float) -> tuple[float, float]:
        """(ΔH, Δδ) in degrees of a mount commanded to (ha, dec): where it points minus where sent."""
        east, north = 0.0, 0.0
        h, d = np.array([ha]), np.array([dec])
        for name, value in self.terms.items():
            dh, dd = term_offsets(name, h, d, self.latitude)
            east, north = east + value * float(dh[0]), north + value * float(dd[0])
        cos_d = max(math.cos(math.radians(dec)), 1e-6)
        return east / cos_d / ARCSEC, north / ARCSEC

    def to_sky(self, ha: float, dec: float) -> tuple[float, float]:
        """Where a mount commanded to (ha, dec) points (of date, degrees)."""
        dh, dd = self.offsets(ha, dec)
        return float(_wrap(ha + dh)), _clip_dec(dec + dd)

    def to_mount(self, ha: float, dec: float) -> tuple[float, float]:
        """Where to command the mount so that it points at (ha, dec) (of date, degrees)."""
        h, d = ha, dec
        for _ in range(50):  # converges in a few rounds: the terms change slowly over the sky
            dh, dd = self.offsets(h, d)
            new_h, new_d = float(_wrap(ha - dh)), _clip_dec(dec - dd)
            done = abs(_wrap(new_h - h)) < 1e-10 and abs(new_d - d) < 1e-10
            h, d = new_h, new_d
            if done:
                break
        return h, d

    def to_sky_icrs(self, ra: float, dec: float, longitude: float, unix_time: float) -> tuple[float, float]:
        """:meth:`to_sky` for ICRS (ra, dec) at east ``longitude`` and the time."""
        return _in_icrs(self.to_sky, ra, dec, longitude, unix_time)

    def to_mount_icrs(self, ra: float, dec: float, longitude: float, unix_time: float) -> tuple[float, float]:
        """:meth:`to_mount` for ICRS (ra, dec) at east ``longitude`` and the time."""
        return _in_icrs(self.to_mount, ra, dec, longitude, unix_time)

    def to_dict(self) -> dict[str, Any]:
        """The model as plain data (the file format: see :meth:`from_dict`)."""
        data: dict[str, Any] = {
            "mount": self.mount,
            "latitude": self.latitude,
            "terms": {name: round(value, 4) for name, value in self.terms.items()},
        }
        if self.sigmas:
            data["sigmas"] = {name: round(value, 4) for name, value in self.sigmas.items()}
        if self.statistics is not None:
            data["fit"] = self.statistics.to_dict()
        return data

    @classmethod
    def from_dict(cls, data: object, *, mount: str | None = None) -> PointingModel:
        """The model from :meth:`to_dict`'s data; with ``mount`` given, it must be that mount's."""
        if not isinstance(data, Mapping):
            raise PointingModelError("a pointing model must be a mapping with mount, latitude and terms")
        unknown = sorted(set(data) - {"mount", "latitude", "terms", "sigmas", "fit"})
        if unknown:
            raise PointingModelError(f"unknown key(s) {', '.join(map(str, unknown))} in a pointing model")
        name = data.get("mount")
        if not isinstance(name, str) or not name:
            raise PointingModelError("the pointing model names no mount (key 'mount')")
        if mount is not None and name != mount:
            raise PointingModelError(f"the pointing model is for mount {name!r}, not {mount!r}")
        try:
            terms = {str(k): float(v) for k, v in dict(data.get("terms") or {}).items()}
            sigmas = {str(k): float(v) for k, v in dict(data.get("sigmas") or {}).items()}
            fit = data.get("fit")
            statistics = None if fit is None else FitStatistics(**dict(fit))
            latitude = float(data["latitude"])
        except (KeyError, TypeError, ValueError) as exc:
            raise PointingModelError(f"malformed pointing model: {exc}") from exc
        check_term_names(list(sigmas))
        return cls(name, latitude, terms, sigmas, statistics)


def _in_icrs(
    convert: Callable[[float, float], tuple[float, float]],
    ra: float,
    dec: float,
    longitude: float,
    unix_time: float,
) -> tuple[float, float]:
    return from_hadec(*convert(*to_hadec(ra, dec, longitude, unix_time)), longitude, unix_time)


def _clip_dec(dec: float) -> float:
    return max(-90.0, min(90.0, dec))


def _sky_offsets(pairs: Sequence[PointingPair]) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Commanded (ha, dec) and on-sky offsets (east along HA, north) in arcsec of the pairs."""
    data = np.array(
        [(p.ha_commanded, p.dec_commanded, p.ha_solved, p.dec_solved) for p in pairs], dtype=float
    ).reshape(-1, 4)
    ha, dec = data[:, 0], data[:, 1]
    dh = _wrap(data[:, 2] - ha) * np.cos(np.radians(dec)) * ARCSEC
    dd = (data[:, 3] - dec) * ARCSEC
    return ha, dec, dh, dd


def _rms(dh: FloatArray, dd: FloatArray) -> float:
    return float(np.sqrt(np.mean(dh**2 + dd**2))) if dh.size else 0.0


def fit_pointing_model(
    pairs: Sequence[PointingPair],
    *,
    mount: str,
    latitude: float,
    terms: Sequence[str] = DEFAULT_TERMS,
    clip: float = 3.0,
    max_rounds: int = 5,
) -> PointingModel:
    """Least-squares fit of ``terms`` to the pairs, rejecting points beyond ``clip`` times the RMS.

    Raises PointingModelError for unknown terms or fewer usable points than the fit needs (two
    equations per point, one unknown per term, and at least one degree of freedom left).
    """
    names = check_term_names(terms)
    if not names:
        raise PointingModelError("no pointing terms to fit")
    ha, dec, dh, dd = _sky_offsets(pairs)
    if 2 * len(ha) <= len(names):
        raise PointingModelError(
            f"{len(ha)} points are too few to fit {len(names)} terms (need > {len(names) / 2:g})"
        )
    design = np.array([np.concatenate(term_offsets(name, ha, dec, latitude)) for name in names]).T
    observed = np.concatenate([dh, dd])
    keep = np.ones(len(ha), dtype=bool)
    for _ in range(max_rounds):
        rows = np.concatenate([keep, keep])
        solution, *_ = np.linalg.lstsq(design[rows], observed[rows], rcond=None)
        residual = observed - design @ solution
        radial = np.hypot(residual[: len(ha)], residual[len(ha) :])
        rms = float(np.sqrt(np.mean(radial[keep] ** 2)))
        new_keep = radial <= clip * rms if rms > 0 else keep
        if np.array_equal(new_keep, keep) or 2 * int(new_keep.sum()) <= len(names):
            break
        keep = new_keep
    rows = np.concatenate([keep, keep])
    dof = int(rows.sum()) - len(names)
    variance = float(np.sum(residual[rows] ** 2)) / max(dof, 1)
    covariance = np.linalg.pinv(design[rows].T @ design[rows]) * variance
    sigmas = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    statistics = FitStatistics(
        points=int(keep.sum()),
        rejected=int((~keep).sum()),
        rms_before=_rms(dh[keep], dd[keep]),
        rms_after=_rms(residual[: len(ha)][keep], residual[len(ha) :][keep]),
    )
    return PointingModel(
        mount,
        float(latitude),
        {name: float(value) for name, value in zip(names, solution, strict=True)},
        {name: float(value) for name, value in zip(names, sigmas, strict=True)},
        statistics,
    )
