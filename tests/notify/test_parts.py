"""The chat modules' pure parts: command parsing, outbox, rate limits, event lines."""

from __future__ import annotations

import pytest

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.events import (
    BadWeatherEvent,
    GoodWeatherEvent,
    ModuleStateChangedEvent,
    SafetyAlarmEvent,
    TaskFailedEvent,
)
from nightcrew.interfaces import ModuleState
from nightcrew.modules.notify._commands import Exec, Help, Login, LogLevel, Logout, Modules, parse_command
from nightcrew.modules.notify._outbox import IncomingLimit, Outbox, RateLimit, TokenBucket
from nightcrew.modules.notify._text import describe_event


@pytest.mark.parametrize(
    ("line", "command"),
    [
        ("/help", Help()),
        ("/start", Help()),
        ("  /login  s3cret with spaces ", Login("s3cret with spaces")),
        ("/logout", Logout()),
        ("/loglevel", LogLevel(None)),
        ("/loglevel warning", LogLevel("WARNING")),
        ("/modules@observatory_bot", Modules()),
        ("/exec roof.close_roof()", Exec("roof", "close_roof", ())),
        ("/EXEC camera.set_exposure_time(2.5)", Exec("camera", "set_exposure_time", (2.5,))),
        (
            "/exec camera.expose('R', [1, 2], {'a': None}, True)",
            Exec("camera", "expose", ("R", [1, 2], {"a": None}, True)),
        ),
    ],
)
def test_commands(line: str, command: object) -> None:
    assert parse_command(line) == command


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("", "commands start with '/'"),
        ("exec roof.close_roof()", "commands start with '/'"),
        ("/login", "usage: /login SECRET"),
        ("/loglevel LOUD", "unknown level 'LOUD'"),
        ("/exec", "usage: /exec"),
        ("/exec roof.close_roof", "expected module.method"),
        ("/exec close_roof()", "expected module.method"),
        ("/exec a.b.c()", "expected module.method"),
        ("/exec roof.f(x=1)", "keyword arguments are not supported"),
        ("/exec roof.f(open('/etc/passwd'))", "arguments must be literals"),
        ("/exec roof.f(1 if True else 2)", "arguments must be literals"),
        ("/exec roof.f(" + "(" * 300 + ")" * 300 + ")", "too many nested parentheses"),
        ("/exec roof.f(" + "9" * 5000 + ")", "cannot read the call|line too long|not a call"),
        ("/exec " + "a" * 2001, "line too long"),
        ("/rm -rf", "unknown command /rm"),
    ],
)
def test_bad_lines(line: str, message: str) -> None:
    with pytest.raises(InvalidArgumentError, match=message) as raised:
        parse_command(line)
    assert len(raised.value.message) < 300  # a hostile line is never echoed whole


def test_the_secret_is_not_in_the_repr() -> None:
    assert "hunter2" not in repr(parse_command("/login hunter2"))


def test_outbox_keeps_events_before_records_and_counts_what_it_drops() -> None:
    outbox = Outbox(capacity=3)
    for index in range(5):
        outbox.put_record("INFO", f"record {index}")
    outbox.put_event("event A")
    assert len(outbox) == 3 and outbox.dropped == 3
    message = outbox.take_message()
    assert message == "[3 dropped (too many to send): 3 INFO]\nevent A\nrecord 3\nrecord 4"
    assert outbox.take_message() is None
    for index in range(5):
        outbox.put_event(f"event {index}")
    assert outbox.take_message() == "[2 dropped (too many to send): 2 event]\nevent 2\nevent 3\nevent 4"


def test_outbox_splits_into_messages_of_bounded_size() -> None:
    outbox = Outbox(capacity=100)
    for index in range(100):
        outbox.put_record("ERROR", f"{index:03d} " + "x" * 96)
    messages = []
    while (message := outbox.take_message(max_chars=1000)) is not None:
        messages.append(message)
    # 101 characters a line with its newline: 9 lines a message, 12 messages, none lost.
    assert [len(m.splitlines()) for m in messages] == [9] * 11 + [1]
    assert max(len(m) for m in messages) <= 1000
    outbox.put_record("ERROR", "y" * 5000)
    long = outbox.take_message()
    assert long is not None and len(long) < 1100 and long.endswith("(5000 characters)")


def test_token_bucket_allows_a_burst_then_the_rate() -> None:
    bucket = TokenBucket(RateLimit(messages=2, per=60.0), now=0.0)
    for _ in range(2):
        assert bucket.wait_time(0.0) == 0.0
        bucket.take(0.0)
    assert bucket.wait_time(0.0) == pytest.approx(30.0)
    assert bucket.wait_time(30.0) == 0.0


def test_incoming_limit_per_sender() -> None:
    limit = IncomingLimit(RateLimit(messages=3, per=60.0), max_senders=2)
    assert [limit.allows("a", 0.0) for _ in range(4)] == [True, True, True, False]
    assert limit.allows("b", 0.0) and limit.allows("c", 0.0)
    assert limit.allows("a", 20.0)  # one refilled


@pytest.mark.parametrize(
    ("options", "key"),
    [
        ({"messages": 0}, "messages"),
        ({"per": 0.0}, "per"),
        ({"per": float("nan")}, "per"),
        ({"queue": 0}, "queue"),
        ({"per": "x"}, "per"),
        ({"messages": True}, "messages"),
    ],
)
def test_bad_rate_limits(options: dict[str, float], key: str) -> None:
    with pytest.raises(ConfigError, match=f"rate_limit.{key}"):
        RateLimit(**options)  # type: ignore[arg-type]


def test_event_lines() -> None:
    assert describe_event(BadWeatherEvent(reason="roof.rain: is true"), "weather") == (
        "BAD WEATHER (weather): roof.rain: is true"
    )
    assert describe_event(SafetyAlarmEvent(reason="no heartbeat"), "watchdog") == (
        "SAFETY ALARM (watchdog): no heartbeat"
    )
    failed = TaskFailedEvent(name="M42", id="7", reason="camera timed out")
    assert describe_event(failed, "mastermind") == "TASK FAILED (mastermind): M42 [7]: camera timed out"
    error = ModuleStateChangedEvent(last=ModuleState.READY, current=ModuleState.ERROR, error="no power")
    assert describe_event(error, "camera") == "MODULE ERROR: camera: no power"
    back = ModuleStateChangedEvent(last=ModuleState.ERROR, current=ModuleState.READY)
    assert describe_event(back, "camera") is None
    assert describe_event(GoodWeatherEvent(), "weather") == "GoodWeatherEvent (weather): eta=None"
