"""``nightcrew init DIR --indi HOST:PORT`` against the indi-bin simulators (indiserver in a network
namespace of its own, reached like a remote server): the directory is written and checked.

Without indi-bin or root the test skips, except under CI=true, where it fails.
"""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.clock import RealClock
from nightcrew.config import load_config
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.indi import IndiRoof
from nightcrew.testing import Observatory
from nightcrew.testing.indi import IndiServer
from tests.observatory.simulators import run_indi_simulators, server_init


@pytest.fixture(scope="module")
def indi_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[IndiServer]:
    yield from run_indi_simulators(tmp_path_factory.mktemp("indiserver"))


def test_init_writes_the_indi_simulators_by_role(
    indi_server: IndiServer,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    directory = tmp_path / "observatory"
    site = ["--latitude", "51.5", "--longitude", "9.9"]
    server = f"{indi_server.host}:{indi_server.port}"
    assert main(["init", str(directory), "--non-interactive", "--indi", server, *site]) == 0
    out = capsys.readouterr().out
    written = out.splitlines()[0].removeprefix(f"wrote {directory}: ").split(", ")
    roles = ["telescope", "camera", "dome", "focuser", "filters", "rotator", "conditions", "cover"]
    assert written[:8] == roles
    expected = {
        "telescope": "Telescope Simulator",
        "camera": "CCD Simulator",
        "dome": "Dome Simulator",
        "focuser": "Focuser Simulator",
        "filters": "Filter Simulator",
        "rotator": "Rotator Simulator",
        "conditions": "Weather Simulator",
        "cover": "Light Panel Simulator",
    }
    for name, device in expected.items():
        config = load_config(directory / f"{name}.yaml")
        assert (config["host"], config["port"], config["device"]) == (
            indi_server.host,
            indi_server.port,
            device,
        )
    weather = load_config(directory / "weather.yaml")
    assert list(weather["checks"]) == ["conditions.safe"]  # the INDI weather driver's own verdict
    assert load_config(directory / "mastermind.yaml")["roof"] == "dome"
    server_init(directory, monkeypatch)
    assert main(["check", "."]) == 0


def test_an_indi_server_that_is_not_there(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    args = ["init", str(tmp_path / "o"), "--non-interactive", "--latitude", "1", "--longitude", "2"]
    assert main([*args, "--indi", "127.0.0.1:9"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("nightcrew: error: INDI server 127.0.0.1:9: no connection") and "\n" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def roll_off_server(tmp_path: Path) -> Iterator[IndiServer]:
    yield from run_indi_simulators(tmp_path / "indiserver", ["indi_rolloff_dome"])


def test_a_roll_off_roof_is_named_roof_and_opened_by_unparking(
    roll_off_server: IndiServer, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """indi_rolloff_dome is a DOME device like the dome simulator; its driver's name says roll-off,
    so init names it ``roof`` and writes the IndiRoof module (DOME_PARK), which drives it."""
    server = roll_off_server
    directory = tmp_path / "observatory"
    site = ["--latitude", "51.5", "--longitude", "9.9", "--comm", "embedded"]
    args = ["init", str(directory), "--non-interactive", "--indi", f"{server.host}:{server.port}", *site]
    assert main(args) == 0
    assert capsys.readouterr().out.startswith(f"wrote {directory}: roof, ")
    config = load_config(directory / "roof.yaml")
    assert (config["class"], config["device"]) == ("nightcrew.modules.indi.IndiRoof", "RollOff Simulator")
    asyncio.run(_close(server.host, server.port, "RollOff Simulator"))


async def _close(host: str, port: int, device: str) -> None:
    """The roof module reads the simulator open, closes it and reads it closed."""
    async with Observatory(clock=RealClock()) as obs:
        roof = await obs.start(IndiRoof, "roof", host=host, port=port, device=device)
        assert await roof.get_motion_status() is MotionStatus.IDLE  # the simulator starts open
        await roof.close_roof()  # 10 wall seconds in the simulator
        assert await roof.get_motion_status() is MotionStatus.PARKED
        assert roof._indi.vector("DOME_PARK").members["PARK"] is True
