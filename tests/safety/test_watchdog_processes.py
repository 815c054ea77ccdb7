"""The safety watchdog, the roof's own offline rule and its dead-man's switch, and the supervisor's
frozen-process watch, with every module a supervised process on Prosody.

The roof and telescope are the bundled simulated ones (examples/sim-processes), the mastermind a
plain module under that name, all on one accelerated clock (10 clock seconds per wall second).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import re
import signal
import time
from collections.abc import AsyncIterator
from datetime import UTC, datetime, timedelta
from pathlib import Path

import pytest

from nightcrew.clock import AcceleratedClock
from nightcrew.errors import MoveError
from nightcrew.events import (
    SafetyAlarmEvent,
    SafetyClearedEvent,
    WatchdogHeartbeatEvent,
    hardware_event_names,
)
from nightcrew.interfaces import IMotion, IRoof, ITelescope, MotionStatus
from nightcrew.modules import Module
from nightcrew.server import accounts_from_configs, create_missing_passwords
from nightcrew.testing import modules_ready, wait_for
from tests.comm.xmpp_servers import DOMAIN
from tests.modules.sim_processes import starting_policy_file
from tests.supervisor.conftest import REPOSITORY, START_TIMEOUT, SupervisedDirectory

pytestmark = pytest.mark.xmpp
log = logging.getLogger(__name__)
OVERLAYS = REPOSITORY / "examples" / "sim-processes"
SPEED = 10.0
CLOCK_START = "2026-11-10T17:50:00"
MODULES = ["roof", "telescope", "mastermind", "watchdog"]
#: Wall seconds without a heartbeat before the supervisor calls a module frozen (`up --frozen-after`).
FROZEN_AFTER = 6
#: Clock seconds without the watchdog's heartbeat before roof and telescope secure themselves.
WATCHDOG_SILENT = 40


def policy_of(supervised: SupervisedDirectory) -> Path:
    """The observatory's access policy: the watchdog alone trusted with the safety events."""
    path = supervised.directory / "access.policy"
    events = "".join(f"  {name}: [safety]\n" for name in hardware_event_names())
    path.write_text(
        "roles: {operator: ['*'], modules: ['*'], safety: []}\n"
        "accounts: {operator: [operator], roof: [modules], telescope: [modules], mastermind: [modules],"
        " watchdog: [modules, safety]}\nsafety_roles: [safety]\n"
        f"events:\n{events}"
    )
    return path


def write_observatory(
    supervised: SupervisedDirectory, *, park_when_offline: float = 300, dead_mans_switch: bool = False
) -> None:
    comm = (
        f"comm:\n  <<: !include {OVERLAYS}/xmpp.yaml\n  jid: {{name}}@{DOMAIN}\n"
        "  password: !include secrets/{name}.password\n"
        f"  policy: {policy_of(supervised)}\n"
    )
    for name in ("roof", "telescope"):
        extra = f"park_when_offline: {park_when_offline}\n" + comm.format(name=name)
        if dead_mans_switch:  # as docs/operations.md tells a user to add to roof.yaml and telescope.yaml
            extra += f"watchdog: watchdog\npark_when_watchdog_silent: {WATCHDOG_SILENT}\n"
        (supervised.directory / f"{name}.yaml").write_text(f"<<: !include {OVERLAYS / name}.yaml\n{extra}")
    overlay = comm + f"clock: !include {OVERLAYS}/clock.yaml\n"
    (supervised.directory / "mastermind.yaml").write_text(
        "class: nightcrew.modules.Module\n" + overlay.format(name="mastermind")
    )
    (supervised.directory / "watchdog.yaml").write_text(
        "class: nightcrew.modules.safety.SafetyWatchdog\n"
        "watch: {mastermind: 15}\nroof: roof\ntelescope: telescope\ninterval: 2\nanswer_timeout: 3\n"
        + overlay.format(name="watchdog")
    )
    (supervised.directory / "xmpp.yaml").unlink()  # the overlays bring their own
    files = [supervised.directory / f"{name}.yaml" for name in MODULES]
    create_missing_passwords(files)  # what `nightcrew server init` makes, then registers
    for account in accounts_from_configs(files):
        supervised.prosody.account(account.user, account.password)


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
        comm=supervised.operator_comm(policy=str(policy_of(supervised))),
        clock=AcceleratedClock(CLOCK_START, SPEED, wall_start=wall_start),
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


async def test_frozen_mastermind_then_frozen_watchdog_reported_restarted_and_the_roof_closed(
    supervised: SupervisedDirectory, driver: Module
) -> None:
    write_observatory(supervised, dead_mans_switch=True)
    supervised.up("--frozen-after", str(FROZEN_AFTER))
    frozen: list[int] = []
    try:
        await _freeze_mastermind_then_watchdog(supervised, driver, frozen)
    finally:  # after a failure: a stopped process would not even die with the supervisor
        for pid in frozen:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGCONT)


async def _freeze_mastermind_then_watchdog(
    supervised: SupervisedDirectory, driver: Module, frozen: list[int]
) -> None:
    clock = driver.clock
    await wait_for(
        lambda: modules_ready(driver, MODULES), START_TIMEOUT * SPEED, clock=clock, message="modules ready"
    )
    alarms: list[SafetyAlarmEvent] = []
    cleared, beating = asyncio.Event(), asyncio.Event()

    async def on_alarm(event: SafetyAlarmEvent, sender: str) -> None:
        alarms.append(event)

    async def on_cleared(event: SafetyClearedEvent, sender: str) -> None:
        cleared.set()

    async def on_beat(event: WatchdogHeartbeatEvent, sender: str) -> None:
        beating.set()

    await driver.comm.register_event(SafetyAlarmEvent, on_alarm)
    await driver.comm.register_event(SafetyClearedEvent, on_cleared)
    await driver.comm.register_event(WatchdogHeartbeatEvent, on_beat)
    await asyncio.wait_for(beating.wait(), 30)  # the roof opens only while the watchdog beats
    await open_up(driver)
    assert await status_of(driver, "roof") is MotionStatus.IDLE  # open

    # 1. A frozen mastermind: the watchdog closes and parks; the supervisor kills and restarts it.
    mastermind = (await supervised.status())["mastermind"]["pid"]
    stopped_at = clock.time()
    os.kill(mastermind, signal.SIGSTOP)
    frozen.append(mastermind)
    await wait_for(lambda: bool(alarms), 60, clock=clock, message="safety alarm")
    assert alarms[0].reason.startswith("mastermind: no answer for ")
    # the alarm holds: the roof refuses to open while the mastermind is frozen (it is restarted
    # FROZEN_AFTER wall seconds after the SIGSTOP, some 40 clock seconds after the alarm)
    with pytest.raises(MoveError, match=r"safety alarm \(mastermind: no answer for "):
        await (await driver.comm.proxy("roof", IRoof)).open_roof()
    await wait_for(lambda: _both_parked(driver), 60, clock=clock, message="roof closed and telescope parked")
    took = clock.time() - stopped_at
    assert took <= 60
    log.info("roof closed and telescope parked %.1f clock s after the mastermind's SIGSTOP", took)
    status = await supervised.wait_for_status(
        lambda s: s["mastermind"]["restarts"] == 1, "frozen mastermind restarted"
    )
    assert (
        status["mastermind"]["last_exit"] == f"frozen (no heartbeat for {FROZEN_AFTER} s); killed by SIGKILL"
    )
    assert (
        f"mastermind (pid {mastermind}) is frozen: no heartbeat for {FROZEN_AFTER} s"
        in supervised.supervisor_log()
    )
    # heartbeats back from the new process: the alarm clears, the roof may open again
    await asyncio.wait_for(cleared.wait(), START_TIMEOUT)
    await open_up(driver)

    # 2. A frozen watchdog: roof and telescope secure themselves (the dead-man's switch), and the
    # supervisor kills and restarts it.
    watchdog = (await supervised.status())["watchdog"]["pid"]
    os.kill(watchdog, signal.SIGSTOP)
    frozen.append(watchdog)
    # bounded: its silence (40 s), one check (every 5 s), 30 s of closing, and the polls' way
    took = await wait_for(
        lambda: _both_parked(driver), 120, clock=clock, message="closed and parked without the watchdog"
    )
    log.info("roof closed and telescope parked %.1f clock s after the watchdog's SIGSTOP", took)
    for name in ("roof", "telescope"):
        found = re.search(
            rf"no heartbeat from the watchdog 'watchdog' for (\d+) s \(limit {WATCHDOG_SILENT} s\): parking",
            (supervised.log_dir / f"{name}.log").read_text(),
        )
        assert found, f"{name} did not secure itself"
        assert int(found[1]) >= WATCHDOG_SILENT  # the switch never fires early
    status = await supervised.wait_for_status(
        lambda s: s["watchdog"]["restarts"] == 1, "frozen watchdog restarted"
    )
    assert status["watchdog"]["last_exit"] == f"frozen (no heartbeat for {FROZEN_AFTER} s); killed by SIGKILL"
    assert all(status[name]["restarts"] == 0 for name in ("roof", "telescope"))
    assert supervised.terminate() == 0


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
