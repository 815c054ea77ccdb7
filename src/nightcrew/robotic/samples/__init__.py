"""Sample request groups for the simulated night (2026-11-10 at the sim's site, Göttingen).

Ten YAML files, one request group each, valid under :mod:`nightcrew.robotic.tasks` and placed
so their targets are up (within their airmass limits) in their windows on the night that
``nightcrew sim`` runs: globular and open clusters (M15, the Pleiades, h and chi Persei, M52 with
an auto-focus first), galaxies (M31, M33, NGC 7331), a light curve of Algol (REPEAT_EXPOSE),
twilight sky flats and bias/dark frames. Try them with::

    nightcrew tasks add $(python -c "import nightcrew.robotic.samples as s; print(*s.sample_paths())")
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from nightcrew.robotic.tasks import RequestGroup, load_request_group_file

__all__ = ["load_samples", "sample_paths"]


def sample_paths() -> list[Path]:
    """The sample files, by name."""
    folder = resources.files(__name__)
    return sorted(Path(str(entry)) for entry in folder.iterdir() if entry.name.endswith(".yaml"))


def load_samples() -> dict[str, RequestGroup]:
    """The validated sample groups, by file stem."""
    return {path.stem: load_request_group_file(path) for path in sample_paths()}
