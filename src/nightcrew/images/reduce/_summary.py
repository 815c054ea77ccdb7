"""The night's summary table (one row per raw file) and a small progress bar for the terminal."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import TextIO

import numpy as np
from astropy.table import Table  # type: ignore[import-untyped]

__all__ = ["SUMMARY_NAME", "ProgressBar", "SummaryRow", "read_summary", "write_summary"]

SUMMARY_NAME = "summary.ecsv"


@dataclass(frozen=True)
class SummaryRow:
    """What happened to one raw file.

    ``status`` is ``reduced`` (science frame written to ``output``), ``calibration`` (went into the
    master named in ``output``), ``failed`` (a science frame that could not be reduced: see
    ``message``), ``broken`` (not a readable FITS file) or ``ignored`` (an image type not reduced,
    or a calibration frame taken off its cooling set point).
    """

    file: str
    sha256: str
    role: str
    status: str
    output: str = ""
    solver: str = ""
    stars: int = 0
    rms_arcsec: float = math.nan
    ra: float = math.nan
    dec: float = math.nan
    message: str = ""


def write_summary(path: Path, rows: list[SummaryRow]) -> None:
    """Write ``rows`` as an ECSV table (sorted by file name), replacing the file atomically."""
    names = [f.name for f in fields(SummaryRow)]
    ordered = sorted(rows, key=lambda r: r.file)
    table = (
        Table(rows=[tuple(asdict(r).values()) for r in ordered], names=names)
        if ordered
        else Table(names=names)
    )
    temporary = path.with_suffix(".tmp.ecsv")
    table.write(temporary, format="ascii.ecsv", overwrite=True)
    temporary.replace(path)


def read_summary(path: Path) -> dict[str, SummaryRow]:
    """Rows of an earlier run by file name; empty when there is none (or it is unreadable)."""
    if not path.exists():
        return {}
    try:
        table = Table.read(path, format="ascii.ecsv")
    except (OSError, ValueError):
        return {}
    if not {f.name for f in fields(SummaryRow)} <= set(table.colnames):
        return {}  # written by another version: start afresh
    rows: dict[str, SummaryRow] = {}
    for r in table:
        rows[_text(r["file"])] = SummaryRow(
            file=_text(r["file"]),
            sha256=_text(r["sha256"]),
            role=_text(r["role"]),
            status=_text(r["status"]),
            output=_text(r["output"]),
            solver=_text(r["solver"]),
            stars=int(r["stars"]),
            rms_arcsec=float(r["rms_arcsec"]),
            ra=float(r["ra"]),
            dec=float(r["dec"]),
            message=_text(r["message"]),
        )
    return rows


def _text(value: object) -> str:
    """A string cell; ECSV reads empty strings back as masked."""
    return "" if np.ma.is_masked(value) else str(value)


class ProgressBar:
    """``[#####-----] 12/40 name`` on one line of ``stream`` (redrawn in place on a terminal)."""

    def __init__(self, total: int, stream: TextIO, *, width: int = 30) -> None:
        self.total = max(total, 1)
        self.stream = stream
        self.width = width
        self.done = 0
        self._tty = stream.isatty()

    def step(self, label: str) -> None:
        self.done += 1
        filled = round(self.width * self.done / self.total)
        line = f"[{'#' * filled}{'-' * (self.width - filled)}] {self.done}/{self.total} {label}"
        if self._tty:
            self.stream.write(f"\r\x1b[K{line}")
            if self.done >= self.total:
                self.stream.write("\n")
        else:
            self.stream.write(line + "\n")
        self.stream.flush()
