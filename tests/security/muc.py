"""Room administration requests (XEP-0045) sent as a person, to show what a person may not do."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

NS_OWNER = "http://jabber.org/protocol/muc#owner"
NS_ADMIN = "http://jabber.org/protocol/muc#admin"


async def room_iq(comm: Any, room: str, kind: str, namespace: str, *children: ET.Element) -> Any:
    """Send one owner/admin query to ``room`` on ``comm``'s session; slixmpp's IqError if refused."""
    client = comm._require_connection().client
    iq: Any = client.make_iq_set(ito=room) if kind == "set" else client.make_iq_get(ito=room)
    query = ET.Element(f"{{{namespace}}}query")
    for child in children:
        query.append(child)
    iq.append(query)
    return await iq.send(timeout=10)


def admin_item(affiliation: str, jid: str) -> ET.Element:
    return ET.Element(f"{{{NS_ADMIN}}}item", affiliation=affiliation, jid=jid)


def ruling_attempts(domain: str, person: str) -> dict[str, tuple[str, str, list[ET.Element]]]:
    """What only an owner or admin may do to a room: destroy, configure, grant, ban, promote."""
    return {
        "destroy": ("set", NS_OWNER, [ET.Element(f"{{{NS_OWNER}}}destroy")]),
        "configure": ("get", NS_OWNER, []),
        "grant membership": ("set", NS_ADMIN, [admin_item("member", f"x@{domain}")]),
        "ban": ("set", NS_ADMIN, [admin_item("outcast", f"operator@{domain}")]),
        "make itself owner": ("set", NS_ADMIN, [admin_item("owner", f"{person}@{domain}")]),
    }
