"""The automation examples (focus model, flat fields) validate and build."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, config_files, load_config, validate_config
from nightcrew.modules import Module

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "automation"
FILES = config_files([EXAMPLES])


def test_every_automation_module_has_an_example() -> None:
    classes = {load_config(path)["class"].rsplit(".", 1)[1] for path in FILES}
    assert classes == {"FocusModel", "FlatField", "FlatFieldPointing", "FlatFieldScheduler"}


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_example_validates_and_builds(path: Path) -> None:
    config = load_config(path)
    validate_config(config, Module)
    module = build_object({**config, "name": path.stem}, Module)
    assert isinstance(module, Module)
