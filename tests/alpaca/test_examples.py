"""examples/alpaca: every file passes `nightcrew check`, the client modules' files drive
alpaca-simulators, and a bad Alpaca config is one line naming file, line and key."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.interfaces import ModuleState
from nightcrew.modules import Module
from nightcrew.modules.alpaca import AlpacaCamera, AlpacaFilterWheel, AlpacaFocuser, AlpacaTelescope
from nightcrew.testing.alpaca import AlpacaSimulator

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "alpaca"
CLIENT_EXAMPLES = {
    "telescope.yaml": AlpacaTelescope,
    "camera.yaml": AlpacaCamera,
    "focuser.yaml": AlpacaFocuser,
    "filterwheel.yaml": AlpacaFilterWheel,
}


def nightcrew_check(*paths: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "nightcrew", "check", *map(str, paths)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def test_nightcrew_check_accepts_every_example() -> None:
    result = nightcrew_check(EXAMPLES)
    assert result.returncode == 0, result.stderr
    checked = {line.removeprefix("OK ").rsplit("/", 1)[-1] for line in result.stdout.splitlines()}
    assert set(CLIENT_EXAMPLES) <= checked


@pytest.mark.parametrize(("file", "cls"), CLIENT_EXAMPLES.items(), ids=list(CLIENT_EXAMPLES))
async def test_client_example_builds_and_connects(
    file: str, cls: type[Module], alpaca_simulator: AlpacaSimulator, tmp_path: Path
) -> None:
    config = load_config(EXAMPLES / file)
    validate_config(config, Module)
    # The examples name the usual port 11111; the session's simulator stands in for it.
    overrides: dict[str, Any] = {"name": file.removesuffix(".yaml"), "server": alpaca_simulator.url}
    if "vfs" in config:
        overrides["vfs"] = {"class": "nightcrew.vfs.VirtualFileSystem", "roots": {}}
    module = build_object({**config, **overrides}, Module)
    assert type(module) is cls
    try:
        await module.open()
        assert module.state is ModuleState.READY, await module.get_error_string()
    finally:
        await module.close()


@pytest.mark.parametrize(
    ("text", "line"),
    [
        (
            "class: nightcrew.modules.alpaca.AlpacaToaster\nserver: http://127.0.0.1:11111\n",
            "bad.yaml:1: key 'class': 'nightcrew.modules.alpaca' has no attribute 'AlpacaToaster'",
        ),
        (
            "class: nightcrew.modules.alpaca.AlpacaFocuser\nserver: htp//127.0.0.1:11111\n",
            "bad.yaml:2: key 'server': an Alpaca server URL starts with http:// or https://, "
            "got 'htp//127.0.0.1:11111'",
        ),
        (
            "class: nightcrew.modules.alpaca.AlpacaCamera\ndevice_number: 0\nserver: http://host:11111/api/v1\n",
            "bad.yaml:3: key 'server': an Alpaca server URL is only scheme://host:port",
        ),
        (
            "class: nightcrew.modules.alpaca.AlpacaFilterWheel\nserver: http://h:1\ndevice_number: one\n",
            "bad.yaml:3: key 'device_number': ",
        ),
    ],
)
def test_a_bad_alpaca_config_is_one_line(tmp_path: Path, text: str, line: str) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    result = nightcrew_check(path)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(str(tmp_path)) and line in lines[0], result.stderr
