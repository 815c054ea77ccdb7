"""The dead-man's switch of roofs and telescopes, in-process on virtual time: open for as long as the
watchdog beats, closed and parked by themselves when it stops, open again once it is back."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.errors import ConfigError, MoveError
from nightcrew.events import WatchdogHeartbeatEvent
from nightcrew.interfaces import MotionStatus
from nightcrew.modules import Module
from nightcrew.modules.safety import SafetyWatchdog
from nightcrew.modules.sim import SimRoof, SimTelescope
from nightcrew.testing import Observatory

SILENT = 60.0  # park_when_watchdog_silent, clock seconds
NIGHT = 4 * 3600.0
ROOF = Path(__file__).resolve().parents[2] / "examples" / "observatory" / "roof.yaml"


async def test_roof_open_while_the_watchdog_beats_closed_and_parked_when_it_stops(
    observatory: Observatory,
) -> None:
    switch = {"watchdog": "watchdog", "park_when_watchdog_silent": SILENT}
    await observatory.start(Module, "mastermind")
    watchdog = await observatory.start(SafetyWatchdog, "watchdog", watch={"mastermind": 300}, interval=10)
    roof = await observatory.start(SimRoof, "roof", open_time=30.0, close_time=30.0, **switch)
    telescope = await observatory.start(SimTelescope, "telescope", **switch)
    await roof.open_roof()
    await telescope.init()
    await telescope.move_altaz(45.0, 120.0)

    def closed_and_parked() -> bool:
        return roof._motion_status is MotionStatus.PARKED and telescope._motion_status is MotionStatus.PARKED

    # A whole night with a living watchdog: nothing closes.
    await observatory.clock.sleep(NIGHT)
    assert roof._motion_status is MotionStatus.IDLE and telescope._motion_status is MotionStatus.IDLE

    await watchdog.close()  # as silent as a frozen one
    took = await observatory.wait_for(closed_and_parked, SILENT + 60.0, interval=1.0)
    # the limit, one check of the switch (every 5 s) and the roof's 30 s of closing
    assert SILENT < took <= SILENT + 5.0 + 30.0 + 2.0
    with pytest.raises(
        MoveError, match=r"no heartbeat from the watchdog 'watchdog' for \d+ s \(limit 60 s\)"
    ):
        await roof.open_roof()

    # Only the named watchdog's beat counts.
    await observatory.module("mastermind", Module).comm.send_event(WatchdogHeartbeatEvent())
    await observatory.clock.sleep(1.0)
    with pytest.raises(MoveError, match="no heartbeat from the watchdog"):
        await roof.open_roof()

    await observatory.start(SafetyWatchdog, "watchdog", watch={"mastermind": 300}, interval=10)
    await observatory.clock.sleep(1.0)
    await roof.open_roof()
    assert roof._motion_status is MotionStatus.IDLE


@pytest.mark.parametrize("cls", [SimRoof, SimTelescope])
@pytest.mark.parametrize("limit", [0, -5, float("inf"), float("nan")])
def test_park_when_watchdog_silent_must_be_positive(cls: type[Module], limit: float) -> None:
    site = {"latitude": 50, "longitude": 10}
    with pytest.raises(ConfigError) as caught:
        cls(name="x", site=site, watchdog="watchdog", park_when_watchdog_silent=limit)
    assert f"key 'park_when_watchdog_silent': must be > 0 seconds (finite), got {limit}" in str(caught.value)


@pytest.mark.usefixtures("bundled_xmpp_files")  # the bundled roof.yaml names its XMPP comm
def test_check_validates_the_switch_keys(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """As docs/operations.md tells a user to add them to roof.yaml."""
    monkeypatch.chdir(tmp_path)
    switch = "watchdog: watchdog\npark_when_watchdog_silent: {}\n"
    Path("roof.yaml").write_text(f"<<: !include {ROOF}\n" + switch.format(120))
    assert main(["check", "roof.yaml"]) == 0
    Path("roof.yaml").write_text(f"<<: !include {ROOF}\n" + switch.format(0))
    assert main(["check", "roof.yaml"]) == 2
    assert capsys.readouterr().err.splitlines() == [
        "roof.yaml:3: key 'park_when_watchdog_silent': must be > 0 seconds (finite), got 0.0"
    ]
