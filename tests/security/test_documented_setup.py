"""The documented set-up under attack (issue 26's "Done when"), as docs/observatory.md sets it up.

An observatory directory in the shape ``nightcrew init --comm xmpp`` writes (module files naming
``comm.yaml`` and their own ``secrets/NAME.password``; the people's ``operator.yaml`` and
``observer.yaml``; the comm naming the policy ``server init`` writes), then, in it, ``nightcrew
server init xmpp --port P *.yaml`` (the passwords, the accounts, the starting policy),
``nightcrew server start xmpp`` and ``nightcrew up .``. An outsider has an account on the server,
registered by its administrator, but is not in the policy. The modules: a simulated roof with the
dead-man's switch, a simulated camera and the safety watchdog, on the real clock. One set-up for
the whole file; the tests run in order (the last one freezes the watchdog).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import signal
import stat
import subprocess
import sys
import tempfile
import time
from collections.abc import AsyncIterator, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from bench.hostile_rpc import _Attacker

from nightcrew.cli.main import main
from nightcrew.comm.xmpp import XmppComm
from nightcrew.comm.xmpp._settings import XmppSettings
from nightcrew.comm.xmpp._xmlrpc import build_call
from nightcrew.config import build_object, load_config
from nightcrew.errors import ForbiddenError, InvalidArgumentError, RemoteError
from nightcrew.events import (
    BadWeatherEvent,
    Event,
    GoodWeatherEvent,
    SafetyAlarmEvent,
    SafetyClearedEvent,
    TestEvent,
    WatchdogHeartbeatEvent,
    hardware_event_names,
)
from nightcrew.interfaces import MotionStatus, interface_methods
from nightcrew.modules import Module
from nightcrew.security import is_state_changing, load_policy, read_audit
from nightcrew.server import Account, register_account, start_server, stop_server
from nightcrew.supervisor import send_request
from nightcrew.testing import modules_ready, wait_for

from ..comm.xmpp_servers import free_port, require_command
from .muc import room_iq, ruling_attempts

pytestmark = pytest.mark.xmpp

REPOSITORY = Path(__file__).resolve().parents[2]
DOMAIN = "observatory.local"
ROOM = f"nightcrew@conference.{DOMAIN}"
MODULES = ("roof", "camera", "watchdog")
PEOPLE = ("operator", "observer")
FROZEN_AFTER = 15  # `nightcrew up --frozen-after`: wall seconds without a beat (after the switch)
WATCHDOG_SILENT = 8  # the roof's dead-man's switch: seconds without the watchdog's heartbeat
WITHIN = 60.0  # wall seconds for processes to start on a loaded machine
FORGED: list[Event] = [
    BadWeatherEvent(reason="forged"),
    GoodWeatherEvent(),
    SafetyAlarmEvent(reason="forged"),
    SafetyClearedEvent(),
    WatchdogHeartbeatEvent(),
]
#: The hardware-moving events a roof acts on: all but RapidResponseEvent, which only a mastermind
#: hears (its forgery is refused there: tests/comm/test_hardware_events.py).
ROOF_HEARS = sorted(set(hardware_event_names()) - {"RapidResponseEvent"})
assert sorted(event.event_name() for event in FORGED) == ROOF_HEARS
_MODULE_FILES = {
    "roof": "class: nightcrew.modules.sim.SimRoof\nopen_time: 1\nclose_time: 1\n"
    f"watchdog: watchdog\npark_when_watchdog_silent: {WATCHDOG_SILENT}\n",
    "camera": "class: nightcrew.modules.sim.SimCamera\n",
    "watchdog": "class: nightcrew.modules.safety.SafetyWatchdog\n"
    "watch: {roof: 60}\nroof: roof\ntelescope: null\ninterval: 1\nanswer_timeout: 3\n",
}


@dataclass
class Observatory:
    directory: Path
    socket: Path
    supervisor: subprocess.Popen[bytes]
    outsider_password: str = "the-outsider's-own"
    stopped: list[int] = field(default_factory=list)

    def comm(self, person: str) -> XmppComm:
        built = build_object(load_config(self.directory / f"{person}.yaml"))
        assert isinstance(built, XmppComm)
        return built

    def log(self, module: str) -> str:
        path = self.directory / "logs" / f"{module}.log"
        return path.read_text(errors="replace") if path.exists() else ""

    async def status(self) -> dict[str, dict[str, Any]]:
        reply = await send_request(self.socket, {"command": "status", "module": None})
        return {m["name"]: m for m in reply["modules"]}

    async def raw(self, account: str) -> _Attacker:
        """A raw session of ``account`` (the outsider, or a person with the password of its file),
        which sends stanzas as written: direct calls need no room."""
        password = self.outsider_password
        if account != "outsider":
            password = load_config(self.directory / f"{account}.yaml")["password"]
        settings = XmppSettings.from_options(
            f"{account}@{DOMAIN}", password, server=self.server, room="nightcrew",
            ca_file=str(self.directory / "xmpp" / "certs" / f"{DOMAIN}.crt"), resource="raw",
        )  # fmt: skip
        attacker = _Attacker(settings)
        await attacker.connection.open()
        return attacker

    @property
    def server(self) -> str:
        return str(load_config(self.directory / "comm.yaml")["server"])


def _write_directory(directory: Path, port: int) -> None:
    """Module and person files in the shape ``nightcrew init --comm xmpp`` writes them (its device
    discovery is not what is tested here), the comm naming the policy ``server init`` writes."""
    (directory / "comm.yaml").write_text(
        "class: nightcrew.comm.xmpp.XmppComm\n"
        f"server: 127.0.0.1:{port}\nroom: nightcrew\nca_file: xmpp/certs/{DOMAIN}.crt\n"
        "policy: xmpp/access.policy\naudit: audit.jsonl\n"
    )
    own = (
        "  <<: !include comm.yaml\n  jid: {name}@"
        + DOMAIN
        + "\n  password: !include secrets/{name}.password\n"
    )
    for name, body in _MODULE_FILES.items():
        (directory / f"{name}.yaml").write_text(body + "comm:\n" + own.format(name=name))
    for person in PEOPLE:
        (directory / f"{person}.yaml").write_text(own.format(name=person).replace("  ", ""))


@pytest.fixture(scope="module")
def observatory(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Observatory]:
    require_command("prosody", "prosody")
    directory = tmp_path_factory.mktemp("observatory")
    port = free_port()
    _write_directory(directory, port)
    files = sorted(str(path) for path in directory.glob("*.yaml"))
    assert main(["server", "init", str(directory / "xmpp"), "--port", str(port), *files]) == 0
    start_server(directory / "xmpp")
    socket = Path(tempfile.mkdtemp(prefix="nc-doc-")) / "control.sock"  # short: a Unix socket path
    supervisor = subprocess.Popen(
        [sys.executable, "-m", "nightcrew", "up", ".", "--socket", str(socket),
         "--frozen-after", str(FROZEN_AFTER)],
        cwd=directory, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT,
        env={**os.environ, "PYTHONPATH": str(REPOSITORY / "src")},
    )  # fmt: skip
    setup = Observatory(directory, socket, supervisor)
    try:
        # The administrator registers an account that is not the observatory's.
        register_account(directory / "xmpp", Account("outsider", DOMAIN, setup.outsider_password))
        yield setup
    finally:
        for pid in setup.stopped:  # a stopped process would not even die with the supervisor
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGCONT)
        supervisor.send_signal(signal.SIGTERM)
        try:
            supervisor.wait(timeout=60)
        except subprocess.TimeoutExpired:
            supervisor.kill()
            supervisor.wait()
        stop_server(directory / "xmpp")


async def _person(observatory: Observatory, name: str) -> Module:
    # People may not create the room: they enter once the modules have (as `nightcrew modules`).
    await wait_for(
        lambda: all(f"{m} is ready" in observatory.log(m) for m in MODULES), WITHIN, message="modules ready"
    )
    module = Module(comm=observatory.comm(name))
    await asyncio.wait_for(module.open(), WITHIN)
    return module


@pytest.fixture
async def operator(observatory: Observatory) -> AsyncIterator[Module]:
    module = await _person(observatory, "operator")
    try:
        await wait_for(lambda: modules_ready(module, MODULES), WITHIN, message="modules ready")
        yield module
    finally:
        await module.close()


@pytest.fixture
async def observer(observatory: Observatory, operator: Module) -> AsyncIterator[Module]:
    module = await _person(observatory, "observer")
    try:
        await wait_for(lambda: set(MODULES) <= set(module.comm.clients), WITHIN, message="observer in")
        yield module
    finally:
        await module.close()


async def _roof(operator: Module) -> MotionStatus:
    return MotionStatus(await operator.comm.execute("roof", "get_motion_status", []))


def test_server_init_made_one_random_password_per_account_and_the_policy(observatory: Observatory) -> None:
    secrets = observatory.directory / "secrets"
    assert stat.S_IMODE(secrets.stat().st_mode) == 0o700
    passwords = {}
    for name in (*MODULES, *PEOPLE):
        path = secrets / f"{name}.password"
        assert stat.S_IMODE(path.stat().st_mode) == 0o600, path
        passwords[name] = path.read_text()
    assert len(set(passwords.values())) == len(passwords)  # no shared password
    policy = load_policy(observatory.directory / "xmpp" / "access.policy")
    assert policy.roles_of("watchdog") == ("modules", "safety") and policy.roles_of("roof") == ("modules",)
    assert (policy.roles_of("operator"), policy.roles_of("observer")) == (("operator",), ("observer",))
    assert policy.roles_of("outsider") == ()


async def test_outsider_and_observer_are_refused_every_state_changing_method(
    observatory: Observatory, operator: Module, observer: Module
) -> None:
    outsider = await observatory.raw("outsider")
    refused = {"outsider": 0, "observer": 0}
    exposure = await operator.comm.execute("camera", "get_exposure_time", [])
    try:
        for module in MODULES:
            methods = interface_methods(await operator.comm.get_interfaces(module))
            changing = sorted(name for name in methods if is_state_changing(name))
            assert changing, module
            for method in changing:
                call = build_call(method, [])
                answer = await outsider.call(f"{module}@{DOMAIN}/nightcrew", call)
                assert answer == "ForbiddenError", f"outsider {module}.{method}: {answer}"
                refused["outsider"] += 1
                with (
                    _saying(f"{module}.{method}"),
                    pytest.raises(ForbiddenError, match=rf"observer may not call {module}\.{method}\(\)"),
                ):
                    await observer.comm.execute(module, method, [])
                refused["observer"] += 1
    finally:
        await outsider.connection.close()
    print(f"refused: {refused}")
    assert refused["outsider"] == refused["observer"] > 10
    # Nothing obeyed: the roof still closed, the camera's setting unchanged; all audited as refused.
    assert await _roof(operator) is MotionStatus.PARKED
    assert await operator.comm.execute("camera", "get_exposure_time", []) == exposure
    for person, count in refused.items():
        records = list(read_audit(observatory.directory / "audit.jsonl", caller=person))
        assert len(records) == count and {r.outcome for r in records} == {"forbidden"}


async def test_forged_hardware_events_are_not_obeyed(
    observatory: Observatory, operator: Module, observer: Module
) -> None:
    await asyncio.wait_for(operator.comm.execute("roof", "open_roof", []), 30)
    assert await _roof(operator) is MotionStatus.IDLE  # open
    # The outsider cannot even enter the room the events go through.
    intruder = Module(comm=XmppComm(
        f"outsider@{DOMAIN}", observatory.outsider_password,
        server=observatory.server, room="nightcrew",
        ca_file=str(observatory.directory / "xmpp" / "certs" / f"{DOMAIN}.crt"),
    ))  # fmt: skip
    with pytest.raises(RemoteError, match=f"cannot enter room {ROOM}"):
        await intruder.open()
    await intruder.close()
    outsider = await observatory.raw("outsider")  # sending to the room all the same
    try:
        for event in FORGED:
            fields = json.dumps(event.to_dict())
            element = f'<event xmlns="urn:nightcrew:event" name="{event.event_name()}">{fields}</event>'
            outsider.connection.send_text("message", ROOM, element, type="groupchat")
    finally:
        await outsider.connection.close()
    # The observer, a member, forges every event that moves hardware; a marker tells when all arrived.
    heard: list[str] = []

    async def on_marker(event: TestEvent, sender: str) -> None:
        heard.append(event.message)

    await operator.comm.register_event(TestEvent, on_marker)
    for event in FORGED:
        await observer.comm.send_event(event)
    await observer.comm.send_event(TestEvent(message="forged all"))
    await wait_for(lambda: "forged all" in heard, 20, message="the marker")
    log_line = "refused {} from observer: the policy does not name it as a sender of this event"
    await wait_for(
        lambda: all(log_line.format(name) in observatory.log("roof") for name in ROOF_HEARS),
        20, message="every forged event refused by the roof",
    )  # fmt: skip
    assert await _roof(operator) is MotionStatus.IDLE  # 0 obeyed: still open
    assert "from outsider" not in observatory.log("roof")  # the room did not even pass them on
    refused = read_audit(observatory.directory / "audit.jsonl", caller="observer", module="roof")
    assert {r.method for r in refused if r.outcome == "forbidden"} >= set(ROOF_HEARS)


async def test_people_cannot_destroy_or_configure_the_room(
    observatory: Observatory, observer: Module
) -> None:
    from slixmpp.exceptions import IqError

    operator = await _person(observatory, "operator")
    try:
        for person, module in (("observer", observer), ("operator", operator)):
            for what, (kind, namespace, children) in ruling_attempts(DOMAIN, person).items():
                with pytest.raises(IqError) as refused:
                    await room_iq(module.comm, ROOM, kind, namespace, *children)
                assert refused.value.iq["error"]["condition"] in ("forbidden", "not-allowed"), (person, what)
        assert set(MODULES) <= set(observer.comm.clients)  # the room is still there, with its modules
    finally:
        await operator.close()


async def test_bounds_and_payloads_are_refused_cleanly(observatory: Observatory, operator: Module) -> None:
    started = time.monotonic()
    for value in (1e308, 2**70):
        with pytest.raises(InvalidArgumentError, match=r"argument 'exposure_time': .* out of range"):
            await operator.comm.execute("camera", "set_exposure_time", [value])
    assert time.monotonic() - started < 10  # refused at once, no exposure started
    # A 1.9 MB call from the outsider and a deep event in the room: refused while they stream in.
    outsider = await observatory.raw("outsider")
    try:
        big = build_call("set_exposure_time", ["A" * 1_900_000])
        assert await outsider.call(f"camera@{DOMAIN}/nightcrew", big) != "result"
    finally:
        await outsider.connection.close()
    member = await observatory.raw("observer")  # a member of the room, under its own name
    try:
        member.connection.send_text(
            "presence", f"{ROOM}/observer", '<x xmlns="http://jabber.org/protocol/muc"/>'
        )
        await wait_for(
            lambda: "observer" in operator.comm.clients, 20, message="the raw observer in the room"
        )
        deep = "[" * 5000 + "]" * 5000
        member.connection.send_text(
            "message",
            ROOM,
            f'<event xmlns="urn:nightcrew:event" name="TestEvent">{deep}</event>',
            type="groupchat",
        )
        refusal = "dropped TestEvent from observer: its payload is nested deeper than"
        await wait_for(lambda: refusal in observatory.log("camera"), 20, message="the deep event refused")
    finally:
        await member.connection.close()
    assert await operator.comm.execute("camera", "get_exposure_time", []) >= 0  # still answering
    for module in MODULES:
        assert "Traceback" not in observatory.log(module), module


async def test_a_frozen_watchdog_is_detected_and_the_roof_closes(
    observatory: Observatory, operator: Module, observer: Module
) -> None:
    if await _roof(operator) is not MotionStatus.IDLE:
        await asyncio.wait_for(operator.comm.execute("roof", "open_roof", []), 30)
    watchdog = (await observatory.status())["watchdog"]["pid"]
    os.kill(watchdog, signal.SIGSTOP)
    observatory.stopped.append(watchdog)
    stopped_at = time.monotonic()

    async def forge_heartbeats() -> None:  # the observer tries to hold the switch; refused
        while True:
            await observer.comm.send_event(WatchdogHeartbeatEvent())
            await asyncio.sleep(1)

    forging = asyncio.create_task(forge_heartbeats())
    try:
        # The roof closes by its dead-man's switch, which no forged beat holds off ...
        await wait_for(lambda: _roof_is(operator, MotionStatus.PARKED), WITHIN, message="the roof closed")
        closed_after = time.monotonic() - stopped_at
        # ... and the supervisor finds the process frozen (then kills and restarts it).
        status = await _wait_for_status(
            observatory,
            lambda s: s["watchdog"]["state"] == "frozen" or "frozen" in s["watchdog"]["last_exit"],
        )
    finally:
        forging.cancel()
        await asyncio.gather(forging, return_exceptions=True)
    print(f"roof closed {closed_after:.1f} s after the watchdog's SIGSTOP")
    assert closed_after >= WATCHDOG_SILENT - 1
    watchdog_status = status["watchdog"]
    assert f"no heartbeat for {FROZEN_AFTER} s" in watchdog_status["error"] + watchdog_status["last_exit"]
    assert "no heartbeat from the watchdog 'watchdog' for" in observatory.log("roof")
    assert "refused WatchdogHeartbeatEvent from observer" in observatory.log("roof")


def _watchdog_found_frozen(status: dict[str, Any]) -> bool:
    """Frozen now, or restarted already (polls may miss the moment between finding and restarting)."""
    return status["watchdog"]["state"] == "frozen" or "frozen" in status["watchdog"]["last_exit"]


async def _roof_is(operator: Module, status: MotionStatus) -> bool:
    return await _roof(operator) is status


async def _wait_for_status(observatory: Observatory, check: Any) -> dict[str, Any]:
    deadline = time.monotonic() + WITHIN
    while True:
        status = await observatory.status()
        if check(status):
            return status
        assert time.monotonic() < deadline, status
        await asyncio.sleep(0.1)


@contextlib.contextmanager
def _saying(what: str) -> Iterator[None]:
    try:
        yield
    except BaseException as exc:
        raise AssertionError(f"{what}: {exc}") from exc
