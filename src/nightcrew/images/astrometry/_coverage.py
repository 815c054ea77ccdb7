"""Do the installed astrometry.net index files fit the camera? One line that says what to install if not.

astrometry.net finds a frame by quads of four of its stars, so the index files must hold quads
that fit inside the frame: from about 0.45 to 0.6 of its width (docs/pipeline.md lists which
index series covers which field). Debian's ``astrometry-data-tycho2`` starts at 22' quads and so
solves fields from ~40' up; a 20' field needs quads of 8'..12' (scales 4-5 of the 4200 or 5200
series). :func:`index_coverage_problem` answers for one directory and field;
:func:`observatory_coverage_problems` for a whole observatory directory (``nightcrew check``).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from nightcrew.config import load_config, to_plain
from nightcrew.errors import ConfigError
from nightcrew.sim.index_files import QUAD_FRACTIONS, index_quad_scale_arcsec, index_scales_for_field

__all__ = [
    "camera_field_arcmin",
    "camera_fields_arcmin",
    "index_coverage_problem",
    "observatory_coverage_problems",
]

DEFAULT_INDEX_DIR = "/usr/share/astrometry"
"""Where Debian's ``astrometry-data-*`` packages put their index files."""
_ARCSEC_PER_RAD = 206264.806


def _series_for(width_arcmin: float) -> str:
    """The index scales (astrometry.net's numbering) whose quads fit a field this wide."""
    scales = index_scales_for_field(width_arcmin)
    first, last = min(scales), max(scales)
    if first == last:
        return f"index files of scale {first} (astrometry.net's index-52{first:02d} or index-42{first:02d})"
    series = f"index-52{first:02d}..index-52{last:02d} or index-42{first:02d}..index-42{last:02d}"
    return f"index files of scales {first}..{last} (astrometry.net's {series})"


def index_coverage_problem(index_dir: str | Path, width_arcmin: float) -> str | None:
    """One line saying what to install when the index files of ``index_dir`` cannot solve a field
    ``width_arcmin`` wide (their smallest quads do not fit in it); None when they can or when the
    directory holds no index files (nothing installed there yet: the solvers say so themselves)."""
    directory = Path(index_dir).expanduser()
    smallest = [
        scale[0] / 60.0
        for path in sorted(directory.glob("index-*.fits"))
        if (scale := index_quad_scale_arcsec(path)) is not None
    ]
    if not smallest or min(smallest) <= QUAD_FRACTIONS[1] * width_arcmin:
        return None
    return (
        f"the camera's {width_arcmin:.3g}' field is too small for the index files in {directory} "
        f"(smallest quads {min(smallest):.3g}'): install {_series_for(width_arcmin)} and name their "
        f"directory with index_dir"
    )


def camera_field_arcmin(config: Mapping[str, Any]) -> float | None:
    """The field width (arcmin) a camera's module file states (``detector`` chip and pixel size,
    ``optics`` focal length, as the simulated camera takes them); None when it does not."""
    detector, optics = config.get("detector"), config.get("optics")
    if not isinstance(detector, Mapping) or not isinstance(optics, Mapping):
        return None
    try:
        pixels = max(float(detector["chip_width"]), float(detector["chip_height"]))
        scale = _ARCSEC_PER_RAD * float(detector["pixel_size_um"]) * 1e-3 / float(optics["focal_length_mm"])
    except (KeyError, TypeError, ValueError, ZeroDivisionError):
        return None
    return pixels * scale / 60.0


def camera_fields_arcmin(files: Iterable[Path]) -> list[float]:
    """The field widths (arcmin) the camera module files among ``files`` state."""
    fields = []
    for path in files:
        try:
            width = camera_field_arcmin(to_plain(load_config(path)))
        except ConfigError:
            continue  # reported by the file's own check
        if width is not None:
            fields.append(width)
    return fields


def _index_dirs(node: Any) -> Iterable[str]:
    """The index directories the astrometry processors anywhere in a module's config solve with."""
    if isinstance(node, Mapping):
        kind = str(node.get("class", ""))
        bare_solve_field = kind.endswith("SolveFieldAstrometry") and "solver" not in node
        system_config = kind.endswith(".SolveField") and "config" not in node
        if kind.endswith("CatalogAstrometry") or bare_solve_field or system_config:
            yield str(node.get("index_dir") or DEFAULT_INDEX_DIR)
        for value in node.values():
            yield from _index_dirs(value)
    elif isinstance(node, list):
        for value in node:
            yield from _index_dirs(value)


def observatory_coverage_problems(files: Iterable[Path]) -> list[str]:
    """For the module files of one observatory: a line per index directory its solvers use that
    cannot solve the smallest field any of its cameras states."""
    configs = []
    for path in files:
        try:
            configs.append(to_plain(load_config(path)))
        except ConfigError:
            continue  # reported by the file's own check
    fields = [width for config in configs if (width := camera_field_arcmin(config)) is not None]
    if not fields:
        return []
    directories = sorted({directory for config in configs for directory in _index_dirs(config)})
    problems = [index_coverage_problem(directory, min(fields)) for directory in directories]
    return [problem for problem in problems if problem is not None]
