"""What the archive checks in an uploaded file, and the header values it indexes.

An upload is accepted only as a complete FITS file (gzip-compressed when its name ends in ``.gz``):
it starts with ``SIMPLE  =  T``, is a whole number of 2880-byte blocks, every HDU's data lies
inside the file, no image declares more pixels than the configured limit, and the header (the
primary one, merged with the first extension's when the primary has no data, as in
tile-compressed files) has the required keywords :data:`REQUIRED` with usable values. Blocking
(astropy, zlib): run in a thread.
"""

from __future__ import annotations

import contextlib
import io
import math
import re
import warnings
import zlib
from dataclasses import dataclass, field
from datetime import UTC, datetime, timedelta
from typing import Any

from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.services.archive._errors import Rejected

__all__ = [
    "LINK_KEYWORDS",
    "REDUCED",
    "REQUIRED",
    "FrameFacts",
    "FrameLink",
    "check_basename",
    "declared_pixels",
    "gunzip_upload",
    "inspect_fits",
    "iso_date_obs",
]

#: Keywords every frame must have: when, with what, what kind, how long.
REQUIRED = ("DATE-OBS", "INSTRUME", "IMAGETYP", "EXPTIME")
#: RLEVEL of a reduced frame (the LCO convention; raw frames are 0).
REDUCED = 91
#: Keywords naming the frames a frame was made from: the raw frame and the masters, by basename.
LINK_KEYWORDS = {"RAWFILE": "raw", "BIASFILE": "bias", "DARKFILE": "dark", "FLATFILE": "flat"}
#: What ``nightcrew reduce`` writes today: the masters' DATE-OBS and size ("<DATE-OBS> x<N>").
_CAL_KEYWORDS = {"CAL-BIAS": "bias", "CAL-DARK": "dark", "CAL-FLAT": "flat"}
_BLOCK = 2880
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._+-]{0,199}")
_SUFFIXES = (".fits", ".fit", ".fts", ".fits.fz", ".fits.gz", ".fz")


@dataclass(frozen=True)
class FrameLink:
    """A frame this one was made from: by basename, or (``nightcrew reduce``) by master DATE-OBS."""

    role: str
    basename: str | None = None
    date_obs: str | None = None


@dataclass(frozen=True)
class FrameFacts:
    """The indexed values of one frame, and its whole header as cards."""

    date_obs: datetime
    day_obs: str
    instrument: str
    imagetyp: str
    exptime: float
    object: str | None
    filter: str | None
    proposal: str | None
    task: str | None
    rlevel: int
    ra: float | None
    dec: float | None
    cards: list[tuple[str, Any, str]]
    links: list[FrameLink] = field(default_factory=list)


def check_basename(name: str) -> str:
    """The upload's file name, refused unless a plain FITS file name."""
    if not _NAME.fullmatch(name) or ".." in name or not name.lower().endswith(_SUFFIXES):
        raise Rejected(
            400,
            f"filename {name!r} must be a plain file name (letters, digits, . _ + -; no directories) "
            f"ending in one of {', '.join(_SUFFIXES)}",
        )
    return name


_GZIP_MAGIC = b"\x1f\x8b"


def gunzip_upload(basename: str, data: bytes, max_bytes: int) -> bytes:
    """The FITS bytes of an upload: ``data`` itself, or unpacked when ``basename`` ends in ``.gz``.

    Unpacks at most ``max_bytes`` (a small gzip file may unpack to gigabytes); the compression
    must agree with the name, so that a download is what its name says.
    """
    packed = data.startswith(_GZIP_MAGIC)
    if basename.lower().endswith(".gz") != packed:
        say = "is gzip-compressed: name it .fits.gz" if packed else "ends in .gz but is not gzip-compressed"
        raise Rejected(400, f"{basename} {say}")
    if not packed:
        return data
    unpacker = zlib.decompressobj(wbits=16 + zlib.MAX_WBITS)
    try:
        fits_bytes = unpacker.decompress(data, max_bytes + 1)
    except zlib.error as exc:
        raise Rejected(400, f"{basename} is not a readable gzip file: {exc}") from None
    if len(fits_bytes) > max_bytes:
        raise Rejected(413, f"{basename} unpacks to more than the limit of {max_bytes} bytes")
    if not unpacker.eof or unpacker.unused_data:
        raise Rejected(400, f"{basename} is a truncated gzip file or holds more than one member")
    return fits_bytes


def declared_pixels(hdu: Any) -> int:
    """The pixels an image HDU's header declares (ZNAXISn when tile-compressed); 0 if none."""
    if not getattr(hdu, "is_image", False) or not hdu.shape:
        return 0
    return math.prod(int(side) for side in hdu.shape)


def inspect_fits(data: bytes, max_pixels: int) -> FrameFacts:
    """Check ``data`` is a complete FITS file with the required keywords and no image of more
    than ``max_pixels`` pixels; return what to index."""
    if not data.startswith(b"SIMPLE  =                    T"):
        raise Rejected(415, "not a FITS file: it does not start with 'SIMPLE  =  T'")
    if len(data) % _BLOCK:
        raise Rejected(
            400, f"truncated FITS file: {len(data)} bytes is not a whole number of 2880-byte blocks"
        )
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # astropy warns (not raises) about a short file
            hdus = fits.open(io.BytesIO(data), lazy_load_hdus=False, memmap=False)
            header = _merged_header(hdus, len(data))
            _check_pixels(hdus, max_pixels)
    except Rejected:
        raise
    except Exception as exc:  # astropy's parse errors have no common class
        what = "truncated FITS file" if "truncated" in str(exc) else "not a readable FITS file"
        raise Rejected(400, f"{what}: {exc}") from exc
    return _facts(header)


def _check_pixels(hdus: fits.HDUList, max_pixels: int) -> None:
    for index, hdu in enumerate(hdus):
        pixels = declared_pixels(hdu)
        if pixels > max_pixels:
            shape = " x ".join(str(side) for side in reversed(hdu.shape))
            raise Rejected(
                422,
                f"HDU {index} declares {shape} = {pixels} pixels, more than max_frame_pixels ({max_pixels})",
            )


def _merged_header(hdus: fits.HDUList, size: int) -> fits.Header:
    for index in range(len(hdus)):
        info = hdus.fileinfo(index)
        if info["datLoc"] + info["datSpan"] > size:
            raise Rejected(
                400,
                f"truncated FITS file: HDU {index}'s data ends at byte {info['datLoc'] + info['datSpan']}, "
                f"the file has {size}",
            )
    header = hdus[0].header.copy()
    if header.get("NAXIS", 0) == 0 and len(hdus) > 1:
        for card in hdus[1].header.cards:
            if card.keyword not in header and card.keyword not in ("XTENSION", "PCOUNT", "GCOUNT", ""):
                header[card.keyword] = (card.value, card.comment)
    return header


def _facts(header: fits.Header) -> FrameFacts:
    missing = [key for key in REQUIRED if key not in header or header[key] in (None, "")]
    if missing:
        raise Rejected(422, f"missing FITS keywords {', '.join(missing)} (required: {', '.join(REQUIRED)})")
    date_obs = _date_obs(header["DATE-OBS"])
    exptime = header["EXPTIME"]
    if isinstance(exptime, bool) or not isinstance(exptime, int | float) or not 0 <= exptime < math.inf:
        raise Rejected(422, f"EXPTIME must be a number of seconds >= 0, got {exptime!r}")
    day_obs = _day_obs(header.get("DAY-OBS"), date_obs, header.get("SITELONG"))
    links = [
        FrameLink(role, basename=str(header[key]).strip())
        for key, role in LINK_KEYWORDS.items()
        if header.get(key)
    ]
    for key, role in _CAL_KEYWORDS.items():
        if header.get(key) and not any(link.role == role for link in links):
            with contextlib.suppress(Rejected):  # a summary we cannot read links nothing
                master_date = _date_obs(str(header[key]).split(" x")[0])
                links.append(FrameLink(role, date_obs=iso_date_obs(master_date)))
    ra, dec = _coordinates(header)
    return FrameFacts(
        date_obs=date_obs,
        day_obs=day_obs,
        instrument=str(header["INSTRUME"]).strip(),
        imagetyp=str(header["IMAGETYP"]).strip().lower(),
        exptime=float(exptime),
        object=_text(header.get("OBJECT")),
        filter=_text(header.get("FILTER")),
        proposal=_text(header.get("PROPID", header.get("PROPOSAL"))),
        task=_text(header.get("TASK-NAM", header.get("TASK-ID"))),
        rlevel=_rlevel(header, bool(links)),
        ra=ra,
        dec=dec,
        cards=[(card.keyword, _json_value(card.value), str(card.comment)) for card in header.cards],
        links=links,
    )


def iso_date_obs(moment: datetime) -> str:
    """DATE-OBS as the index stores it: ISO, UTC, milliseconds, no zone (as FITS writes it)."""
    return moment.astimezone(UTC).replace(tzinfo=None).isoformat(timespec="milliseconds")


def _date_obs(value: Any) -> datetime:
    try:
        parsed = datetime.fromisoformat(str(value).strip())
    except ValueError:
        raise Rejected(422, f"DATE-OBS must be an ISO date and time, got {value!r}") from None
    return parsed.replace(tzinfo=UTC) if parsed.tzinfo is None else parsed.astimezone(UTC)


def _day_obs(value: Any, date_obs: datetime, longitude: Any) -> str:
    """The night's date: DAY-OBS, else the date of the local noon before DATE-OBS.

    Local mean solar time from SITELONG (east positive; 0 when missing): a night keeps one date
    even where it crosses midnight UTC.
    """
    if value in (None, ""):
        east = (
            float(longitude)
            if isinstance(longitude, int | float) and not isinstance(longitude, bool)
            else 0.0
        )
        return (date_obs + timedelta(hours=east / 15.0 - 12.0)).strftime("%Y%m%d")
    digits = str(value).replace("-", "").strip()
    if not re.fullmatch(r"\d{8}", digits):
        raise Rejected(422, f"DAY-OBS must be YYYYMMDD or YYYY-MM-DD, got {value!r}")
    return digits


def _rlevel(header: fits.Header, names_sources: bool) -> int:
    value = header.get("RLEVEL")
    if value is None:
        return REDUCED if names_sources else 0
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 255:
        raise Rejected(422, f"RLEVEL must be an integer 0..255, got {value!r}")
    return value


def _coordinates(header: fits.Header) -> tuple[float | None, float | None]:
    ra, dec = header.get("RA"), header.get("DEC")
    if ra is None or dec is None:
        return None, None
    try:
        if isinstance(ra, str) or isinstance(dec, str):  # LCO style: "hh:mm:ss", "dd:mm:ss"
            from astropy.coordinates import Angle  # type: ignore[import-untyped]

            ra_deg = float(Angle(str(ra), unit="hourangle").degree) if isinstance(ra, str) else float(ra)
            dec_deg = float(Angle(str(dec), unit="deg").degree) if isinstance(dec, str) else float(dec)
        else:
            ra_deg, dec_deg = float(ra), float(dec)
    except ValueError:
        raise Rejected(422, f"RA/DEC must be degrees or sexagesimal, got {ra!r}, {dec!r}") from None
    if not (0 <= ra_deg < 360 and -90 <= dec_deg <= 90):
        raise Rejected(422, f"RA/DEC out of range: {ra_deg}, {dec_deg}")
    return ra_deg, dec_deg


def _text(value: Any) -> str | None:
    return None if value is None or str(value).strip() == "" else str(value).strip()


def _json_value(value: Any) -> Any:
    if isinstance(value, bool | int | float | str):
        return value if not (isinstance(value, float) and not math.isfinite(value)) else str(value)
    return None if isinstance(value, fits.card.Undefined) else str(value)
