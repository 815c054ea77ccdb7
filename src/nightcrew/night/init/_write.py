"""Writing an observatory directory all at once: into a temporary folder beside it, renamed at the end.

So a failure (discovery, a full disk) leaves no half-written directory. Files with passwords get
mode 0600 and their folder 0700 from the start (never readable by others, not even briefly).
With ``force`` the files are put into an existing directory one by one (``os.replace``, each whole),
and everything else there (the task archive, the XMPP server's folder, images) is kept.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from nightcrew.errors import ConfigError

__all__ = ["write_directory"]

_PRIVATE = "secrets"


def write_directory(directory: Path, files: dict[str, str], *, force: bool = False) -> None:
    """Write ``files`` (relative path → text) as ``directory``.

    Raises:
        ConfigError: ``directory`` exists and is not empty (without ``force``), or is not a directory.
    """
    if directory.exists() and not directory.is_dir():
        raise ConfigError(f"{directory} exists and is not a directory")
    occupied = directory.is_dir() and any(directory.iterdir())
    if occupied and not force:
        raise ConfigError(
            f"{directory} is not empty; use --force to write into it (files of the same name are replaced)"
        )
    directory.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{directory.name}.init-", dir=directory.parent))
    try:
        for relative, text in files.items():
            _write_file(staging / relative, text, private=relative.startswith(f"{_PRIVATE}/"))
        if not occupied:
            staging.chmod(0o755)  # mkdtemp's 0700 would hide the directory; secrets/ keeps its own 0700
            if directory.is_dir():
                directory.rmdir()  # empty: the staging folder takes its place
            staging.replace(directory)
            return
        for relative in files:
            target = directory / relative
            target.parent.mkdir(mode=0o700 if relative.startswith(f"{_PRIVATE}/") else 0o777, exist_ok=True)
            (staging / relative).replace(target)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _write_file(path: Path, text: str, *, private: bool) -> None:
    path.parent.mkdir(mode=0o700 if private else 0o777, parents=True, exist_ok=True)
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600 if private else 0o644)
    with os.fdopen(descriptor, "w", encoding="utf-8") as file:
        file.write(text)
