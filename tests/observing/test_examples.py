"""The examples under examples/observing are valid configurations that build their modules."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.modules import Module

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "examples" / "observing").glob("*.yaml"))


def test_every_module_has_an_example() -> None:
    names = {path.stem for path in EXAMPLES}
    assert {"autofocus", "acquisition", "guiding", "science_guiding", "seeing"} <= names


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_validates_and_builds(path: Path) -> None:
    config = load_config(path)
    validate_config(config, Module)
    assert isinstance(build_object({**config, "name": path.stem}, Module), Module)
