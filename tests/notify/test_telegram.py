"""The Telegram module against a stand-in for the Bot API on loopback (see telegram_standin.py).

Telegram's servers cannot be reached from the tests; the stand-in answers getMe, getUpdates and
sendMessage as the documented Bot API does, and python-telegram-bot's ``base_url`` points at it.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import pytest

from nightcrew.errors import ConfigError
from nightcrew.interfaces import ModuleState, MotionStatus
from nightcrew.modules.notify import Telegram
from nightcrew.modules.sim import SimRoof
from nightcrew.security import read_audit

from .conftest import (
    OBSERVER,
    OBSERVER_ID,
    OPERATOR,
    OPERATOR_ID,
    SECRETS,
    STRANGER_ID,
    TOKEN,
    SecuredObservatory,
    users,
)
from .telegram_standin import BotApiStandIn

PEOPLE = users({OPERATOR: OPERATOR_ID, OBSERVER: OBSERVER_ID})


def roof_status(roof: SimRoof) -> MotionStatus:
    """The roof's motion status now (a function: each look is a new one)."""
    return roof._motion_status


async def start_bot(obs: SecuredObservatory, api: BotApiStandIn, **options: object) -> Telegram:
    options.setdefault("users", PEOPLE)
    return await obs.start(
        Telegram, "telegram", token=TOKEN, base_url=api.base_url, poll_timeout=5, **options
    )


async def say(api: BotApiStandIn, person: int, text: str, expect: str, *, sent: float | None = None) -> str:
    """What the bot answers ``person`` for ``text`` (the first new message containing ``expect``)."""
    before = len(api.sent)
    await api.person_says(person, text, sent=sent)
    reply = await api.wait_for(person, lambda t: expect in t, f"reply to {text!r}", since=before)
    return reply.text


async def test_login_first_then_commands(bot_api: BotApiStandIn, observatory: SecuredObservatory) -> None:
    roof = await observatory.start(SimRoof, "roof", open_time=1.0, close_time=1.0)
    await start_bot(observatory, bot_api)
    # Not logged in: told so, nothing executed.
    reply = await say(bot_api, OPERATOR_ID, "/exec roof.open_roof()", "Not logged in")
    assert "Nothing was done" in reply
    assert roof_status(roof) is MotionStatus.PARKED
    assert await say(bot_api, OPERATOR_ID, "/login wrong-secret", "Wrong secret") == "Wrong secret."
    assert "Logged in as olga" in await say(bot_api, OPERATOR_ID, f"/login {SECRETS[OPERATOR]}", "Logged in")
    # Both /login messages, with their secrets, are deleted from the chat.
    deleted = await bot_api.wait_for_deletions(2)
    assert [chat for chat, _ in deleted] == [OPERATOR_ID, OPERATOR_ID] and deleted[0] != deleted[1]
    modules = await say(bot_api, OPERATOR_ID, "/modules", "roof:")
    assert "IRoof" in modules
    assert "Log level: ERROR" in await say(bot_api, OPERATOR_ID, "/loglevel error", "Log level")
    assert "unknown level 'LOUD'" in await say(bot_api, OPERATOR_ID, "/loglevel LOUD", "unknown level")
    await say(bot_api, OPERATOR_ID, "/exec roof.open_roof()", "roof.open_roof(): done")
    assert roof_status(roof) is MotionStatus.IDLE
    status = await say(bot_api, OPERATOR_ID, "/exec roof.get_motion_status()", "get_motion_status")
    assert status == "roof.get_motion_status(): 'idle'"
    # A stranger learns their id, nothing else.
    assert f"your id is {STRANGER_ID}" in await say(bot_api, STRANGER_ID, "/start", "your id")
    assert await say(bot_api, STRANGER_ID, "/login olga-secret-1", "Wrong") == "Wrong secret."
    assert "Logged out" in await say(bot_api, OPERATOR_ID, "/logout", "Logged out")
    assert "Not logged in" in await say(bot_api, OPERATOR_ID, "/modules", "Not logged in")


@pytest.mark.parametrize(
    ("line", "answer"),
    [
        ("/exec roof.close_roof(", "not a call"),
        ("/exec __import__('os').system('true')", "expected module.method(arguments)"),
        ("/exec roof.move(open=1)", "keyword arguments are not supported"),
        ("/exec roof.set(x)", "arguments must be literals"),
        ("/exec roof.f(" + "[" * 500 + "]" * 500 + ")", "too many nested parentheses"),
        ("/exec", "usage: /exec"),
        ("/frobnicate", "unknown command /frobnicate"),
        ("hello", "commands start with '/'"),
        ("/exec nothere.close_roof()", "no module 'nothere' online"),
        ("/exec roof.fly()", "module 'roof' has no method 'fly'"),
        ("/exec roof.open_roof(1, 2)", "InvalidArgumentError"),
        ("/exec " + "x" * 3000, "line too long"),
    ],
)
async def test_bad_lines_get_one_clear_answer(
    bot_api: BotApiStandIn, observatory: SecuredObservatory, line: str, answer: str
) -> None:
    roof = await observatory.start(SimRoof, "roof", open_time=1.0, close_time=1.0)
    await start_bot(observatory, bot_api)
    await say(bot_api, OPERATOR_ID, f"/login {SECRETS[OPERATOR]}", "Logged in")
    reply = await say(bot_api, OPERATOR_ID, line, answer)
    assert len(reply) < 1200 and "Traceback" not in reply
    assert roof_status(roof) is MotionStatus.PARKED


async def test_observer_is_refused_and_the_refusal_audited(
    bot_api: BotApiStandIn, observatory: SecuredObservatory, caplog: pytest.LogCaptureFixture
) -> None:
    roof = await observatory.start(SimRoof, "roof", open_time=1.0, close_time=1.0)
    await start_bot(observatory, bot_api)
    await say(bot_api, OBSERVER_ID, f"/login {SECRETS[OBSERVER]}", "Logged in as oscar")
    reply = await say(bot_api, OBSERVER_ID, "/exec roof.open_roof()", "ForbiddenError")
    assert reply == "ForbiddenError: oscar may not call roof.open_roof()"
    assert roof_status(roof) is MotionStatus.PARKED
    assert "'parked'" in await say(bot_api, OBSERVER_ID, "/exec roof.get_motion_status()", "get_motion")
    [record] = read_audit(observatory.audit, caller=OBSERVER)
    assert (record.module, record.method, record.outcome) == ("roof", "open_roof", "forbidden")
    assert "refused roof.open_roof() to oscar" in caplog.text


async def test_wrong_secrets_are_rate_limited_and_never_logged(
    bot_api: BotApiStandIn, observatory: SecuredObservatory, caplog: pytest.LogCaptureFixture
) -> None:
    await start_bot(observatory, bot_api)
    for attempt in range(5):
        await say(bot_api, OPERATOR_ID, f"/login guess-{attempt}", "Wrong secret")
    reply = await say(bot_api, OPERATOR_ID, f"/login {SECRETS[OPERATOR]}", "Too many")
    assert reply.startswith("Too many wrong secrets")
    assert "guess-" not in caplog.text and SECRETS[OPERATOR] not in caplog.text
    assert TOKEN not in caplog.text


async def test_a_flood_of_log_records_is_batched_rate_limited_and_summarised(
    bot_api: BotApiStandIn, observatory: SecuredObservatory
) -> None:
    bot = await start_bot(observatory, bot_api, rate_limit={"messages": 2, "per": 60.0, "queue": 50})
    roof = await observatory.start(SimRoof, "roof")
    await say(bot_api, OPERATOR_ID, f"/login {SECRETS[OPERATOR]}", "Logged in")
    flood = logging.getLogger("nightcrew.test.flood")
    with_roof = roof.comm
    # 2000 warnings in the roof's name, at once: the bot's handlers only queue, never wait.
    from nightcrew.log import current_module

    token = current_module.set(with_roof.name)
    try:
        for index in range(2000):
            flood.warning("flood record %d", index)
        flood.info("below the level: not forwarded")
    finally:
        current_module.reset(token)
    message = await bot_api.wait_for(OPERATOR_ID, lambda t: "flood record" in t, "the batch")
    # All came before the first message could go: one message says what was dropped and holds
    # the newest records that the queue kept (50).
    lines = message.text.splitlines()
    assert lines[0] == "[1950 dropped (too many to send): 1950 WARNING]"
    assert lines[1:] == [f"WARNING roof: flood record {i}" for i in range(1950, 2000)]
    flood.warning("one more")  # still in no module's name: not forwarded
    # The module still answers at once (a reply is not rate-limited).
    assert "roof:" in await say(bot_api, OPERATOR_ID, "/modules", "roof:")
    assert bot.state.value == "ready"
    assert not any("below the level" in t or "one more" in t for t in bot_api.texts(OPERATOR_ID))


async def test_a_blocked_chat_does_not_stop_the_others(
    bot_api: BotApiStandIn, observatory: SecuredObservatory
) -> None:
    await start_bot(observatory, bot_api)
    roof = await observatory.start(SimRoof, "roof", open_time=1.0, close_time=1.0)
    await say(bot_api, OPERATOR_ID, f"/login {SECRETS[OPERATOR]}", "Logged in")
    await say(bot_api, OBSERVER_ID, f"/login {SECRETS[OBSERVER]}", "Logged in")
    bot_api.blocked.add(OBSERVER_ID)
    await roof.open_roof()
    await roof.close_roof()
    await bot_api.wait_for(OPERATOR_ID, lambda t: "Roof closed (roof)" in t, "roof closed")


async def test_sessions_survive_a_restart_and_old_lines_are_not_acted_on(
    bot_api: BotApiStandIn, observatory: SecuredObservatory, tmp_path: Path
) -> None:
    saved = tmp_path / "state" / "sessions.json"
    bot = await start_bot(observatory, bot_api, sessions=str(saved))
    await say(bot_api, OPERATOR_ID, f"/login {SECRETS[OPERATOR]}", "Logged in")
    await say(bot_api, OPERATOR_ID, "/loglevel error", "Log level: ERROR")
    await say(bot_api, OBSERVER_ID, f"/login {SECRETS[OBSERVER]}", "Logged in")
    assert saved.stat().st_mode & 0o777 == 0o600
    await bot.close()
    # Restarted, with the observer no longer a user: the operator's session and level are back.
    await start_bot(observatory, bot_api, sessions=str(saved), users=users({OPERATOR: OPERATOR_ID}))
    roof = await observatory.start(SimRoof, "roof", open_time=1.0, close_time=1.0)
    await roof.open_roof()
    await roof.close_roof()
    await bot_api.wait_for(OPERATOR_ID, lambda t: "Roof closed (roof)" in t, "roof closed, without a login")
    assert await say(bot_api, OPERATOR_ID, "/loglevel", "Log level") == "Log level: ERROR"
    assert "Not logged in" in await say(bot_api, OBSERVER_ID, "/modules", "Not logged in")
    # A line that waited at Telegram for 10 minutes is not acted on.
    reply = await say(bot_api, OPERATOR_ID, "/exec roof.open_roof()", "Not done", sent=time.time() - 600)
    assert "Send it again" in reply and roof_status(roof) is MotionStatus.PARKED


async def test_a_refused_token_puts_the_module_in_error_state(
    bot_api: BotApiStandIn, observatory: SecuredObservatory, caplog: pytest.LogCaptureFixture
) -> None:
    bot = await observatory.start(
        Telegram, "telegram", token="999:wrong-token", base_url=bot_api.base_url, users={}
    )
    await observatory.wait_for(lambda: bot.state is ModuleState.ERROR, 300.0, message="no error state")
    assert "refused the bot's token" in await bot.get_error_string()
    assert "wrong-token" not in caplog.text


async def test_groups_are_not_answered_and_a_flood_of_lines_is_cut(
    bot_api: BotApiStandIn, observatory: SecuredObservatory
) -> None:
    await start_bot(observatory, bot_api)
    await bot_api.person_says(OPERATOR_ID, "/help", group=-77)
    for _ in range(40):
        await bot_api.person_says(STRANGER_ID, "/help")
    await say(bot_api, OPERATOR_ID, "/help", "Commands")  # after all of the above
    await bot_api.wait_for(STRANGER_ID, lambda _: len(bot_api.texts(STRANGER_ID)) >= 30, "30 replies")
    assert len(bot_api.texts(STRANGER_ID)) == 30  # INCOMING_LIMIT: the other 10 lines got no reply
    assert bot_api.texts(-77) == []


async def test_telegrams_flood_control_is_obeyed(
    bot_api: BotApiStandIn, observatory: SecuredObservatory
) -> None:
    await start_bot(observatory, bot_api)
    await say(bot_api, OPERATOR_ID, f"/login {SECRETS[OPERATOR]}", "Logged in")
    bot_api.throttle = 1  # the next message is refused with 429, retry_after 1 s
    before = len(bot_api.sent)
    await bot_api.person_says(OPERATOR_ID, "/loglevel")
    await bot_api.wait_for(OPERATOR_ID, lambda t: t == "Log level: WARNING", "the reply", since=before)
    assert bot_api.throttle == 0


def test_bad_options_are_refused_without_showing_secrets() -> None:
    with pytest.raises(ConfigError, match=r"token.*value not shown"):
        Telegram(name="t", token="no-colon-here", users={})
    with pytest.raises(ConfigError, match=r"users\.olga.*not a Telegram user id"):
        Telegram(name="t", token=TOKEN, users={"olga": {"account": "olga", "secret_hash": "x"}})
    with pytest.raises(ConfigError, match=r"users\.1001\.secret_hash.*not a secret hash"):
        Telegram(name="t", token=TOKEN, users={1001: {"account": "olga", "secret_hash": "plain"}})
    with pytest.raises(ConfigError, match=r"events.*unknown event 'RainEvent'"):
        Telegram(name="t", token=TOKEN, users={}, events=["RainEvent"])
    with pytest.raises(ConfigError, match=r"rate_limit\.messages"):
        Telegram(name="t", token=TOKEN, users={}, rate_limit={"messages": 0})
    assert TOKEN not in repr(Telegram(name="t", token=TOKEN, users={}))
