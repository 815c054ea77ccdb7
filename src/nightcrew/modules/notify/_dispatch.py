"""One dispatcher for every chat transport: a person's line in, the reply out.

Who may do what is the observatory's access policy: each chat user is mapped to a policy account,
and ``/exec`` checks that account's rights (:meth:`Policy.allows`) *before* the call goes out
through the chat module's own comm. A refused call is a :class:`~nightcrew.errors.ForbiddenError`
and, like every state-changing attempt, is recorded in the comm's audit trail under the person's
account. The callee then checks the chat module's own account as it checks every caller, so the
chat module's role bounds what any of its people can do.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from nightcrew.comm.base import Comm
from nightcrew.comm.codec import encode
from nightcrew.comm.rpc import shorten
from nightcrew.errors import ForbiddenError, InterfaceError, InvalidArgumentError, NightcrewError, RemoteError
from nightcrew.interfaces.base import interface_methods
from nightcrew.modules.notify._commands import (
    HELP,
    Exec,
    Help,
    Login,
    LogLevel,
    Logout,
    Modules,
    parse_command,
)
from nightcrew.modules.notify._users import ChatUser
from nightcrew.security import LoginLimiter, dummy_password_hash, is_state_changing, verify_password

__all__ = ["CommandDispatcher", "Session", "execute_as"]

log = logging.getLogger(__name__)

#: Calls one person may have running at once (a flood of /exec lines is refused, not queued).
MAX_RUNNING_CALLS = 3
#: Longest result shown in a reply.
MAX_RESULT_CHARS = 1000
NOT_LOGGED_IN = "Not logged in: send /login SECRET first. Nothing was done."


@dataclass
class Session:
    """A logged-in person: where replies and notifications go, and their log level."""

    user: ChatUser
    address: str
    level: str
    running: int = 0


async def execute_as(comm: Comm, account: str, module: str, method: str, args: list[Any]) -> Any:
    """Call ``module.method(*args)`` through ``comm`` for policy account ``account``.

    Raises ForbiddenError when the policy does not give ``account`` the call (recorded in the
    comm's audit trail, as every state-changing attempt is), RemoteError for a module not online,
    InterfaceError for a method it lacks, and the remote call's own errors.
    """
    if module not in comm.clients:
        online = ", ".join(sorted(comm.clients)) or "none"
        raise RemoteError(f"no module '{shorten(module, 60)}' online (online: {online})")
    interfaces = await comm.get_interfaces(module)
    declaring = next((i for i in interfaces if method in interface_methods([i])), None)
    if declaring is None:
        methods = ", ".join(sorted(interface_methods(interfaces)))
        raise InterfaceError(f"module '{module}' has no method '{shorten(method, 60)}' (methods: {methods})")
    outcome = "ok"
    try:
        policy = comm.policy
        if policy is not None and not policy.allows(account, module, method, declaring.__name__):
            outcome = "forbidden"
            log.warning("refused %s.%s() to %s (chat): not allowed by the policy", module, method, account)
            raise ForbiddenError(f"{account} may not call {module}.{method}()", module=module)
        wire = [encode(arg, f"argument {i + 1}") for i, arg in enumerate(args)]
        return await comm.execute(module, method, wire)
    except BaseException as exc:
        if outcome == "ok":
            outcome = "forbidden" if isinstance(exc, ForbiddenError) else type(exc).__name__
        raise
    finally:
        audit = comm.audit
        if audit is not None and is_state_changing(method):
            audit.record(account, module, method, args, outcome)


class CommandDispatcher:
    """Parses and runs the commands of the people of one chat transport (``channel``).

    Args:
        channel: The transport's name, for log lines (``telegram``, ``xmpp``).
        users: The people, by their key on the chat.
        comm: The chat module's comm (calls go out through it).
        default_level: The log level of a new session.
        on_login: Called with each new session (the module starts sending to it).
        on_logout: Called with each ended session.
    """

    def __init__(
        self,
        channel: str,
        users: Mapping[str, ChatUser],
        comm: Callable[[], Comm],
        *,
        default_level: str,
        on_login: Callable[[Session], None],
        on_logout: Callable[[Session], None],
    ) -> None:
        self._channel = channel
        self._users = users
        self._comm = comm
        self._default_level = default_level
        self._on_login = on_login
        self._on_logout = on_logout
        self.sessions: dict[str, Session] = {}
        self._limiter = LoginLimiter(attempts=5, window=300.0)

    async def handle(self, key: str, address: str, text: str) -> str:
        """The reply to ``text`` from the person ``key`` (whose replies go to ``address``)."""
        session = self.sessions.get(key)
        try:
            command = parse_command(text)
        except InvalidArgumentError as exc:
            return exc.message if session is not None else NOT_LOGGED_IN
        if isinstance(command, Help):
            return HELP if key in self._users else f"{HELP}\nYou are not a user here; your id is {key}."
        if isinstance(command, Login):
            return await self._login(key, address, command.secret)
        if session is None:
            return NOT_LOGGED_IN
        if isinstance(command, Logout):
            del self.sessions[key]
            self._on_logout(session)
            return "Logged out."
        if isinstance(command, LogLevel):
            if command.level is not None:
                session.level = command.level
            return f"Log level: {session.level}"
        if isinstance(command, Modules):
            return await self._modules()
        return await self._exec(session, command)

    @property
    def users(self) -> Mapping[str, ChatUser]:
        return self._users

    def restore(self, user: ChatUser, address: str, level: str) -> None:
        """Take up a session saved before a restart."""
        session = Session(user, address, level)
        self.sessions[user.key] = session
        self._on_login(session)

    async def _login(self, key: str, address: str, secret: str) -> str:
        wait = self._limiter.retry_after([key])
        if wait > 0:
            return f"Too many wrong secrets; try again in {wait:.0f} s."
        user = self._users.get(key)
        # scrypt takes ~50 ms on purpose: not on the event loop.
        stored = user.secret_hash if user else dummy_password_hash()
        matches = await asyncio.to_thread(verify_password, secret, stored)
        if user is None or not matches:
            self._limiter.failed([key])
            log.warning("wrong secret in /login on %s from %s", self._channel, shorten(key, 60))
            return "Wrong secret."
        old = self.sessions.get(key)
        if old is not None:
            self._on_logout(old)
        session = Session(user, address, old.level if old else self._default_level)
        self.sessions[key] = session
        self._on_login(session)
        log.info("%s logged in on %s as %s", shorten(key, 60), self._channel, user.account)
        return f"Logged in as {user.account}. Log level: {session.level}. Send /help for the commands."

    async def _modules(self) -> str:
        comm = self._comm()
        lines = []
        for client in sorted(comm.clients):
            try:
                names = await comm.get_interface_names(client)
            except NightcrewError:
                continue  # went offline while asked
            lines.append(f"{client}: {', '.join(names)}")
        return "\n".join(lines) or "No modules online."

    async def _exec(self, session: Session, command: Exec) -> str:
        if session.running >= MAX_RUNNING_CALLS:
            return f"Busy: {session.running} calls of yours are running; nothing was done."
        session.running += 1
        try:
            result = await execute_as(
                self._comm(), session.user.account, command.module, command.method, list(command.args)
            )
        except NightcrewError as exc:
            return f"{type(exc).__name__}: {exc.message}"
        finally:
            session.running -= 1
        shown = "done" if result is None else shorten(repr(result), MAX_RESULT_CHARS)
        return f"{command.module}.{command.method}(): {shown}"
