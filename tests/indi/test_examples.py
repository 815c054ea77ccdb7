"""The client examples in examples/indi build, and run against the simulators they name."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.interfaces import ModuleState
from nightcrew.modules import Module
from nightcrew.testing.indi import SIMULATORS, IndiServer

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "indi"
CLIENT_EXAMPLES = sorted(p for p in EXAMPLES.glob("*.yaml") if p.name != "server.yaml")


def test_there_is_an_example_for_every_indi_module() -> None:
    classes = {load_config(path)["class"].rsplit(".", 1)[1] for path in CLIENT_EXAMPLES}
    assert classes == {
        "IndiTelescope",
        "IndiCamera",
        "IndiFocuser",
        "IndiFilterWheel",
        "IndiDome",
        "IndiWeather",
        "IndiRotator",
        "IndiCoverCalibrator",
    }
    assert {load_config(path)["device"] for path in CLIENT_EXAMPLES} == set(SIMULATORS.values())


@pytest.mark.parametrize("path", CLIENT_EXAMPLES, ids=lambda p: p.name)
async def test_example_runs_against_the_simulator(
    path: Path, indi_server: IndiServer, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("INDI_IMAGES", str(tmp_path))
    config = load_config(path)
    validate_config(config, Module)
    # The examples name 127.0.0.1; the test's simulators live in their own network namespace.
    module = build_object(
        {**config, "name": path.stem, "host": indi_server.host, "port": indi_server.port}, Module
    )
    assert isinstance(module, Module)
    try:
        await module.open()
        assert module.state is ModuleState.READY, await module.get_error_string()
    finally:
        await module.close()
