"""Reading a night's twilight sky flats from FITS files, for fitting exposure-time functions.

Used by ``nightcrew flats fit`` and by the night report. The solar altitude comes from the
``SUNALT`` card the flat-fielder writes, else from DATE-OBS and the site cards (SITELAT,
SITELONG); target and bias levels from ``FLATTGT``/``FLATBIAS`` unless given. Saturated or nearly
empty frames are left out, with the reason.
"""

from __future__ import annotations

from collections import defaultdict
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

__all__ = ["Group", "read_flats"]

#: A frame whose median is above this fraction of SATURATE is left out.
_SATURATED = 0.9
#: A frame with less than this fraction of the target signal is left out (roof closed, night).
_TOO_FAINT = 0.05

Group = tuple[str, str]  # (filter, binning)


def read_flats(
    directory: Path, target: float | None = None, bias: float | None = None
) -> tuple[dict[Group, list[Any]], dict[Group, tuple[float, float]], list[str]]:
    """Usable flats per (filter, binning), their (target, bias) levels, and what was skipped why."""
    import numpy as np
    from astropy.io import fits  # type: ignore[import-untyped]

    from nightcrew.flatfield.fit import FlatSample

    groups: dict[Group, list[FlatSample]] = defaultdict(list)
    levels: dict[Group, tuple[float, float]] = {}
    skipped: list[str] = []
    for path in sorted(directory.rglob("*.fits*")):
        try:
            with fits.open(path) as hdus:
                header, data = hdus[0].header, hdus[0].data
                if str(header.get("IMAGETYP", "")).lower() != "skyflat":
                    continue
                if data is None:
                    raise ValueError("no image data")
                level = float(np.median(data))
            altitude = _sun_altitude(header)
            exposure = float(header["EXPTIME"])
        except (OSError, ValueError, KeyError, TypeError) as exc:
            skipped.append(f"{path.name}: {exc}")
            continue
        group = (
            str(header.get("FILTER", "none")),
            f"{header.get('XBINNING', 1)}x{header.get('YBINNING', 1)}",
        )
        want = float(target if target is not None else header.get("FLATTGT", 30000.0))
        floor = float(bias if bias is not None else header.get("FLATBIAS", 0.0))
        saturate = float(header.get("SATURATE", 65535))
        if level >= _SATURATED * saturate:
            skipped.append(f"{path.name}: saturated (median {level:.0f} ADU)")
            continue
        if level - floor < _TOO_FAINT * (want - floor):
            skipped.append(f"{path.name}: too faint (median {level:.0f} ADU)")
            continue
        groups[group].append(FlatSample(altitude, exposure, level))
        levels.setdefault(group, (want, floor))
    return dict(groups), levels, skipped


def _sun_altitude(header: Any) -> float:
    """SUNALT, else the Sun's altitude at DATE-OBS seen from SITELAT/SITELONG."""
    if "SUNALT" in header:
        return float(header["SUNALT"])
    from nightcrew.astro import sun_altitude

    if not {"DATE-OBS", "SITELAT", "SITELONG"} <= set(header):
        raise ValueError("no SUNALT card and no DATE-OBS/SITELAT/SITELONG to compute it")
    start = datetime.fromisoformat(str(header["DATE-OBS"]))
    if start.tzinfo is None:  # FITS times are UTC
        start = start.replace(tzinfo=UTC)
    return sun_altitude(float(header["SITELAT"]), float(header["SITELONG"]), start.timestamp())
