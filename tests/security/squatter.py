"""An attacker's XMPP client (plain slixmpp, no nightcrew code), run as its own process by the tests.

It joins the room under a module's name, prints ``joined``, waits until the room removes it and
prints ``removed <status codes>`` and ends. Every wait is bounded; it always ends by itself.

Usage: python squatter.py JID PASSWORD HOST PORT ROOM NICK CA_FILE
"""

from __future__ import annotations

import asyncio
import sys
from pathlib import Path
from typing import Any

import slixmpp

_WAIT = 60.0


async def squat(jid: str, password: str, host: str, port: int, room: str, nick: str, ca_file: str) -> None:
    client = slixmpp.ClientXMPP(jid, password)
    client.ca_certs = Path(ca_file)
    client.register_plugin("xep_0045")
    muc: Any = client.plugin["xep_0045"]
    session, removed = asyncio.Event(), asyncio.get_running_loop().create_future()

    def on_presence(presence: Any) -> None:
        ours = presence["from"].bare == room and presence["from"].resource == nick
        ours = ours and presence["type"] == "unavailable"
        if ours and not removed.done():
            codes = presence.xml.findall(".//{http://jabber.org/protocol/muc#user}status")
            removed.set_result(sorted(code.get("code", "") for code in codes))

    client.add_event_handler("session_start", lambda _: session.set())
    client.add_event_handler("groupchat_presence", on_presence)
    client.connect(host, port)
    await asyncio.wait_for(session.wait(), _WAIT)
    await muc.join_muc_wait(slixmpp.JID(room), nick, maxstanzas=0, timeout=_WAIT)
    print("joined", flush=True)
    codes = await asyncio.wait_for(removed, _WAIT)
    print("removed", *codes, flush=True)
    await client.disconnect(wait=2.0)


if __name__ == "__main__":
    jid, password, host, port, room, nick, ca_file = sys.argv[1:8]
    asyncio.run(squat(jid, password, host, int(port), room, nick, ca_file))
