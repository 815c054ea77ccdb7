"""A night's raw frames: what each file is, and how they group into masters and science frames."""

from __future__ import annotations

import hashlib
import io
import warnings
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from astropy.io import fits  # type: ignore[import-untyped]
from astropy.utils.exceptions import AstropyUserWarning  # type: ignore[import-untyped]

from nightcrew.images.calibration import FrameKey, MasterKind, frame_key, off_set_point

__all__ = ["FrameEntry", "GroupKey", "frame_role", "group_frames", "read_entry"]

#: IMAGETYP values (lower case) and what a reduction does with them; others are ignored.
_ROLES = {
    "bias": "bias",
    "zero": "bias",
    "dark": "dark",
    "flat": "flat",
    "skyflat": "flat",
    "domeflat": "flat",
    "object": "object",
    "light": "object",
    "science": "object",
}


@dataclass(frozen=True)
class FrameEntry:
    """One raw file: its name, content checksum, role and key; ``error`` set when unreadable;
    ``off_set_point`` when it was taken off its cooling set point (no master takes it)."""

    path: Path
    sha256: str
    role: str | None
    key: FrameKey | None
    error: str | None = None
    off_set_point: bool = False


@dataclass(frozen=True, order=True)
class GroupKey:
    """Frames combined into one master: role, binning and (per role) filter or exposure time."""

    role: str
    binning: str
    filter: str = ""
    exposure_s: float = 0.0

    @property
    def master_kind(self) -> MasterKind:
        return MasterKind(self.role)

    @property
    def file_name(self) -> str:
        """Name of the master file, e.g. ``master_dark_1x1_120s.fits``."""
        parts = [f"master_{self.role}", self.binning]
        if self.filter:
            parts.append(self.filter)
        if self.role == "dark":
            parts.append(f"{self.exposure_s:g}s")
        return "_".join(parts).replace("/", "-").replace(" ", "-") + ".fits"


def frame_role(header: fits.Header) -> str | None:
    """``bias``, ``dark``, ``flat`` or ``object`` from IMAGETYP, None for anything else."""
    return _ROLES.get(str(header.get("IMAGETYP", "")).strip().lower())


def read_entry(path: Path) -> FrameEntry:
    """The entry of one file: checksum and header; a file that is not readable FITS gets ``error``."""
    content = path.read_bytes()
    digest = hashlib.sha256(content).hexdigest()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", AstropyUserWarning)  # truncated files only warn
            with fits.open(io.BytesIO(content), memmap=False) as hdul:
                hdul.verify("exception")
                header = next((h.header for h in hdul if h.is_image and h.data is not None), None)
    except (OSError, ValueError, TypeError, AstropyUserWarning, fits.VerifyError) as exc:
        return FrameEntry(path, digest, None, None, error=f"not a readable FITS file: {exc}")
    if header is None:
        return FrameEntry(path, digest, None, None, error="no image data in the FITS file")
    return FrameEntry(
        path, digest, frame_role(header), frame_key(header), off_set_point=off_set_point(header)
    )


def group_frames(entries: Iterable[FrameEntry]) -> dict[GroupKey, list[FrameEntry]]:
    """Calibration frames grouped for masters: biases by binning, darks by binning and exposure
    time, flats by binning and filter. Science frames, unreadable files and frames taken off their
    cooling set point are left out."""
    groups: dict[GroupKey, list[FrameEntry]] = defaultdict(list)
    for entry in entries:
        if entry.key is None or entry.role not in ("bias", "dark", "flat") or entry.off_set_point:
            continue
        key = GroupKey(
            role=entry.role,
            binning=entry.key.binning,
            filter=(entry.key.filter or "") if entry.role == "flat" else "",
            exposure_s=entry.key.exposure_s if entry.role == "dark" else 0.0,
        )
        groups[key].append(entry)
    return {key: sorted(groups[key], key=lambda e: e.path.name) for key in sorted(groups)}
