"""Every example under examples/sim/ is a valid configuration that builds a module."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.modules import Module

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "examples" / "sim").glob("*.yaml"))


def test_there_is_an_example_for_every_sim_device() -> None:
    classes = {load_config(path)["class"].rsplit(".", 1)[1] for path in EXAMPLES}
    expected = {"SimTelescope", "SimFocuser", "SimFilterWheel", "SimRoof", "SimDome", "SimWeatherStation"}
    assert expected <= classes


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_validates_and_builds(path: Path) -> None:
    config = load_config(path)
    validate_config(config, Module)
    module = build_object({**config, "name": path.stem}, Module)
    assert isinstance(module, Module)
