"""Every example of the simulated observatory is a valid configuration that builds a module.

The files live in ``examples/observatory``; the package's ``nightcrew/night/observatory`` is a
link to that directory (a built package holds a copy), so the examples and what ``nightcrew sim``
runs are the same files. ``nightcrew sim`` reads them with :func:`files_environ` and replaces the
``comm`` and ``clock`` they name for ``nightcrew up`` (tests/supervisor/test_observatory_up.py runs
them that way).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, config_files, load_config, validate_config
from nightcrew.modules import Module
from nightcrew.night.build import bundled_observatory, files_environ

REPOSITORY = Path(__file__).resolve().parents[2]
EXAMPLES = config_files([bundled_observatory()], environ=files_environ())
#: What `nightcrew sim` puts in place of the files' own.
REPLACED = ("comm", "clock")


def test_examples_observatory_is_the_bundled_observatory() -> None:
    observatory = REPOSITORY / "examples" / "observatory"
    assert observatory.is_dir() and not observatory.is_symlink()  # the one source
    assert bundled_observatory().resolve() == observatory.resolve()
    assert (REPOSITORY / "examples" / "sim").resolve() == observatory.resolve()  # the older name


def test_there_is_an_example_for_every_sim_device() -> None:
    classes = {load_config(path, environ=files_environ())["class"].rsplit(".", 1)[1] for path in EXAMPLES}
    expected = {
        "SimTelescope",
        "SimFocuser",
        "SimFilterWheel",
        "SimRoof",
        "SimDome",
        "SimWeatherStation",
        "SimCamera",
    }
    assert expected <= classes


def test_the_site_fragment_is_not_a_module_file() -> None:
    assert all(path.name != "site.yaml" for path in EXAMPLES)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_validates_and_builds(path: Path) -> None:
    config = load_config(path, environ=files_environ())
    validate_config(config, Module)
    kept = {key: value for key, value in config.items() if key not in REPLACED}
    module = build_object({**kept, "name": path.stem}, Module)
    assert isinstance(module, Module)
