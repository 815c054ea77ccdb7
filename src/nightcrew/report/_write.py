"""Writing ``report.html`` (and its thumbnails) into a night's output directory."""

from __future__ import annotations

from collections.abc import Sequence
from html import escape
from pathlib import Path

from nightcrew.report._data import Night, read_night
from nightcrew.report._metrics import night_numbers
from nightcrew.report._sections import (
    cadences_section,
    flats_section,
    focus_section,
    frames_section,
    guiding_section,
    scheduler_section,
    summary_section,
    tasks_section,
    time_budget_section,
    timeline_section,
)
from nightcrew.report._time_budget import acquisitions, time_budget
from nightcrew.report.records import NIGHT_RECORD

__all__ = ["NIGHT_RECORD", "REPORT_FILE", "THUMBNAILS", "night_site", "write_report"]

REPORT_FILE = "report.html"
THUMBNAILS = "thumbnails"

_STYLE = """
body { font-family: sans-serif; margin: 2em; color: #222; max-width: 1100px; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.5em 0; font-size: 0.9em; }
td, th { border: 1px solid #ddd; padding: 2px 6px; text-align: left; vertical-align: middle; }
th { background: #f0f0f0; }
.key { display: inline-block; width: 10px; height: 10px; margin: 0 3px 0 10px; }
.legend { font-size: 0.8em; }
"""


def night_site(night: Night) -> tuple[float, float]:
    """(latitude, longitude) of the night's record; the bundled observatory's without one."""
    for record in night.of(NIGHT_RECORD):
        site = record.data.get("site") or {}
        if "latitude" in site and "longitude" in site:
            return float(site["latitude"]), float(site["longitude"])
    return 51.56, 9.94


def write_report(
    out_dir: Path,
    *,
    thumbnails: bool = True,
    night: Night | None = None,
    cadences: Sequence[tuple[str, str]] = (),
) -> Path:
    """Read the night in ``out_dir`` (or take ``night``, read from there already) and write
    ``out_dir/report.html``; returns its path. ``cadences``: each cadence request's progress
    (name, progress) from the task archive, shown in a section of their own when there are any."""
    if night is None:
        night = read_night(out_dir)
    latitude, longitude = night_site(night)
    numbers = night_numbers(night, latitude=latitude, longitude=longitude)
    spent = time_budget(night, latitude=latitude, longitude=longitude)
    thumbs = _write_thumbnails(out_dir, night) if thumbnails else {}
    sections = [
        ("Summary", summary_section(numbers, night)),
        ("Timeline: tasks, weather, roof and Sun", timeline_section(night, numbers, latitude, longitude)),
        ("Where the good-weather dark time went", time_budget_section(spent, acquisitions(night))),
        ("Tasks", tasks_section(numbers)),
        *([("Cadences", cadences_section(cadences))] if cadences else []),
        ("Scheduler", scheduler_section(night, numbers)),
        ("Focus", focus_section(night)),
        ("Sky flats: exposure time against solar altitude", flats_section(_flat_fits(out_dir))),
        ("Guiding", guiding_section(night.frames)),
        (f"Frames ({len(night.frames)})", frames_section(night.frames, thumbs)),
    ]
    body = "".join(f"<h2>{escape(title)}</h2>{html}" for title, html in sections)
    title = f"nightcrew night report: {out_dir.name}"
    page = (
        f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>{escape(title)}</title>"
        f"<style>{_STYLE}</style></head><body><h1>{escape(title)}</h1>{body}</body></html>\n"
    )
    path = out_dir / REPORT_FILE
    path.write_text(page, encoding="utf-8")
    return path


def _flat_fits(out_dir: Path) -> dict[tuple[str, str], object]:
    """The exposure-time fits of ``nightcrew flats fit``, per filter and binning (none: empty)."""
    from nightcrew.flatfield.fit import fit_exposure_function
    from nightcrew.images.flat_frames import read_flats

    groups, levels, _ = read_flats(out_dir / "frames")
    fits: dict[tuple[str, str], object] = {}
    for group, samples in groups.items():
        try:
            fits[group] = fit_exposure_function(samples, *levels[group])
        except ValueError:  # too few flats in this group
            continue
    return fits


def _write_thumbnails(out_dir: Path, night: Night) -> dict[str, str]:
    """A small PNG per frame in ``out_dir/thumbnails`` (kept if already there); name -> relative path."""
    from astropy.io import fits  # type: ignore[import-untyped]

    from nightcrew.images.png import encode_png, stretch_to_uint8

    folder = out_dir / THUMBNAILS
    folder.mkdir(exist_ok=True)
    paths: dict[str, str] = {}
    for frame in night.frames:
        target = folder / (Path(frame.name).stem + ".png")
        if not target.is_file():
            data = fits.getdata(out_dir / "frames" / frame.name)
            target.write_bytes(encode_png(stretch_to_uint8(data, max_size=128)))
        paths[frame.name] = f"{THUMBNAILS}/{target.name}"
    return paths
