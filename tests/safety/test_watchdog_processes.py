"""The safety watchdog and the roof's own offline rule, with every module a supervised process on Prosody.

The roof and telescope are the bundled simulated ones (examples/sim-processes), the mastermind a
plain module under that name, all on one accelerated clock (10 clock seconds per wall second).
"""

from __future__ import annotations

import asyncio
import logging
import os
import signal
import time
from collections.abc import AsyncIterator
from datetime import UTC, datetime, timedelta
from pathlib import Path

import pytest

from nightcrew.clock import AcceleratedClock
from nightcrew.errors import MoveError
from nightcrew.events import SafetyAlarmEvent, SafetyClearedEvent
from nightcrew.interfaces import IMotion, IRoof, ITelescope, MotionStatus
from nightcrew.modules import Module
from nightcrew.testing import modules_ready, wait_for
from tests.comm.xmpp_servers import DOMAIN, PASSWORD
from tests.modules.sim_processes import starting_policy_file
from tests.supervisor.conftest import REPOSITORY, START_TIMEOUT, SupervisedDirectory

pytestmark = pytest.mark.xmpp
log = logging.getLogger(__name__)
OVERLAYS = REPOSITORY / "examples" / "sim-processes"
SPEED = 10.0
CLOCK_START = "2026-11-10T17:50:00"
MODULES = ["roof", "telescope", "mastermind", "watchdog"]


def write_observatory(supervised: SupervisedDirectory, *, park_when_offline: float = 300) -> None:
    for name in MODULES:
        supervised.prosody.account(name)
    for name in ("roof", "telescope"):
        extra = f"park_when_offline: {park_when_offline}\n"
        (supervised.directory / f"{name}.yaml").write_text(f"<<: !include {OVERLAYS / name}.yaml\n{extra}")
    overlay = (
        f"comm:\n  <<: !include {OVERLAYS}/xmpp.yaml\n  jid: {{name}}@{DOMAIN}\n"
        f"clock: !include {OVERLAYS}/clock.yaml\n"
    )
    (supervised.directory / "mastermind.yaml").write_text(
        "class: nightcrew.modules.Module\n" + overlay.format(name="mastermind")
    )
    (supervised.directory / "watchdog.yaml").write_text(
        "class: nightcrew.modules.safety.SafetyWatchdog\n"
        "watch: {mastermind: 15}\nroof: roof\ntelescope: telescope\ninterval: 2\nanswer_timeout: 3\n"
        + overlay.format(name="watchdog")
    )
    (supervised.directory / "xmpp.yaml").unlink()  # the overlays bring their own


@pytest.fixture
def wall_start() -> str:
    return (datetime.now(UTC) + timedelta(seconds=1)).strftime("%Y-%m-%dT%H:%M:%S")


@pytest.fixture
def sim_env(
    supervised: SupervisedDirectory, wall_start: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """What the overlays read, for the supervisor (and so its modules) started by the test."""
    prosody = supervised.prosody
    for key, value in {
        "SIM_XMPP_PASSWORD": PASSWORD,
        "SIM_XMPP_SERVER": prosody.address,
        "SIM_XMPP_DOMAIN": DOMAIN,
        "SIM_XMPP_ROOM": supervised.room,
        "SIM_XMPP_CA_FILE": str(prosody.ca_file),
        "SIM_XMPP_POLICY": starting_policy_file(tmp_path, DOMAIN),
        "SIM_CLOCK_START": CLOCK_START,
        "SIM_CLOCK_SPEED": str(SPEED),
        "SIM_WALL_START": wall_start,
        "SIM_IMAGES": str(tmp_path / "images"),
    }.items():
        monkeypatch.setenv(key, value)


@pytest.fixture
async def driver(supervised: SupervisedDirectory, wall_start: str, sim_env: None) -> AsyncIterator[Module]:
    module = Module(
        comm=supervised.operator_comm(), clock=AcceleratedClock(CLOCK_START, SPEED, wall_start=wall_start)
    )
    await module.open()
    try:
        yield module
    finally:
        await module.close()


async def status_of(driver: Module, name: str) -> MotionStatus:
    return MotionStatus(await (await driver.comm.proxy(name, IMotion)).get_motion_status())


async def open_up(driver: Module) -> None:
    roof, telescope = await driver.comm.proxy("roof", IRoof), await driver.comm.proxy("telescope", ITelescope)
    await asyncio.wait_for(asyncio.gather(roof.open_roof(), telescope.init()), 60)
    await asyncio.wait_for(telescope.move_altaz(45.0, 120.0), 60)


async def test_frozen_mastermind_roof_closed_and_telescope_parked_within_60_clock_seconds(
    supervised: SupervisedDirectory, driver: Module
) -> None:
    write_observatory(supervised)
    supervised.up()
    clock = driver.clock
    await wait_for(
        lambda: modules_ready(driver, MODULES), START_TIMEOUT * SPEED, clock=clock, message="modules ready"
    )
    alarms: list[SafetyAlarmEvent] = []
    cleared = asyncio.Event()

    async def on_alarm(event: SafetyAlarmEvent, sender: str) -> None:
        alarms.append(event)

    async def on_cleared(event: SafetyClearedEvent, sender: str) -> None:
        cleared.set()

    await driver.comm.register_event(SafetyAlarmEvent, on_alarm)
    await driver.comm.register_event(SafetyClearedEvent, on_cleared)
    await open_up(driver)
    assert await status_of(driver, "roof") is MotionStatus.IDLE  # open

    mastermind = (await supervised.status())["mastermind"]["pid"]
    os.kill(mastermind, signal.SIGSTOP)
    try:
        took = await wait_for(
            lambda: _both_parked(driver), 60, clock=clock, message="roof closed and telescope parked"
        )
        assert took <= 60
        log.info("roof closed and telescope parked %.1f clock s after SIGSTOP", took)
        assert alarms and alarms[0].reason.startswith("mastermind: no answer for ")
        # the alarm holds: the roof refuses to open while the mastermind is still frozen
        with pytest.raises(MoveError, match=r"safety alarm \(mastermind: no answer for "):
            await (await driver.comm.proxy("roof", IRoof)).open_roof()
    finally:
        os.kill(mastermind, signal.SIGCONT)
    # heartbeats back: the alarm clears, the roof may open again (the supervisor never restarted it)
    await asyncio.wait_for(cleared.wait(), 30)
    await asyncio.wait_for((await driver.comm.proxy("roof", IRoof)).open_roof(), 60)
    assert (await supervised.status())["mastermind"]["restarts"] == 0
    # a clean stop closes the open roof first (park_on_close in the overlays)
    assert supervised.terminate() == 0
    roof_log = (supervised.log_dir / "roof.log").read_text()
    assert "roof: parking before closing" in roof_log
    assert "roof: motion status parking -> parked" in roof_log.split("roof: parking before closing")[-1]


async def _roof_is(driver: Module, status: MotionStatus) -> bool:
    return await status_of(driver, "roof") is status


async def _both_parked(driver: Module) -> bool:
    roof, telescope = await status_of(driver, "roof"), await status_of(driver, "telescope")
    return roof is MotionStatus.PARKED and telescope is MotionStatus.PARKED


async def test_prosody_killed_roof_closes_by_itself_and_everything_is_back_within_10_s(
    supervised: SupervisedDirectory, driver: Module
) -> None:
    write_observatory(supervised, park_when_offline=20)  # 2 wall seconds at this speed
    supervised.up()
    clock = driver.clock
    await wait_for(
        lambda: modules_ready(driver, MODULES), START_TIMEOUT * SPEED, clock=clock, message="modules ready"
    )
    await open_up(driver)
    prosody = supervised.prosody
    logs = [supervised.log_dir / f"{name}.log" for name in ("roof", "telescope")]

    os.kill(prosody.pid(), signal.SIGKILL)
    try:
        # Roof and telescope hear nobody: they park by themselves (their logs say so, while the
        # server is down).
        await wait_for(
            lambda: all("no connection to the other modules" in p.read_text() for p in logs),
            60 * SPEED, clock=clock, message="roof closing and telescope parking without the server",
        )  # fmt: skip
    finally:
        prosody.start()
    restarted = time.monotonic()
    await wait_for(lambda: modules_ready(driver, MODULES), 30 * SPEED, clock=clock, message="modules back")
    back = time.monotonic() - restarted
    assert back <= 10, f"modules back after {back:.1f} s"
    log.info("every module back %.1f s after Prosody's restart", back)
    # both finish (the roof closes in 30 clock s) without being told to: one rule for both
    await wait_for(
        lambda: _both_parked(driver),
        60,
        clock=clock,
        message="roof closed and telescope parked by themselves",
    )
    status = await supervised.status()
    assert all(status[name]["restarts"] == 0 for name in MODULES)  # reconnected, not restarted
    assert supervised.terminate() == 0
