"""XmppChat on Prosody, with a real second client (slixmpp) as the person with a chat app."""

from __future__ import annotations

from collections.abc import Callable
from datetime import UTC, datetime, timedelta

import pytest

from nightcrew.errors import ConfigError
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.notify import XmppChat
from nightcrew.modules.sim import SimRoof
from nightcrew.security import read_audit
from tests.comm.xmpp_servers import DOMAIN, XmppServer

from .conftest import OBSERVER, OPERATOR, SECRETS, SecuredObservatory, users
from .xmpp_person import Person

pytestmark = pytest.mark.xmpp

CHAT = f"xmppchat@{DOMAIN}"


def chat_options(server: XmppServer) -> dict[str, object]:
    """How XmppChat reaches the server, and its people (the operator's and observer's own accounts)."""
    account = server.account("xmppchat")
    return {
        "jid": account.jid,
        "password": account.password,
        "server": server.address,
        "ca_file": server.ca_file,
        "users": users({OPERATOR: f"{OPERATOR}@{DOMAIN}", OBSERVER: f"{OBSERVER}@{DOMAIN}"}),
    }


async def test_people_log_in_and_call_with_their_own_rights(
    prosody: XmppServer, people: Callable[[str], Person], observatory: SecuredObservatory
) -> None:
    roof = await observatory.start(SimRoof, "roof", open_time=1.0, close_time=1.0)
    chat = await observatory.start(XmppChat, "xmppchat", **chat_options(prosody))
    assert chat.jid == CHAT
    olga, oscar, stranger = people(OPERATOR), people(OBSERVER), people("stranger")
    for person in (olga, oscar, stranger):
        await person.connect()
    assert "Not logged in" in await olga.say(CHAT, "/exec roof.open_roof()", "Not logged in")
    assert await olga.say(CHAT, "/login nope", "Wrong") == "Wrong secret."
    assert "Logged in as olga" in await olga.say(CHAT, f"/login {SECRETS[OPERATOR]}", "Logged in")
    assert "roof: " in await olga.say(CHAT, "/modules", "roof:")
    assert await olga.say(CHAT, "/exec roof.open_roof()", "open_roof") == "roof.open_roof(): done"
    assert roof._motion_status is MotionStatus.IDLE
    assert "Logged in as oscar" in await oscar.say(CHAT, f"/login {SECRETS[OBSERVER]}", "Logged in")
    refused = await oscar.say(CHAT, "/exec roof.close_roof()", "Forbidden")
    assert refused == "ForbiddenError: oscar may not call roof.close_roof()"
    assert "not a call" in await oscar.say(CHAT, "/exec roof.close_roof(", "not a call")
    assert f"your id is stranger@{DOMAIN}" in await stranger.say(CHAT, "/help", "your id")
    assert await stranger.say(CHAT, f"/login {SECRETS[OPERATOR]}", "Wrong") == "Wrong secret."
    assert roof._motion_status is MotionStatus.IDLE
    # A message a server kept for an hour (XEP-0203 delay) is not acted on.
    an_hour_ago = (datetime.now(UTC) - timedelta(hours=1)).isoformat()
    stale = await olga.say(CHAT, "/exec roof.close_roof()", "Not done", delayed_since=an_hour_ago)
    assert "Send it again" in stale and roof._motion_status is MotionStatus.IDLE
    outcomes = [(r.caller, r.method, r.outcome) for r in read_audit(observatory.audit, module="roof")]
    assert ("olga", "open_roof", "ok") in outcomes and ("oscar", "close_roof", "forbidden") in outcomes
    assert ("xmppchat", "open_roof", "ok") in outcomes  # the roof's own record of the caller it saw


def test_bad_options() -> None:
    with pytest.raises(ConfigError, match=r"users\.olga.*not a JID"):
        XmppChat(name="c", jid=CHAT, password="pw", users={"olga": {"account": "olga", "secret_hash": "x"}})
    with pytest.raises(ConfigError, match=r"password"):
        XmppChat(name="c", jid=CHAT, password="", users={})
    with pytest.raises(ConfigError, match=r"TLS cannot be turned off"):
        XmppChat(name="c", jid=CHAT, password="pw", users={}, server="example.org", require_tls=False)
