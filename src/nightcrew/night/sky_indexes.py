"""The simulated sky's astrometry.net index files for a night's fields, built before the night starts.

A real observatory installs the index series that fits its camera before its first night; the
simulated observatory builds its sky's (:mod:`nightcrew.sim.sky_index`) for the fields its tasks
point at, with the simulated camera's seed, depth and field from its module file. The solvers find
them where the observatory files say (``index_dir: ~/.cache/nightcrew/indexes/seed42-G16``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

from nightcrew.config import to_plain
from nightcrew.night.build import load_in_process
from nightcrew.robotic.tasks import RequestGroup
from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.render import CameraModel, Optics
from nightcrew.sim.sky_index import SkyIndexBuilder

__all__ = ["build_night_sky_indexes", "task_fields"]

_SIM_CAMERA = "nightcrew.modules.sim.SimCamera"


def task_fields(tasks: Sequence[RequestGroup]) -> list[tuple[float, float]]:
    """RA, Dec (deg) of every sidereal target of ``tasks``, each once, in task order."""
    fields: dict[tuple[float, float], None] = {}
    for group in tasks:
        for request in group.requests:
            for configuration in request.configurations:
                ra, dec = (
                    getattr(configuration.target, "ra", None),
                    getattr(configuration.target, "dec", None),
                )
                if isinstance(ra, float) and isinstance(dec, float):
                    fields[(ra, dec)] = None
    return list(fields)


def build_night_sky_indexes(
    directory: Path,
    tasks: Sequence[RequestGroup],
    *,
    environ: Mapping[str, str] | None = None,
    seed: int | None = None,
    progress: Callable[[str], None] | None = None,
) -> Path | None:
    """Build the index files the night's frames need; their directory (None: no simulated camera).

    ``directory`` is the observatory directory (its ``camera.yaml``, read with the variables
    ``environ`` as the night reads it, e.g. its chip size) and ``seed`` the night's seed (default:
    the file's).
    """
    path = directory / "camera.yaml"
    camera = to_plain(load_in_process(path, environ)) if path.is_file() else {}
    if camera.get("class") != _SIM_CAMERA:
        return None
    detector = CameraModel(**{**to_plain(camera.get("detector") or {})})
    optics = Optics(**{**to_plain(camera.get("optics") or {})})
    width_px = max(detector.chip_width, detector.chip_height)
    width_arcmin = width_px * optics.pixel_scale_arcsec(detector.pixel_size_um) / 60.0
    sky = StarCatalog(
        seed=int(camera.get("seed", 0) if seed is None else seed),
        depth=float(camera.get("catalog_depth", 16.0)),
    )
    fields = [(ra, dec) for ra, dec in task_fields(tasks) if math.isfinite(ra) and math.isfinite(dec)]
    return SkyIndexBuilder(sky, progress=progress).blocking_build(fields, width_arcmin=[width_arcmin])
