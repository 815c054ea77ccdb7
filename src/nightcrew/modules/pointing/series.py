"""Pointing series: point at a grid across the sky, solve each image, write commanded vs solved as CSV.

For each point of an alt/az grid (``pattern: grid``, :func:`pointing_grid`, rows and columns; or
``pattern: sky``, :func:`sky_grid`, ``points`` spread evenly over the sky above ``min_altitude``)
the telescope moves there (to the RA/Dec
of that alt/az at that moment, tracking, or to the alt/az itself), the camera exposes, the
``solver`` pipeline plate-solves the frame (e.g. SEP detection + :class:`CatalogAstrometry`, or
:class:`SolveFieldAstrometry`) and the solved centre is compared with the commanded position. The
CSV is rewritten after every point, so an aborted series keeps what it measured. Its columns
(:data:`CSV_COLUMNS`; angles in degrees, offsets in arcsec, solved minus commanded):

==================  =============================================================================
time                start of the exposure (ISO, UTC; the FITS DATE-OBS)
alt_cmd, az_cmd     the grid point
ra_cmd, dec_cmd     commanded ICRS position (sent to the mount, or the grid point's at ``time``;
                    the mount's own position MNT-RA/MNT-DEC when a pointing model corrects it)
ra_solved, ...      solved ICRS centre of the frame, and its alt/az at ``time`` (``alt_solved``,
                    ``az_solved``)
dra, ddec           offsets on the sky: (ra_solved - ra_cmd) * cos(dec), dec_solved - dec_cmd
dalt, daz           (alt_solved - alt_cmd), (az_solved - az_cmd) * cos(alt)
stars, rms          stars the solution rests on and their residual RMS (arcsec), if known
filename            VFS path of the frame
error               why the point has no solution ("" when solved)
latitude, longitude the site (``nightcrew pointing fit`` turns the rows into hour angles)
==================  =============================================================================

Example (YAML)::

    class: nightcrew.modules.pointing.PointingSeries
    telescope: telescope
    camera: camera
    alt_range: [30, 80]     # degrees, lowest and highest row
    alt_steps: 3
    az_steps: 8
    min_altitude: 25        # points below are left out
    filename: /pointing/pointing-{time}.csv
    solver:
      class: nightcrew.images.Pipeline
      steps:
        - {class: nightcrew.images.processors.detection.SepSourceDetection}
        - {class: nightcrew.images.astrometry.CatalogAstrometry}
"""

from __future__ import annotations

import asyncio
import logging
import math
from collections.abc import Awaitable, Mapping, Sequence
from dataclasses import asdict, dataclass
from datetime import UTC, datetime
from typing import Any, Literal

from nightcrew.astro import altaz_to_radec, radec_to_altaz
from nightcrew.astro.pointing import PointingModelError, PointingPair, icrs_pair
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.images import Image, ImageProcessor, Pipeline
from nightcrew.images.astrometry import AstrometryResult, CatalogAstrometry
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.interfaces import IBinning, ICamera, IExposureTime, ImageType, IPointingSeries, ITelescope
from nightcrew.interfaces.quantities import Altitude, ExposureTime
from nightcrew.modules.module import Module
from nightcrew.modules.motion.runner import MotionRunner
from nightcrew.modules.pointing.grids import pointing_grid, sky_grid

__all__ = [
    "CSV_COLUMNS",
    "PointingRow",
    "PointingSeries",
    "exposure_start",
    "pointing_grid",
    "pointing_pairs",
    "pointing_row",
    "sky_grid",
    "solved_centre",
]

log = logging.getLogger(__name__)

ARCSEC = 3600.0


@dataclass(frozen=True)
class PointingRow:
    """One line of the CSV (see the module docstring); solved fields are None without a solution."""

    time: str
    alt_cmd: float
    az_cmd: float
    ra_cmd: float
    dec_cmd: float
    ra_solved: float | None = None
    dec_solved: float | None = None
    alt_solved: float | None = None
    az_solved: float | None = None
    dra: float | None = None
    ddec: float | None = None
    dalt: float | None = None
    daz: float | None = None
    stars: int | None = None
    rms: float | None = None
    filename: str = ""
    error: str = ""
    latitude: float | None = None
    longitude: float | None = None

    def csv(self) -> dict[str, object]:
        """The row for the CSV writer: rounded numbers, empty cells for missing values."""
        return {key: "" if value is None else _rounded(value) for key, value in asdict(self).items()}


#: Column names of the CSV, in order.
CSV_COLUMNS = tuple(PointingRow.__dataclass_fields__)


def _rounded(value: object) -> object:
    return round(value, 7) if isinstance(value, float) else value


def pointing_row(
    time: str,
    commanded_altaz: tuple[float, float],
    commanded_radec: tuple[float, float],
    solved_radec: tuple[float, float],
    solved_altaz: tuple[float, float],
    **extra: Any,
) -> PointingRow:
    """A solved row: the offsets (arcsec) of the solved from the commanded position."""
    (alt, az), (ra, dec) = commanded_altaz, commanded_radec
    (ra_s, dec_s), (alt_s, az_s) = solved_radec, solved_altaz
    return PointingRow(
        time,
        alt,
        az,
        ra,
        dec,
        ra_s,
        dec_s,
        alt_s,
        az_s,
        dra=_wrapped(ra_s - ra) * math.cos(math.radians(dec)) * ARCSEC,
        ddec=(dec_s - dec) * ARCSEC,
        dalt=(alt_s - alt) * ARCSEC,
        daz=_wrapped(az_s - az) * math.cos(math.radians(alt)) * ARCSEC,
        **extra,
    )


def _wrapped(degrees: float) -> float:
    """An angle difference in -180..180."""
    return (degrees + 180.0) % 360.0 - 180.0


class PointingSeries(Module, IPointingSeries):
    """Measures the telescope's pointing across the sky (see the module docstring).

    Args:
        telescope: Module offering ITelescope.
        camera: Module offering ICamera (IExposureTime and IBinning used if offered).
        solver: Image processors that leave a WCS in the image; default SEP detection followed by
            :class:`CatalogAstrometry` with its defaults.
        pattern: ``grid`` (rows and azimuths: ``alt_range``, ``alt_steps``, ``az_steps``) or ``sky``
            (``points`` spread over the sky between ``min_altitude`` and ``alt_range``'s highest).
        alt_range: Altitudes of the lowest and highest row, degrees.
        alt_steps: Rows of the grid.
        az_steps: Azimuths per row.
        points: Points of the ``sky`` pattern.
        min_altitude: Points below this altitude are left out, degrees.
        move: ``radec``: track the RA/Dec of each point at the moment of the move; ``altaz``: move
            to the alt/az itself (no tracking; keep exposures short).
        exposure_time: Seconds per frame.
        binning: Square binning of the frames (a wide field solves more surely), if the camera bins.
        filename: VFS path of the CSV; ``{time}`` becomes the start time (``20240115T220000``).
    """

    def __init__(
        self,
        *,
        telescope: str | ITelescope = "telescope",
        camera: str | ICamera = "camera",
        solver: ImageProcessor | None = None,
        alt_range: tuple[float, float] = (30.0, 80.0),
        alt_steps: int = 3,
        az_steps: int = 8,
        pattern: Literal["grid", "sky"] = "grid",
        points: int = 40,
        min_altitude: Altitude = 20.0,
        move: Literal["radec", "altaz"] = "radec",
        exposure_time: ExposureTime = 2.0,
        binning: int = 1,
        filename: str = "/pointing/pointing-{time}.csv",
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        low, high = alt_range
        if not 0.0 <= low <= high <= 90.0:
            raise ConfigError(
                f"need 0 <= lowest <= highest <= 90 degrees, got {list(alt_range)}", key="alt_range"
            )
        if alt_steps < 1 or az_steps < 1:
            raise ConfigError(
                f"need at least one row and one azimuth, got {alt_steps} x {az_steps}", key="alt_steps"
            )
        if move not in ("radec", "altaz"):
            raise ConfigError(f"must be 'radec' or 'altaz', got {move!r}", key="move")
        if binning < 1:
            raise ConfigError(f"must be >= 1, got {binning}", key="binning")
        if not exposure_time >= 0:
            raise ConfigError(f"must be >= 0 seconds, got {exposure_time}", key="exposure_time")
        if self.site is None:
            raise ConfigError("a pointing series needs the observatory site (alt/az to RA/Dec)", key="site")
        if pattern not in ("grid", "sky"):
            raise ConfigError(f"must be 'grid' or 'sky', got {pattern!r}", key="pattern")
        if pattern == "sky" and not (points >= 1 and min_altitude < high):
            raise ConfigError(
                f"need at least one point below the highest altitude {high}, got {points} "
                f"above {min_altitude}",
                key="points",
            )
        self._points = (
            sky_grid(points, float(min_altitude), float(high))
            if pattern == "sky"
            else pointing_grid((float(low), float(high)), alt_steps, az_steps, float(min_altitude))
        )
        if not self._points:
            raise ConfigError(f"every point of the grid is below {min_altitude} degrees", key="min_altitude")
        self._telescope, self._camera, self._move = telescope, camera, move
        self._solver = self.add_child(solver or Pipeline([SepSourceDetection(), CatalogAstrometry()]))
        self._exposure_time, self._binning, self._filename = float(exposure_time), binning, filename
        self._runner = MotionRunner("pointing series")

    @property
    def points(self) -> list[tuple[float, float]]:
        """The (alt, az) grid in the order visited."""
        return list(self._points)

    async def abort(self) -> None:
        await self._runner.stop("aborted on request")

    async def start_pointing_series(self) -> str:
        self._runner.check_idle()
        return await self._runner.run("pointing series", self._series())

    async def _series(self) -> str:
        telescope = await self.proxy(self._telescope, ITelescope)
        camera = await self.proxy(self._camera, ICamera)
        if isinstance(camera, IExposureTime):
            await camera.set_exposure_time(self._exposure_time)
        if isinstance(camera, IBinning):
            await camera.set_binning(self._binning, self._binning)
        path = self._filename.format(time=self.clock.now().strftime("%Y%m%dT%H%M%S"))
        rows: list[PointingRow] = []
        for number, (alt, az) in enumerate(self._points, start=1):
            try:
                row = await self._measure(telescope, camera, alt, az)
            except asyncio.CancelledError:
                await _quietly(camera.abort(), "abort the exposure")
                await _quietly(telescope.stop_motion(), "stop the telescope")
                raise
            rows.append(row)
            log.info(
                "%s: point %d/%d alt %.1f az %.1f: %s",
                self.name,
                number,
                len(self._points),
                alt,
                az,
                row.error or f'dRA {row.dra:.1f}" dDec {row.ddec:.1f}"',
            )
            await self.vfs.write_csv(path, [r.csv() for r in rows], fieldnames=CSV_COLUMNS)
        return path

    async def _measure(self, telescope: ITelescope, camera: ICamera, alt: float, az: float) -> PointingRow:
        """Move, expose and solve one point; a failed move or solve is a row with its error."""
        assert self.site is not None  # checked in the constructor
        lat, lon = self.site.latitude, self.site.longitude
        radec = altaz_to_radec(alt, az, lat, lon, self.clock.time())
        try:
            if self._move == "radec":
                await telescope.move_radec(*radec)
            else:
                await telescope.move_altaz(alt, az)
            filename = await camera.grab_data(False, ImageType.OBJECT)
        except NightcrewError as exc:
            return PointingRow(
                _iso(self.clock.time()),
                alt,
                az,
                *radec,
                error=f"{type(exc).__name__}: {exc}",
                latitude=lat,
                longitude=lon,
            )
        image = await Image.from_vfs(self.vfs, filename)
        start = exposure_start(image, self.clock.time())
        if self._move == "altaz":  # the grid point drifts across the sky: where it was when exposing
            radec = altaz_to_radec(alt, az, lat, lon, start)
        elif "MNT-RA" in image.header:  # a pointing model moved the mount: the model's fit needs its position
            radec = (float(image.header["MNT-RA"]), float(image.header["MNT-DEC"]))
        try:
            solved = await self._solver(image)
            ra_s, dec_s = solved_centre(solved)
        except NightcrewError as exc:
            return PointingRow(
                _iso(start),
                alt,
                az,
                *radec,
                filename=filename,
                error=f"{type(exc).__name__}: {exc}",
                latitude=lat,
                longitude=lon,
            )
        result = solved.metadata.get("astrometry")
        return pointing_row(
            _iso(start),
            (alt, az),
            radec,
            (ra_s % 360.0, dec_s),
            radec_to_altaz(ra_s, dec_s, lat, lon, start),
            stars=result.matched if isinstance(result, AstrometryResult) else None,
            rms=result.rms_arcsec if isinstance(result, AstrometryResult) else None,
            filename=filename,
            latitude=lat,
            longitude=lon,
        )


def pointing_pairs(rows: Sequence[Mapping[str, str]]) -> tuple[list[PointingPair], float]:
    """The pairs of the solved rows of a series' CSV and the site latitude (for the fit).

    Raises PointingModelError naming the row and column of a value that is missing or not a number.
    """
    pairs: list[PointingPair] = []
    latitude: float | None = None
    for number, row in enumerate(rows, start=2):  # line 1 is the header
        if row.get("error"):
            continue
        try:
            values = {key: float(row[key]) for key in _PAIR_COLUMNS}
            unix_time = datetime.fromisoformat(row["time"].replace("Z", "+00:00")).timestamp()
        except KeyError as exc:
            raise PointingModelError(
                f"line {number}: no column {exc.args[0]!r} (a pointing series CSV?)"
            ) from exc
        except ValueError as exc:
            raise PointingModelError(f"line {number}: {exc}") from exc
        latitude = values["latitude"]
        pairs.append(
            icrs_pair(
                (values["ra_cmd"], values["dec_cmd"]),
                (values["ra_solved"], values["dec_solved"]),
                values["longitude"],
                unix_time,
            )
        )
    if latitude is None:
        raise PointingModelError("no solved point in the series")
    return pairs, latitude


_PAIR_COLUMNS = ("ra_cmd", "dec_cmd", "ra_solved", "dec_solved", "latitude", "longitude")


def solved_centre(solved: Image) -> tuple[float, float]:
    """ICRS (ra, dec) of the centre of a plate-solved frame, degrees."""
    rows, cols = solved.shape
    ra, dec = (float(v[0]) for v in solved.pixel_to_sky([(cols - 1) / 2.0], [(rows - 1) / 2.0]))
    return ra, dec


def exposure_start(image: Image, default: float) -> float:
    """Unix time of the frame's DATE-OBS (``default`` without a readable one)."""
    value = image.header.get("DATE-OBS")
    if not isinstance(value, str):
        return default
    try:
        start = datetime.fromisoformat(value)
    except ValueError:
        return default
    return (start if start.tzinfo else start.replace(tzinfo=UTC)).timestamp()  # FITS times are UTC


def _iso(unix_time: float) -> str:
    return datetime.fromtimestamp(unix_time, UTC).isoformat(timespec="milliseconds").replace("+00:00", "Z")


async def _quietly(call: Awaitable[Any], what: str) -> None:
    try:
        await call
    except NightcrewError as exc:
        log.error("could not %s: %s", what, exc)
