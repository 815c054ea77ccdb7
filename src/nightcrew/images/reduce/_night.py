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
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TextIO

from nightcrew.errors import NightcrewError
from nightcrew.images.astrometry import (
    AstrometryError,
    AstrometryResult,
    CatalogAstrometry,
    FirstSolution,
    SolveFieldAstrometry,
)
from nightcrew.images.calibration import (
    MasterInfo,
    MasterKind,
    build_master,
    calibrate_image,
    frame_key,
    master_kind,
    select_master,
)
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor
from nightcrew.images.processors.detection import SepSourceDetection
from nightcrew.images.processors.photometry import SepPhotometry
from nightcrew.images.reduce._inventory import FrameEntry, GroupKey, group_frames, read_entry
from nightcrew.images.reduce._summary import (
    SUMMARY_NAME,
    ProgressBar,
    SummaryRow,
    read_summary,
    write_summary,
)

__all__ = ["ReduceOptions", "reduce_night"]

log = logging.getLogger(__name__)

_FITS_SUFFIXES = (".fits", ".fit", ".fts", ".fits.gz")


@dataclass(frozen=True)
class ReduceOptions:
    """How to reduce.

    Attributes:
        pixel_scale_arcsec: Unbinned pixel scale for the plate solvers; None: from the headers.
        solve_field: Fall back to astrometry.net when the catalog matcher finds nothing.
        solve_timeout_s: Limit of one solve-field run.
        detection_threshold: SEP detection threshold (sigma).
        sigma: Clipping threshold when combining masters.
    """

    pixel_scale_arcsec: float | None = None
    solve_field: bool = True
    solve_timeout_s: float = 60.0
    detection_threshold: float = 4.0
    sigma: float = 3.0


async def reduce_night(
    raw_dir: Path, out_dir: Path, *, options: ReduceOptions | None = None, progress: TextIO | None = None
) -> list[SummaryRow]:
    """Reduce the FITS files in ``raw_dir`` into ``out_dir`` (see the module docstring)."""
    options = options or ReduceOptions()
    files = await asyncio.to_thread(_blocking_prepare, raw_dir, out_dir)
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

    masters: dict[str, Image] = {}
    for key, members in groups.items():
        rows.update(await _master_rows(key, members, masters, out_dir, options))
        if bar:
            bar.step(key.file_name)
    library = _library(masters)

    pipeline = _pipeline(options)
    for entry in science:
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
            rows[name] = await _reduce_frame(entry, masters, library, pipeline, out_dir)
            write_summary(summary_path, list(rows.values()))  # progress survives an interruption
        if bar:
            bar.step(name)
    write_summary(summary_path, list(rows.values()))
    return sorted(rows.values(), key=lambda r: r.file)


def _blocking_prepare(raw_dir: Path, out_dir: Path) -> list[Path]:
    """The raw FITS files (sorted); creates the output directories."""
    (out_dir / "masters").mkdir(parents=True, exist_ok=True)
    return sorted(p for p in raw_dir.iterdir() if p.is_file() and p.name.lower().endswith(_FITS_SUFFIXES))


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
    entry: FrameEntry, masters: dict[str, Image], library: list[MasterInfo], pipeline: _Steps, out_dir: Path
) -> SummaryRow:
    name = entry.path.name
    row = SummaryRow(name, entry.sha256, "object", "failed")
    try:
        image = Image.from_bytes(await asyncio.to_thread(entry.path.read_bytes))
        key = frame_key(image.header)
        bias = select_master(library, MasterKind.BIAS, key)
        dark = select_master(library, MasterKind.DARK, key)
        flat = select_master(library, MasterKind.FLAT, key)
        # A night without some calibration frames is still worth solving and measuring: calibrate
        # with what there is and say what was missing.
        missing = [kind.value for kind, m in ((MasterKind.DARK, dark), (MasterKind.FLAT, flat)) if m is None]
        if bias is None:
            notes = [f"not calibrated: no master bias for binning {key.binning}"]
        else:
            notes = [f"no master {', '.join(missing)}"] if missing else []
            image = await asyncio.to_thread(
                calibrate_image,
                image,
                bias=masters[bias.path],
                dark=None if dark is None else masters[dark.path],
                flat=None if flat is None else masters[flat.path],
            )
        image, message = await pipeline.run(image)
        message = "; ".join([*notes, message] if message else notes)
        output = name.split(".fits")[0].split(".fit")[0] + "_red.fits"
        content = await asyncio.to_thread(image.to_bytes)
        await asyncio.to_thread((out_dir / output).write_bytes, content)
    except NightcrewError as exc:
        log.warning("%s: %s", name, exc)
        return replace(row, message=str(exc))
    row = replace(
        row,
        status="reduced",
        output=output,
        stars=0 if image.catalog is None else len(image.catalog),
        message=message,
    )
    result = image.metadata.get("astrometry")
    if not isinstance(result, AstrometryResult):
        return row
    rows, cols = image.shape
    ra, dec = image.pixel_to_sky([(cols - 1) / 2.0], [(rows - 1) / 2.0])
    rms = math.nan if result.rms_arcsec is None else result.rms_arcsec
    return replace(row, solver=result.solver, rms_arcsec=rms, ra=float(ra[0]), dec=float(dec[0]))


@dataclass(frozen=True)
class _Steps:
    """Detection, plate solving (its failure is noted, not fatal) and aperture photometry."""

    detection: ImageProcessor
    astrometry: ImageProcessor
    photometry: ImageProcessor

    async def run(self, image: Image) -> tuple[Image, str]:
        image = await self.detection(image)
        message = ""
        try:
            image = await self.astrometry(image)
        except AstrometryError as exc:
            message = f"no astrometric solution: {exc.message.splitlines()[0]}"
        image = await self.photometry(image)
        return image, message


def _pipeline(options: ReduceOptions) -> _Steps:
    solvers: list[ImageProcessor] = [CatalogAstrometry(pixel_scale_arcsec=options.pixel_scale_arcsec)]
    if options.solve_field:
        solvers.append(
            SolveFieldAstrometry(
                pixel_scale_arcsec=options.pixel_scale_arcsec, timeout_s=options.solve_timeout_s
            )
        )
    return _Steps(
        detection=SepSourceDetection(threshold=options.detection_threshold),
        astrometry=FirstSolution(solvers),
        photometry=SepPhotometry(radii=(3.0, 6.0)),
    )
