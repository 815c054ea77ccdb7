"""Access control and audit on every transport (in-process, Prosody, ejabberd).

An observer may set the camera's exposure time but is refused roof.open_roof with ForbiddenError; an
account the policy does not know is refused everything; a safety role may always close the roof;
the audit trail holds every state-changing attempt, refused ones included.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import pytest

from nightcrew.cli.main import main
from nightcrew.comm.base import Comm
from nightcrew.comm.xmpp import XmppComm
from nightcrew.errors import ConfigError, ForbiddenError, NightcrewError
from nightcrew.events import BadWeatherEvent, Event, TestEvent
from nightcrew.interfaces import FitsCard, IFitsHeaderBefore
from nightcrew.modules import Module
from nightcrew.modules.camera.headers import collect_headers
from nightcrew.modules.sim import SimCamera, SimRoof
from nightcrew.security import load_policy, read_audit
from nightcrew.testing.waiting import wait_for

from .conftest import Network
from .sample import Calculator

POLICY = """\
roles:
  observer: ["camera.*", "*.get_*", IModule]
  operator: ["*"]
  safety: []
accounts:
  observer: [observer]
  operator: [operator]
  weather: [safety]
safety_roles: [safety]
"""


async def _start(network: Network, cls: type[Module], name: str, policy: Path, audit: Path) -> Module:
    module = cls(comm=_secured(network, name, policy, audit))
    network._modules.append(module)
    await module.open()
    return module


def _secured(network: Network, name: str, policy: Path, audit: Path) -> Comm:
    if network.server is not None:
        return network.server.comm(name, room=network.room, policy=str(policy), audit=str(audit))
    from nightcrew.comm.local import LocalComm

    return LocalComm(name, network=network._local, policy=str(policy), audit=str(audit))


async def test_observer_sets_exposure_but_may_not_open_the_roof(
    network: Network, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    policy, audit = tmp_path / "policy.yaml", tmp_path / "audit.jsonl"
    policy.write_text(POLICY)
    await _start(network, SimCamera, "camera", policy, audit)
    roof = await _start(network, SimRoof, "roof", policy, audit)
    assert isinstance(roof, SimRoof)
    observer = await network.start(Calculator, "observer")
    stranger = await network.start(Calculator, "stranger")

    await observer.comm.execute("camera", "set_exposure_time", [2.5])
    assert await observer.comm.execute("camera", "get_exposure_time", []) == 2.5
    with pytest.raises(ForbiddenError, match=r"observer may not call roof\.open_roof\(\)") as refused:
        await observer.comm.execute("roof", "open_roof", [])
    assert refused.value.module == "roof"
    for module, method, args in (("camera", "set_exposure_time", [1.0]), ("roof", "get_motion_status", [])):
        with pytest.raises(ForbiddenError, match=f"stranger may not call {module}.{method}"):
            await stranger.comm.execute(module, method, args)
    assert "refused open_roof() to observer" in caplog.text
    assert roof.opened == 0.0  # nothing moved

    records = list(read_audit(audit))
    assert [(r.caller, r.module, r.method, r.arguments, r.outcome) for r in records] == [
        ("observer", "camera", "set_exposure_time", ["2.5"], "ok"),
        ("observer", "roof", "open_roof", [], "forbidden"),
        ("stranger", "camera", "set_exposure_time", ["1.0"], "forbidden"),
    ]


async def test_safety_role_may_always_close(network: Network, tmp_path: Path) -> None:
    policy, audit = tmp_path / "policy.yaml", tmp_path / "audit.jsonl"
    policy.write_text(POLICY.replace("  weather: [safety]\n", "  telescope: [safety]\n"))
    await _start(network, SimRoof, "roof", policy, audit)
    safety = await network.start(Calculator, "telescope")
    await safety.comm.execute("roof", "close_roof", [])
    with pytest.raises(ForbiddenError):
        await safety.comm.execute("roof", "open_roof", [])


def test_audit_cli_filters(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from nightcrew.security import AuditLog

    log = AuditLog(tmp_path / "audit.jsonl")
    log.record("observer", "roof", "open_roof", [], "forbidden")
    AuditLog(tmp_path / "audit.jsonl").record(
        "operator", "roof", "close_roof", ["x" * 1000], "ok"
    )  # a restart
    assert main(["audit", str(tmp_path / "audit.jsonl"), "--outcome", "forbidden"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 1 and lines[0].endswith("observer  roof.open_roof()  forbidden")
    assert main(["audit", str(tmp_path / "audit.jsonl"), "--method", "close_*"]) == 0
    line = capsys.readouterr().out
    assert "operator  roof.close_roof(" in line and "(1002 characters)" in line and len(line) < 400


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("roles: {a: [x]}\naccounts: {bob: [b]}\n", "key 'accounts.bob': unknown role 'b'"),
        ("roles: {a: x}\n", "key 'roles.a': expected a list"),
        ("rolez: {}\n", "key 'rolez': unknown key"),
        ("- 1\n", "a policy is a mapping"),
        ("roles: &a [*a]\n", "recursive alias"),
    ],
)
def test_malformed_policy_one_error(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "policy.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=message.replace("(", r"\(").replace(")", r"\)")) as raised:
        load_policy(path)
    assert str(path) in str(raised.value)
    logging.getLogger(__name__).debug("%s", raised.value)


async def test_forged_weather_verdict_is_refused(
    network: Network, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    policy, audit = tmp_path / "policy.yaml", tmp_path / "audit.jsonl"
    policy.write_text(POLICY + "events: {BadWeatherEvent: [safety], GoodWeatherEvent: [safety]}\n")
    roof = await _start(network, Calculator, "roof", policy, audit)
    heard: list[tuple[str, str]] = []

    async def on_event(event: Event, sender: str) -> None:
        heard.append((type(event).__name__, sender))

    await roof.comm.register_event(BadWeatherEvent, on_event)
    await roof.comm.register_event(TestEvent, on_event)
    forger = await network.start(Calculator, "observer")
    weather = await network.start(Calculator, "weather")
    await wait_for(lambda: {"observer", "weather"} <= set(roof.comm.clients), 10)
    await forger.comm.send_event(BadWeatherEvent(reason="forged"))
    await forger.comm.send_event(TestEvent(message="after the forgery"))  # same sender: arrives after it
    await wait_for(lambda: ("TestEvent", "observer") in heard, 10)
    assert ("BadWeatherEvent", "observer") not in heard
    assert "refused BadWeatherEvent from observer" in caplog.text
    await weather.comm.send_event(BadWeatherEvent(reason="rain"))
    await wait_for(lambda: ("BadWeatherEvent", "weather") in heard, 10)


class _Squatter(XmppComm):
    """An extra account that joins the room under another module's name (as the attacker did)."""

    def __init__(self, *args: Any, squatted: str, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._squatted = squatted

    @property
    def name(self) -> str:
        return self._squatted


@pytest.mark.xmpp
async def test_squatted_name_is_not_trusted(
    prosody_network: Network, caplog: pytest.LogCaptureFixture
) -> None:
    network = prosody_network
    assert network.server is not None
    receiver = await network.start(Calculator, "listener")
    heard: list[str] = []

    async def on_event(event: Event, sender: str) -> None:
        heard.append(sender)

    await receiver.comm.register_event(BadWeatherEvent, on_event)
    account = network.server.account("intruder")
    squatter = _Squatter(
        account.jid, account.password, server=network.server.address, room=network.room,
        ca_file=network.server.ca_file, squatted="weather",
    )  # fmt: skip
    await squatter.open()
    try:
        await wait_for(lambda: "intruder@" in caplog.text, 10)
        assert "took the name of module 'weather'" in caplog.text
        assert "weather" not in receiver.comm.clients
        await squatter.send_event(BadWeatherEvent(reason="forged"))
        await wait_for(lambda: "dropped BadWeatherEvent from 'weather'" in caplog.text, 10)
        assert heard == []
    finally:
        await squatter.close()


class _HeaderProvider(Calculator, IFitsHeaderBefore):
    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {"OBJECT": (f"from {self.name}", "target name")}


async def test_forged_header_reply_is_refused(
    network: Network, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    policy, audit = tmp_path / "policy.yaml", tmp_path / "audit.jsonl"
    policy.write_text(
        POLICY.replace("  safety: []\n", "  safety: []\n  devices: []\n").replace(
            "  weather: [safety]\n", "  weather: [safety]\n  telescope: [devices]\n"
        )
        + "header_providers: [devices]\n"
    )
    camera = await _start(network, Calculator, "camera", policy, audit)
    await network.start(_HeaderProvider, "telescope")
    await network.start(_HeaderProvider, "observer")  # a room member, but no header provider
    await wait_for(lambda: {"telescope", "observer"} <= set(camera.comm.clients), 10)
    cards = await collect_headers(camera.comm, "before", 5.0)
    assert cards == {"OBJECT": ("from telescope", "target name")}
    assert "refused FITS headers from observer" in caplog.text


@pytest.mark.xmpp
async def test_password_never_in_logs_or_errors(
    prosody_network: Network, caplog: pytest.LogCaptureFixture
) -> None:
    server = prosody_network.server
    assert server is not None
    caplog.set_level(logging.DEBUG)
    wrong = "wrong-Pa55word-4711"
    comm = XmppComm(
        server.account("calc").jid,
        wrong,
        server=server.address,
        room=prosody_network.room,
        ca_file=server.ca_file,
    )
    with pytest.raises(NightcrewError) as refused:
        await comm.open()
    await comm.close()
    assert "login refused" in str(refused.value)
    right = server.account("calc").password
    shown = str(refused.value) + repr(refused.value) + caplog.text + repr(comm._settings)
    assert wrong not in shown and right not in shown
