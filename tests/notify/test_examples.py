"""The notification examples are valid configurations that build their modules; their policy loads."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.modules import Module
from nightcrew.modules.notify import ChatModule
from nightcrew.security import load_policy

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "notify"
ENVIRON = {
    "TELEGRAM_TOKEN": "123:token",
    "TELEGRAM_PASSWORD": "pw",
    "CHAT_PASSWORD": "pw",
    "XMPPCHAT_PASSWORD": "pw",
}


@pytest.mark.parametrize("name", ["telegram", "xmppchat"])
def test_example_validates_and_builds(name: str, tmp_path: Path) -> None:
    config = load_config(EXAMPLES / f"{name}.yaml", environ=ENVIRON)
    config["comm"]["policy"] = str(EXAMPLES / "policy.yaml")  # the example's /etc path, here
    validate_config(config, Module)
    module = build_object(config, Module)
    assert isinstance(module, ChatModule) and module.name == name
    policy = load_policy(EXAMPLES / "policy.yaml")
    assert policy.allows("alice", "roof", "close_roof", "IRoof")
    assert not policy.allows("bob", "roof", "close_roof", "IRoof")
    assert policy.allows(name, "roof", "close_roof", "IRoof")  # the module itself: what its people may
