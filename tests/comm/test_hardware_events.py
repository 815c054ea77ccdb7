"""Events that move hardware (weather verdicts, safety alarms) are trusted only from their senders.

A forged one - from a room member the policy does not name, or from anyone when the policy does not
mention the event, or on XMPP without a policy - is dropped, logged once and audited; the roof it
was meant for does not move and a latched alarm stays latched.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any, TypeVar

import pytest
import yaml

from nightcrew.errors import MoveError
from nightcrew.events import (
    BadWeatherEvent,
    Event,
    GoodWeatherEvent,
    RapidResponseEvent,
    SafetyAlarmEvent,
    SafetyClearedEvent,
    TestEvent,
    WatchdogHeartbeatEvent,
    hardware_event_names,
)
from nightcrew.interfaces import MotionStatus
from nightcrew.modules import Module
from nightcrew.modules.sim import SimRoof
from nightcrew.security import parse_policy, read_audit
from nightcrew.testing.waiting import wait_for

from .conftest import Network
from .sample import Calculator

HARDWARE_EVENTS: list[Event] = [
    BadWeatherEvent(reason="forged"),
    GoodWeatherEvent(),
    SafetyAlarmEvent(reason="forged"),
    SafetyClearedEvent(),
    WatchdogHeartbeatEvent(),
    RapidResponseEvent(ids=("1",)),  # the right to pre-empt a running task (the mastermind's)
]
POLICY = """\
roles: {operator: ["*"], observer: ["*.get_*"], safety: []}
accounts: {operator: [operator], observer: [observer], weather: [safety], watchdog: [safety],
           "observer:duty": [safety]}
safety_roles: [safety]
"""
EVENTS = "events:\n" + "".join(f"  {name}: [safety]\n" for name in hardware_event_names())
M = TypeVar("M", bound=Module)
REPOSITORY = Path(__file__).resolve().parents[2]


def test_the_marked_events_are_the_weather_verdicts_and_safety_alarms() -> None:
    assert sorted(type(event).__name__ for event in HARDWARE_EVENTS) == hardware_event_names()
    documented = (REPOSITORY / "docs" / "security.md").read_text()
    for name in hardware_event_names():
        assert f"`{name}`" in documented


def test_policy_trusts_a_hardware_event_only_from_the_roles_named() -> None:
    named = parse_policy(yaml.safe_load(POLICY + EVENTS))
    silent = parse_policy(yaml.safe_load(POLICY))
    assert named.accepts_event("watchdog", "SafetyClearedEvent", moves_hardware=True)
    assert not named.accepts_event("observer", "SafetyClearedEvent", moves_hardware=True)
    assert not named.accepts_event("stranger", "SafetyClearedEvent", moves_hardware=True)
    # Not named by the policy: from nobody, the safety modules included; other events from anyone.
    assert not silent.accepts_event("watchdog", "SafetyClearedEvent", moves_hardware=True)
    assert silent.accepts_event("observer", "TestEvent")


async def _start_with_policy(
    network: Network, name: str, policy: Path, module_type: type[M], **options: Any
) -> M:
    """A ``module_type`` on Prosody as ``name``; its comm names ``policy`` and an audit trail beside it."""
    assert network.server is not None
    audit = policy.with_name("audit.jsonl")
    module = module_type(
        comm=network.server.comm(name, room=network.room, policy=str(policy), audit=str(audit)), **options
    )
    network._modules.append(module)
    await module.open()
    return module


async def _send(sender: Module, events: list[Event], heard: list[str]) -> None:
    """Send ``events``, then a marker: when it is heard, the events before it were handled."""
    for event in events:
        await sender.comm.send_event(event)
    marker = TestEvent(message=f"{sender.name}: after {len(events)} events, {len(heard)} heard")
    await sender.comm.send_event(marker)
    await wait_for(lambda: marker.message in heard, 10)


@pytest.mark.xmpp
async def test_every_hardware_event_is_refused_from_a_non_sender_over_prosody(
    prosody_network: Network, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    network = prosody_network
    policy, audit = tmp_path / "policy.yaml", tmp_path / "audit.jsonl"
    policy.write_text(POLICY + EVENTS)
    roof = await _start_with_policy(  # naming the watchdog, the roof listens to its heartbeat too
        network,
        "roof",
        policy,
        SimRoof,
        open_time=0.01,
        close_time=0.01,
        watchdog="watchdog",
        park_when_watchdog_silent=3600,
    )
    heard: list[str] = []

    async def on_marker(event: TestEvent, sender: str) -> None:
        heard.append(event.message)

    await roof.comm.register_event(TestEvent, on_marker)
    pre_emptions: list[RapidResponseEvent] = []

    async def on_rapid_response(event: RapidResponseEvent, sender: str) -> None:  # as a mastermind
        pre_emptions.append(event)

    await roof.comm.register_event(RapidResponseEvent, on_rapid_response)
    observer = await network.start(Calculator, "observer")
    watchdog = await network.start(Calculator, "watchdog")
    await wait_for(lambda: {"observer", "watchdog"} <= set(roof.comm.clients), 10)
    await roof.open_roof()

    with caplog.at_level(logging.WARNING):
        await _send(observer, HARDWARE_EVENTS, heard)
    assert await roof.get_motion_status() is MotionStatus.IDLE  # still open: no forged close obeyed
    assert pre_emptions == []
    for name in hardware_event_names():
        refusals = [r for r in caplog.records if r.getMessage().startswith(f"refused {name} from observer")]
        assert len(refusals) == 1 and refusals[0].levelno == logging.WARNING
    forbidden = [(r.caller, r.module, r.method, r.outcome) for r in read_audit(audit, outcome="forbidden")]
    assert forbidden == [("observer", "roof", type(e).__name__, "forbidden") for e in HARDWARE_EVENTS]
    assert audit.stat().st_mode & 0o777 == 0o600  # the trail is its owner's alone

    # Sent for a person (as the console sends for an operator): trusted as that identity.
    with observer.comm.acting_as("duty"):
        await _send(observer, [RapidResponseEvent(ids=("2",))], heard)
    assert [event.ids for event in pre_emptions] == [("2",)]

    # The watchdog's alarm latches; a forged all-clear does not unlatch it, the watchdog's does.
    await watchdog.comm.send_event(SafetyAlarmEvent(reason="weather silent"))
    await wait_for(lambda: roof.opened == 0.0, 10)
    await _send(observer, [SafetyClearedEvent()], heard)
    with pytest.raises(MoveError, match="safety alarm"):
        await roof.open_roof()
    await _send(watchdog, [SafetyClearedEvent()], heard)
    await roof.open_roof()
    assert roof.opened == 1.0


@pytest.mark.xmpp
async def test_without_a_policy_on_xmpp_and_unnamed_in_a_policy_nobody_is_trusted(
    prosody_network: Network, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    network = prosody_network
    policy = tmp_path / "policy.yaml"
    policy.write_text(POLICY)  # names no event: the safety role is not enough
    assert network.server is not None
    bare = Calculator(comm=network.server.comm("listener", room=network.room))  # no policy: closed
    network._modules.append(bare)
    await bare.open()
    guarded = await _start_with_policy(network, "calc", policy, Calculator)
    heard: list[str] = []

    async def on_event(event: Event, sender: str) -> None:
        heard.append(event.message if isinstance(event, TestEvent) else f"{type(event).__name__} {sender}")

    for receiver in (bare, guarded):
        await receiver.comm.register_event(SafetyClearedEvent, on_event)
        await receiver.comm.register_event(TestEvent, on_event)
    watchdog = await network.start(Calculator, "watchdog")
    await wait_for(lambda: {"listener", "calc"} <= set(watchdog.comm.clients), 10)
    await _send(watchdog, [SafetyClearedEvent()], heard)
    await wait_for(lambda: len(heard) == 2, 10)  # the marker, at both
    assert not [line for line in heard if line.startswith("SafetyClearedEvent")]
    assert "refused SafetyClearedEvent from watchdog: without an access policy" in caplog.text
    assert "refused SafetyClearedEvent from watchdog: the policy does not name it" in caplog.text
