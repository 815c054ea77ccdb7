"""Reducing a night: masters from the calibration frames, then every science frame calibrated,
its stars detected, plate-solved (catalog matcher first, astrometry.net as fallback) and written
with its source catalog.

Output directory layout: ``masters/master_<kind>_<binning>[_<filter>][_<exptime>s].fits``, one
``<raw name>_red.fits`` per science frame (image, ``MASK``, ``CAT`` extensions), and
``summary.ecsv`` (:class:`SummaryRow` per raw file). Work already done is skipped on a re-run: a
master whose ``INPUTSUM`` (checksum of its inputs) is unchanged, and a science frame whose summary
row has the same checksum and whose output still exists. A file that cannot be read, or a frame
that cannot be reduced, is reported in the summary and the night goes on.
"""

from __future__ import annotations

import asyncio
import hashlib
import logging
import math
import os
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TextIO

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.images.astrometry import AstrometryResult
from nightcrew.images.calibration import (
    MasterInfo,
    MasterKind,
    build_master,
    frame_key,
    master_kind,
    select_master,
)
from nightcrew.images.image import Image
from nightcrew.images.reduce._frame import Master, ReductionSteps, StageTimes, reduce_frame
from nightcrew.images.reduce._inventory import FrameEntry, GroupKey, group_frames, read_entry
from nightcrew.images.reduce._summary import (
    SUMMARY_NAME,
    ProgressBar,
    SummaryRow,
    read_summary,
    write_summary,
)

__all__ = ["ReduceOptions", "find_raw_frames", "reduce_night"]

log = logging.getLogger(__name__)

_FITS_SUFFIXES = (".fits", ".fit", ".fts", ".fits.gz")


@dataclass(frozen=True)
class ReduceOptions:
    """How to reduce.

    Attributes:
        pixel_scale_arcsec: Unbinned pixel scale for the plate solvers; None: from the headers.
        index_dir: The astrometry.net index files the catalog matcher and solve-field use
            (the solve service has its own); None: the system's (``/usr/share/astrometry``).
        solver_url: The plate-solving service (``nightcrew solver``) tried after the catalog matcher.
        solve_field: Fall back to astrometry.net's solve-field when the others find nothing.
        solve_timeout_s: Limit of one solve-field run.
        detection_threshold: SEP detection threshold (sigma).
        sigma: Clipping threshold when combining masters.
        workers: Science frames reduced at once (default: one per CPU core).
    """

    pixel_scale_arcsec: float | None = None
    index_dir: str | None = None
    solver_url: str | None = None
    solve_field: bool = True
    solve_timeout_s: float = 60.0
    detection_threshold: float = 4.0
    sigma: float = 3.0
    workers: int = field(default_factory=lambda: os.cpu_count() or 1)

    def __post_init__(self) -> None:
        if self.workers < 1:
            raise ConfigError(f"workers must be >= 1, got {self.workers}")


async def reduce_night(
    raw_dir: Path,
    out_dir: Path,
    *,
    options: ReduceOptions | None = None,
    progress: TextIO | None = None,
    times: StageTimes | None = None,
) -> list[SummaryRow]:
    """Reduce the FITS files in ``raw_dir`` into ``out_dir`` (see the module docstring).

    ``times`` collects the seconds spent per stage. Raises :class:`ConfigError` when
    :func:`find_raw_frames` finds no frames.
    """
    options = options or ReduceOptions()
    times = times or StageTimes()
    files = await asyncio.to_thread(find_raw_frames, raw_dir)
    await asyncio.to_thread((out_dir / "masters").mkdir, parents=True, exist_ok=True)
    summary_path = out_dir / SUMMARY_NAME
    previous = read_summary(summary_path)
    entries = [await asyncio.to_thread(read_entry, path) for path in files]
    groups = group_frames(entries)
    science = [e for e in entries if e.role == "object"]
    bar = ProgressBar(len(groups) + len(science), progress) if progress is not None else None
    rows: dict[str, SummaryRow] = {}
    for entry in entries:
        if entry.error is not None:
            log.warning("%s: %s", entry.path.name, entry.error)
            rows[entry.path.name] = SummaryRow(
                entry.path.name, entry.sha256, "", "broken", message=entry.error
            )
        elif entry.role is None:
            rows[entry.path.name] = SummaryRow(entry.path.name, entry.sha256, "", "ignored")
        elif entry.off_set_point and entry.role != "object":
            message = "taken off its cooling set point (CCD-TEMP vs SET-TEMP): in no master"
            log.warning("%s: %s", entry.path.name, message)
            rows[entry.path.name] = SummaryRow(entry.path.name, entry.sha256, "", "ignored", message=message)

    masters: dict[str, Image] = {}
    for key, members in groups.items():
        rows.update(await _master_rows(key, members, masters, out_dir, options))
        if bar:
            bar.step(key.file_name)
    library = _library(masters)

    steps = ReductionSteps.default(
        pixel_scale_arcsec=options.pixel_scale_arcsec,
        index_dir=options.index_dir,
        solver_url=options.solver_url,
        solve_field=options.solve_field,
        solve_timeout_s=options.solve_timeout_s,
        detection_threshold=options.detection_threshold,
    )
    # Frames are reduced concurrently: their steps run in worker threads (numpy and SEP release
    # the GIL), so each core gets a frame.
    running = asyncio.Semaphore(options.workers)

    async def reduce_one(entry: FrameEntry) -> None:
        name = entry.path.name
        done = previous.get(name)
        if (
            done
            and done.status == "reduced"
            and done.sha256 == entry.sha256
            and (out_dir / done.output).exists()
        ):
            rows[name] = done
        else:
            async with running:
                rows[name] = await _reduce_frame(entry, masters, library, steps, out_dir, times)
            write_summary(summary_path, list(rows.values()))  # in the loop: one writer at a time
        if bar:
            bar.step(name)

    await asyncio.gather(*(reduce_one(entry) for entry in science))
    write_summary(summary_path, list(rows.values()))
    return sorted(rows.values(), key=lambda r: r.file)


def find_raw_frames(raw_dir: Path) -> list[Path]:
    """The FITS files (sorted) in ``raw_dir``, else in ``raw_dir/frames`` (a ``nightcrew sim`` output).

    Raises:
        ConfigError: neither holds a FITS file; the message names where it looked.
    """
    looked = []
    for directory in (raw_dir, raw_dir / "frames"):
        if directory.is_dir():
            looked.append(str(directory))
            files = sorted(
                p for p in directory.iterdir() if p.is_file() and p.name.lower().endswith(_FITS_SUFFIXES)
            )
            if files:
                return files
    suffixes = ", ".join(_FITS_SUFFIXES)
    raise ConfigError(f"no raw frames ({suffixes}) in {' or '.join(looked) or raw_dir}")


async def _master_rows(
    key: GroupKey, members: list[FrameEntry], masters: dict[str, Image], out_dir: Path, options: ReduceOptions
) -> dict[str, SummaryRow]:
    """Build (or reuse) the master of one group; add it to ``masters``; one row per input frame."""
    output = f"masters/{key.file_name}"
    path = out_dir / output
    input_sum = hashlib.sha256("".join(e.sha256 for e in members).encode()).hexdigest()[:16]
    try:
        master = await asyncio.to_thread(_blocking_existing_master, path, input_sum)
        if master is None:
            master = await asyncio.to_thread(_blocking_build_master, key, members, masters, options.sigma)
            master.header["INPUTSUM"] = (input_sum, "Checksum of the input frames")
            content = await asyncio.to_thread(master.to_bytes)
            await asyncio.to_thread(path.write_bytes, content)
    except NightcrewError as exc:
        log.warning("master %s: %s", key.file_name, exc)
        return {
            e.path.name: SummaryRow(e.path.name, e.sha256, key.role, "failed", message=str(exc))
            for e in members
        }
    masters[str(path)] = master
    return {
        e.path.name: SummaryRow(e.path.name, e.sha256, key.role, "calibration", output=output)
        for e in members
    }


def _blocking_existing_master(path: Path, input_sum: str) -> Image | None:
    """The master at ``path`` if it was built from the same inputs."""
    if not path.exists():
        return None
    try:
        master = Image.from_bytes(path.read_bytes())
    except NightcrewError:
        return None
    return master if master.header.get("INPUTSUM") == input_sum else None


def _blocking_build_master(
    key: GroupKey, members: list[FrameEntry], masters: dict[str, Image], sigma: float
) -> Image:
    frames = [Image.from_bytes(e.path.read_bytes()) for e in members]
    frame = frame_key(frames[0].header)
    library = _library(masters)
    bias = select_master(library, MasterKind.BIAS, frame)
    dark = select_master(library, MasterKind.DARK, frame) if key.master_kind is MasterKind.FLAT else None
    return build_master(
        key.master_kind,
        frames,
        bias=None if bias is None else masters[bias.path],
        dark=None if dark is None else masters[dark.path],
        sigma=sigma,
    )


def _library(masters: dict[str, Image]) -> list[MasterInfo]:
    """What the masters built so far are, keyed by their output path."""
    library = []
    for path, master in masters.items():
        kind = master_kind(master)
        if kind is not None:
            library.append(MasterInfo(path, kind, frame_key(master.header)))
    return library


async def _reduce_frame(
    entry: FrameEntry,
    masters: dict[str, Image],
    library: list[MasterInfo],
    steps: ReductionSteps,
    out_dir: Path,
    times: StageTimes,
) -> SummaryRow:
    name = entry.path.name
    row = SummaryRow(name, entry.sha256, "object", "failed")
    try:
        raw = Image.from_bytes(await asyncio.to_thread(entry.path.read_bytes))
        key = frame_key(raw.header)
        chosen = [
            select_master(library, kind, key) for kind in (MasterKind.BIAS, MasterKind.DARK, MasterKind.FLAT)
        ]
        bias, dark, flat = (None if m is None else Master(Path(m.path).name, masters[m.path]) for m in chosen)
        image, notes = await reduce_frame(
            raw, raw_name=name, steps=steps, bias=bias, dark=dark, flat=flat, times=times
        )
        output = name.split(".fits")[0].split(".fit")[0] + "_red.fits"
        started = time.perf_counter()
        content = await asyncio.to_thread(image.to_bytes)
        await asyncio.to_thread((out_dir / output).write_bytes, content)
        times.add("write", started)
    except NightcrewError as exc:
        log.warning("%s: %s", name, exc)
        return replace(row, message=str(exc))
    row = replace(
        row,
        status="reduced",
        output=output,
        stars=0 if image.catalog is None else len(image.catalog),
        message="; ".join(notes),
    )
    result = image.metadata.get("astrometry")
    if not isinstance(result, AstrometryResult):
        return row
    rows, cols = image.shape
    ra, dec = image.pixel_to_sky([(cols - 1) / 2.0], [(rows - 1) / 2.0])
    rms = math.nan if result.rms_arcsec is None else result.rms_arcsec
    return replace(row, solver=result.solver, rms_arcsec=rms, ra=float(ra[0]), dec=float(dec[0]))
