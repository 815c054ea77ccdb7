"""The automation examples are valid configurations that build their modules."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.modules import Module

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"
NAMES = [
    "weather",
    "trigger",
    "kiosk",
    "autonomous_warning",
    "image_writer",
    "image_watcher",
    "http_file_cache",
]


@pytest.mark.parametrize("name", NAMES)
def test_example_validates_and_builds(name: str) -> None:
    config = load_config(EXAMPLES / f"{name}.yaml", environ={})
    validate_config(config, Module)
    module = build_object({**config, "name": name}, Module)
    assert isinstance(module, Module)
    assert type(module).__name__.lower().replace("_", "") == name.replace("_", "")
