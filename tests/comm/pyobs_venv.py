"""pyobs-core 2.19.1 in a venv of its own, built from PyPI once and cached between runs.

Its dependencies differ from nightcrew's (and it is not one of ours), so it never enters our venv.
The venv lives in ``$NIGHTCREW_CACHE`` (default ``~/.cache/nightcrew``) under a name holding the
pyobs-core version, the Python version and a digest of the requirements; it is built in a
temporary directory and renamed into place, under a lock, so concurrent test runs neither build
it twice nor see half a venv.
"""

from __future__ import annotations

import fcntl
import hashlib
import logging
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

__all__ = ["PYOBS_VERSION", "pyobs_venv"]

log = logging.getLogger(__name__)

PYOBS_VERSION = "2.19.1"
#: What the venv holds: pyobs-core, and astroquery, which its telescope modules import (an extra).
REQUIREMENTS = (f"pyobs-core=={PYOBS_VERSION}", "astroquery>=0.4.10,<0.5")
_BUILD_TIMEOUT = 900.0


def _cache_root() -> Path:
    configured = os.environ.get("NIGHTCREW_CACHE")
    return Path(configured) if configured else Path.home() / ".cache" / "nightcrew"


def pyobs_venv() -> Path:
    """The venv's directory (``bin/python``, ``bin/pyobs``), built now if missing."""
    root = _cache_root()
    root.mkdir(parents=True, exist_ok=True)
    python = f"py{sys.version_info.major}{sys.version_info.minor}"
    digest = hashlib.sha256("\n".join(REQUIREMENTS).encode()).hexdigest()[:8]
    target = root / f"pyobs-core-{PYOBS_VERSION}-{python}-{digest}"
    with (root / f"{target.name}.lock").open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another run building it: wait for that one
        if (target / "ok").exists():
            return target
        started = time.monotonic()
        building = root / f"{target.name}.building"
        shutil.rmtree(building, ignore_errors=True)
        shutil.rmtree(target, ignore_errors=True)
        # The base interpreter, not ours: a venv made from inside a venv would see nightcrew's.
        base = Path(sys.base_prefix) / "bin" / f"python{sys.version_info.major}.{sys.version_info.minor}"
        _run([str(base), "-m", "venv", str(building)])
        pip = [str(building / "bin" / "python"), "-m", "pip", "install", "--quiet", "--no-input"]
        _run([*pip, *REQUIREMENTS])
        # venvs hold their own path in scripts: build under the final name's sibling, then rename
        # and repair the script headers rather than rebuilding.
        building.rename(target)
        _fix_script_paths(target, building)
        (target / "ok").write_text(f"built in {time.monotonic() - started:.0f} s\n")
        log.warning(
            "built the pyobs-core %s venv in %.0f s: %s", PYOBS_VERSION, time.monotonic() - started, target
        )
        return target


def _run(command: list[str]) -> None:
    result = subprocess.run(command, capture_output=True, text=True, timeout=_BUILD_TIMEOUT, check=False)
    if result.returncode != 0:
        raise RuntimeError(
            f"{' '.join(command[:4])} … failed:\n{result.stdout[-2000:]}{result.stderr[-2000:]}"
        )


def _fix_script_paths(target: Path, old: Path) -> None:
    """Point scripts (``bin/pyobs``, ``bin/pip``) and ``activate`` at the venv's final place."""
    for script in (target / "bin").iterdir():
        if script.is_symlink() or not script.is_file():
            continue
        try:
            text = script.read_text()
        except UnicodeDecodeError:
            continue
        if str(old) in text:
            script.write_text(text.replace(str(old), str(target)))
    config = target / "pyvenv.cfg"
    config.write_text(config.read_text().replace(str(old), str(target)))
