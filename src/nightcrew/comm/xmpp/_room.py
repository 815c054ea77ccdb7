"""Presence, discovery and events: every module is an occupant of one MUC room (XEP-0045).

Why a room: it works the same on Prosody and ejabberd without roster or pubsub setup, gives
online/offline for free (occupant presence) and broadcasts events to everyone in it. The nickname
is the module name; the room is non-anonymous, so each occupant's real JID (where calls and disco
queries go) is in its presence. Events are groupchat messages; each receiver keeps those it
registered for.
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
import json
import logging
import secrets
import xml.etree.ElementTree as ET
from collections.abc import Callable
from datetime import datetime
from typing import Any

from nightcrew.comm.rpc import shorten
from nightcrew.comm.xmpp._connection import XmppConnection, error_condition, split_jid
from nightcrew.comm.xmpp._rpc import NS_HINTS
from nightcrew.comm.xmpp._stanza_limits import MAX_EVENT_CHARS, load_json_bounded
from nightcrew.errors import CodecError, NightcrewError, RemoteError

__all__ = ["NS_EVENT", "NS_MODULE", "Room"]

log = logging.getLogger(__name__)

NS_MUC = "http://jabber.org/protocol/muc"
NS_MUC_USER = "http://jabber.org/protocol/muc#user"
NS_MUC_ADMIN = "http://jabber.org/protocol/muc#admin"
NS_MUC_REGISTER = "http://jabber.org/protocol/muc#register"
NS_EVENT = "urn:nightcrew:event"
NS_MODULE = "urn:nightcrew:module"
_C = "{jabber:client}"
_JOIN_TIMEOUT = 10.0
#: Wall seconds between attempts to enter under a name someone else holds (the last one repeats).
_NAME_RETRY_DELAYS = (1.0, 2.0, 5.0, 10.0, 30.0)
#: Marks the nickname a module uses for a moment while it takes its own name back; never a module name.
_RECLAIM_MARK = "~"


class _NameTaken(Exception):  # an internal signal: never leaves this module
    """The room refused our nickname: an occupant holds it (or it is reserved)."""


class _NameHeld(Exception):  # an internal signal: join() retries
    """Another account holds this module's name and cannot be removed (now)."""


class Room:
    """Membership of one module in the nightcrew room."""

    def __init__(
        self,
        connection: XmppConnection,
        room_jid: str,
        nick: str,
        *,
        on_online: Callable[[str], None],
        on_offline: Callable[[str], None],
        on_event: Callable[[str, dict[str, Any], str, str | None], None],
        domain: str | None = None,
        members: list[str] | None = None,
    ) -> None:
        self._connection = connection
        # The observatory's other accounts (bare JIDs): made members of the room, never owners.
        self._members = [jid.lower() for jid in members or []]
        # Occupants whose nickname is not their account here are squatters (see _is_squatter).
        self._domain = domain
        self._room_jid = room_jid
        self._nick = nick
        self._on_online = on_online
        self._on_offline = on_offline
        self._on_event = on_event
        self._occupants: dict[str, str] = {}  # nick → real full JID
        self._squatters: dict[str, str] = {}  # nickname → real JID of another account holding it
        self._vacated: asyncio.Future[None] | None = None  # while waiting for a squatter to go
        self._previous: dict[str, str] | None = None  # occupants before a reconnect
        self._joined: asyncio.Future[None] | None = None
        self._rejoin_task: asyncio.Task[None] | None = None
        self._closing = False
        self._joining = False  # our own leaving under a passing name is no removal
        self._state = "starting"
        connection.add_handler("nightcrew room presence", f"{_C}presence", self._on_presence)
        connection.add_handler("nightcrew event", f"{_C}message/{{{NS_EVENT}}}event", self._on_message)

    @property
    def occupants(self) -> list[str]:
        """Names of the other modules in the room."""
        return [nick for nick in self._occupants if nick != self._nick]

    def jid_of(self, nick: str) -> str:
        """The real JID of module ``nick``; RemoteError if it is not online."""
        jid = self._occupants.get(nick) if nick != self._nick else None
        if jid is None:
            raise RemoteError(f"module '{nick}' is not online")
        return jid

    # --- joining -------------------------------------------------------------------------------

    async def join(self) -> None:
        """Enter the room (again after a reconnect) and wait for the occupant list.

        When another account holds this module's name, take it back (see :meth:`_take_back`); when
        that cannot be done, say so and try again (the holder may leave, or be removed by hand):
        a held name is a condition to wait out, not a broken configuration.
        """
        delays = iter(_NAME_RETRY_DELAYS)
        self._joining = True
        try:
            while True:
                try:
                    await self._claim_name()
                    break
                except _NameHeld as exc:
                    delay = next(delays, _NAME_RETRY_DELAYS[-1])
                    log.warning("%s; trying again in %g s", exc, delay)
                    await asyncio.sleep(delay)
        finally:
            self._joining = False
        if self._domain is not None:
            await self._reserve_name()
            await self._admit_members()

    async def _claim_name(self) -> None:
        self._squatters.clear()  # seen on an earlier attempt: whoever holds the name now says so anew
        try:
            await self._enter()
        except _NameTaken as exc:
            if self._domain is None:
                raise _NameHeld(str(exc)) from None
            try:
                await self._take_back()
            except _NameTaken as again:  # even the passing name was refused
                raise _NameHeld(str(again)) from None

    async def _admit_members(self) -> None:
        """Make the observatory's other accounts members of the room (XEP-0045 §9.3), where the
        room does not list them yet: in a members-only room people enter as members, never owners.

        Only an owner or admin may; a refusal (this module is no owner; the account is a server
        admin, hence an owner already) changes nothing and is fine.
        """
        from slixmpp.exceptions import IqError, IqTimeout

        if not self._members:
            return
        listed = await self._affiliated("member")
        missing = [jid for jid in self._members if jid not in listed]

        async def admit(jid: str) -> None:
            try:
                await self._admin_iq(jid, "member", None)
            except (IqError, IqTimeout) as exc:
                log.debug("room %s did not make %s a member: %s", self._room_jid, jid, exc)

        await asyncio.gather(*(admit(jid) for jid in missing))

    async def _affiliated(self, affiliation: str) -> set[str]:
        from slixmpp.exceptions import IqError, IqTimeout

        query = ET.Element(f"{{{NS_MUC_ADMIN}}}query")
        ET.SubElement(query, f"{{{NS_MUC_ADMIN}}}item", affiliation=affiliation)
        iq: Any = self._connection.client.make_iq_get(ito=self._room_jid)
        iq.append(query)
        try:
            answer = await iq.send(timeout=_JOIN_TIMEOUT)
        except (IqError, IqTimeout):
            return set()
        return {str(item.get("jid", "")).lower() for item in answer.xml.iter(f"{{{NS_MUC_ADMIN}}}item")}

    async def _admin_iq(self, jid: str, affiliation: str, reason: str | None) -> None:
        """Set the affiliation of bare JID ``jid`` (XEP-0045 §9); raises slixmpp's IqError/IqTimeout."""
        query = ET.Element(f"{{{NS_MUC_ADMIN}}}query")
        item = ET.SubElement(query, f"{{{NS_MUC_ADMIN}}}item", affiliation=affiliation, jid=jid)
        if reason is not None:
            ET.SubElement(item, f"{{{NS_MUC_ADMIN}}}reason").text = reason
        iq: Any = self._connection.client.make_iq_set(ito=self._room_jid)
        iq.append(query)
        await iq.send(timeout=_JOIN_TIMEOUT)

    async def _reserve_name(self) -> None:
        """Register this module's name with the room (XEP-0045 §7.10), so that no other account may
        enter under it, also while the module is down (the room keeps it if it is persistent).

        Servers and rooms that do not offer registration to this account refuse; that is fine:
        taking the name back (:meth:`_take_back`) still works where the module owns the room.
        """
        from slixmpp.exceptions import IqError, IqTimeout

        query = ET.Element("{jabber:iq:register}query")
        form = ET.SubElement(query, "{jabber:x:data}x", type="submit")
        for var, value in (("FORM_TYPE", NS_MUC_REGISTER), ("muc#register_roomnick", self._nick)):
            ET.SubElement(
                ET.SubElement(form, "{jabber:x:data}field", var=var), "{jabber:x:data}value"
            ).text = value
        iq: Any = self._connection.client.make_iq_set(ito=self._room_jid)
        iq.append(query)
        try:
            await iq.send(timeout=_JOIN_TIMEOUT)
        except IqError as exc:
            log.debug(
                "room %s did not reserve '%s': %s", self._room_jid, self._nick, exc.iq["error"]["condition"]
            )
        except IqTimeout:
            log.debug("room %s did not answer the reservation of '%s'", self._room_jid, self._nick)

    async def _enter(self, *, join: bool = True) -> None:
        self._joined = asyncio.get_running_loop().create_future()
        self._connection.send(self._presence(join=join))
        try:
            await asyncio.wait_for(self._joined, _JOIN_TIMEOUT)
        except TimeoutError:
            raise RemoteError(f"no answer from room {self._room_jid} within {_JOIN_TIMEOUT:g} s") from None
        finally:
            self._joined = None

    async def _take_back(self) -> None:
        """Take this module's name back from a squatter (XEP-0045 §9.1, banning a user).

        The module enters under a passing nickname (``camera~1f2e3d``), finds the real JID of the
        occupant holding its name, bans that account from the room (affiliation ``outcast``: it is
        removed and cannot come back) and changes its nickname to its own name. Banning needs the
        room's owner or admin affiliation: ``nightcrew server init`` makes the observatory's accounts
        owners of every room (component admins). Without it the squatter stays, and this is one
        clear error naming it.
        """
        name = self._nick
        passing = f"{name}{_RECLAIM_MARK}{secrets.token_hex(3)}"
        self._nick = passing
        try:
            await self._enter()
            squatter = self._squatters.get(name)
            if squatter is not None:
                await self._ban(squatter, name)
            self._nick = name
            try:
                await self._enter(join=False)  # a nickname change (XEP-0045 §7.6)
            except _NameTaken:
                raise _NameHeld(
                    f"the name '{name}' is reserved in room {self._room_jid} for another account"
                ) from None
        except BaseException:
            self._nick = passing
            with contextlib.suppress(NightcrewError):  # leave under the passing name
                self._connection.send(self._presence(join=False, kind="unavailable"))
            self._nick = name
            raise

    async def _ban(self, jid: str, name: str) -> None:
        from slixmpp.exceptions import IqError, IqTimeout

        bare = jid.partition("/")[0]
        self._vacated = asyncio.get_running_loop().create_future()
        try:
            await self._admin_iq(bare, "outcast", f"took the name of module '{name}'")
            await asyncio.wait_for(self._vacated, _JOIN_TIMEOUT)
        except IqError as exc:
            condition = exc.iq["error"]["condition"]
            raise _NameHeld(
                f"{bare} holds the name of module '{name}' in room {self._room_jid} and cannot be "
                f"removed ({condition}: this account is not an owner of the room, or {bare} is one)"
            ) from None
        except (IqTimeout, TimeoutError):
            raise RemoteError(
                f"room {self._room_jid} did not remove {bare} within {_JOIN_TIMEOUT:g} s"
            ) from None
        finally:
            self._vacated = None
        log.warning(
            "took back the name '%s' in room %s from %s: banned from the room", name, self._room_jid, bare
        )

    def _removed(self, user: ET.Element | None, codes: set[str | None]) -> None:
        """The room put us out (destroyed, kicked, banned): tell who is gone, then enter again."""
        destroyed = user is not None and user.find(f"{{{NS_MUC_USER}}}destroy") is not None
        why = (
            "was destroyed"
            if destroyed
            else f"removed this module (status {' '.join(sorted(c for c in codes if c))})"
        )
        log.warning("room %s %s; entering it again (which recreates it)", self._room_jid, why)
        self._previous = {}  # after entering again, everyone found is reported online
        for nick in list(self._occupants):
            if self._occupants.pop(nick, None) is not None and nick != self._nick:
                self._on_offline(nick)
        self._rejoin_task = asyncio.get_running_loop().create_task(self._rejoin_loop())

    async def _rejoin_loop(self) -> None:
        delays = iter(_NAME_RETRY_DELAYS)
        try:
            while True:
                try:
                    await self.join()
                    log.warning("entered room %s again", self._room_jid)
                    return
                except NightcrewError as exc:
                    delay = next(delays, _NAME_RETRY_DELAYS[-1])
                    log.warning(
                        "cannot enter room %s again (%s); trying again in %g s", self._room_jid, exc, delay
                    )
                    await asyncio.sleep(delay)
        finally:
            self._rejoin_task = None

    async def close(self) -> None:
        """Stop entering again (the connection closes separately)."""
        self._closing = True
        task, self._rejoin_task = self._rejoin_task, None
        if task is not None:
            task.cancel()
            await asyncio.gather(task, return_exceptions=True)

    def lost(self) -> None:
        """The connection is gone; remember who was there to tell differences after rejoining."""
        if self._previous is None:
            self._previous = dict(self._occupants)
        self._occupants.clear()

    def advertise_state(self, state: str) -> None:
        """Tell the room this module's state (in its presence)."""
        self._state = state
        with contextlib.suppress(NightcrewError):  # if offline, the next join carries it
            self._connection.send(self._presence(join=False))

    def _presence(self, *, join: bool = True, kind: str | None = None) -> ET.Element:
        module = ET.Element(f"{{{NS_MODULE}}}module", state=self._state)
        status = ET.Element(f"{_C}status")
        status.text = self._state
        payload = [status, module]
        if join:
            muc = ET.Element(f"{{{NS_MUC}}}x")
            ET.SubElement(muc, f"{{{NS_MUC}}}history", maxstanzas="0")  # no old events
            payload.insert(0, muc)
        attrs = {"type": kind} if kind else {}
        return self._connection.stanza("presence", f"{self._room_jid}/{self._nick}", *payload, **attrs)

    # --- incoming ------------------------------------------------------------------------------

    def _on_presence(self, stanza: ET.Element) -> bool:
        bare, nick = split_jid(stanza.get("from", ""))
        if bare != self._room_jid or not nick:
            return False  # not from the room, or from the room itself
        self._on_room_presence(stanza, nick)
        return True

    def _on_room_presence(self, stanza: ET.Element, nick: str) -> None:
        kind = stanza.get("type")
        if kind == "error":
            self._on_join_error(stanza)
            return
        user = stanza.find(f"{{{NS_MUC_USER}}}x")
        statuses = user.findall(f"{{{NS_MUC_USER}}}status") if user is not None else []
        codes = {status.get("code") for status in statuses}
        if "110" in codes:  # our own presence: the occupant list is complete
            if kind != "unavailable":
                self._complete_join()
            elif "303" not in codes and not (self._joining or self._closing or self._rejoin_task):
                self._removed(user, codes)  # not a nickname change, not our own leaving
            return
        if kind == "unavailable":
            if self._squatters.pop(nick, None) is not None and self._vacated and not self._vacated.done():
                self._vacated.set_result(None)
            if self._occupants.pop(nick, None) is not None and self._joined is None:
                self._on_offline(nick)
            return
        item = user.find(f"{{{NS_MUC_USER}}}item") if user is not None else None
        jid = item.get("jid") if item is not None else None
        if not jid:
            log.warning("room %s hides real JIDs; module '%s' cannot be called", self._room_jid, nick)
            return
        if self._is_squatter(nick, jid):
            if nick not in self._squatters and _RECLAIM_MARK not in nick:  # not a module taking its name back
                log.warning("%s took the name of module '%s' in room %s: ignored", jid, nick, self._room_jid)
            self._squatters[nick] = jid
            return
        known = nick in self._occupants
        self._occupants[nick] = jid
        if not known and self._joined is None:
            self._on_online(nick)

    def _is_squatter(self, nick: str, jid: str) -> bool:
        """Whether an occupant uses a module name that is not its own account (e.g. an extra account
        joined as ``weather`` while the weather module was down): its events and replies are not that
        module's. Only checked when the observatory's domain is known."""
        if self._domain is None:
            return False
        local, _, domain = jid.partition("/")[0].rpartition("@")
        return local.lower() != nick.lower() or domain.lower() != self._domain

    def _complete_join(self) -> None:
        if self._previous is not None:  # after a reconnect: report who came and went meanwhile
            previous, self._previous = self._previous, None
            for nick in previous:
                if nick not in self._occupants:
                    self._on_offline(nick)
            for nick in self._occupants:
                if nick not in previous and nick != self._nick:
                    self._on_online(nick)
        if self._joined is not None and not self._joined.done():
            self._joined.set_result(None)

    def _on_join_error(self, stanza: ET.Element) -> None:
        condition = error_condition(stanza)
        if condition == "conflict":
            error: Exception = _NameTaken(
                f"another module named '{self._nick}' is already in room {self._room_jid}"
            )
        else:
            error = RemoteError(f"cannot enter room {self._room_jid}: {condition}")
        if self._joined is not None and not self._joined.done():
            self._joined.set_exception(error)
        else:
            log.error("%s", error)

    # --- events --------------------------------------------------------------------------------

    def publish(self, name: str, payload: dict[str, Any], acting: str | None = None) -> None:
        """Send event ``name`` with wire fields ``payload`` to the room (sent in the identity
        ``acting``, the ``acting`` attribute, if given)."""
        element = ET.Element(f"{{{NS_EVENT}}}event", name=name)
        if acting is not None:
            element.set("acting", acting)
        element.text = json.dumps(payload, default=_json_value, separators=(",", ":"))
        if len(element.text) > MAX_EVENT_CHARS:  # every receiver would refuse it
            raise CodecError(f"{name} is larger than {MAX_EVENT_CHARS} characters of JSON")
        stanza = self._connection.stanza(
            "message", self._room_jid, element, ET.Element(f"{{{NS_HINTS}}}no-store"), type="groupchat"
        )
        self._connection.send(stanza)

    def _on_message(self, stanza: ET.Element) -> bool:
        bare, nick = split_jid(stanza.get("from", ""))
        if stanza.get("type") != "groupchat" or bare != self._room_jid:
            return False
        element = stanza.find(f"{{{NS_EVENT}}}event")
        if element is None or nick == self._nick:
            return True  # our own event, echoed by the room
        if nick in self._squatters or nick not in self._occupants:
            log.warning(
                "dropped %s from '%s': sent by an account that is not that module", element.get("name"), nick
            )
            return True
        name = element.get("name", "")
        try:
            payload = load_json_bounded(element.text or "{}")
        except CodecError as exc:
            log.warning("dropped %s from %s: its payload is %s", shorten(name), nick, exc.message)
            return True
        if isinstance(payload, dict) and name:
            self._on_event(name, payload, nick, element.get("acting"))
        return True


def _json_value(value: Any) -> Any:
    """JSON for the wire values JSON lacks: datetimes as ISO 8601, bytes as base64."""
    if isinstance(value, datetime):
        return value.isoformat()
    if isinstance(value, bytes):
        return base64.b64encode(value).decode("ascii")
    raise TypeError(f"{type(value).__name__} is not a wire value")
