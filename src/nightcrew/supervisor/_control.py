"""The supervisor's control socket: one JSON line in, one JSON line out, owner-only.

The socket is a Unix socket in a directory only its owner may enter (mode 0700), itself mode
0600; the server also checks the peer's user id (SO_PEERCRED), so no other user can stop modules.
Requests: ``{"command": "status"|"start"|"stop"|"restart"|"logs", "module": NAME|null,
"lines": N}``; replies: ``{"ok": true, ...}`` or ``{"ok": false, "error": "..."}``.
"""

from __future__ import annotations

import asyncio
import json
import os
import socket
import struct
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

from nightcrew.errors import NightcrewError

__all__ = ["ControlServer", "SupervisorError", "default_socket_path", "send_request"]

_MAX_REQUEST = 65536
_REPLY_TIMEOUT = 60.0  # a stop may wait for modules to close


class SupervisorError(NightcrewError):
    """The supervisor cannot be reached or refused a request."""


def default_socket_path() -> Path:
    """``$NIGHTCREW_SUPERVISOR_SOCKET``, else in ``$XDG_RUNTIME_DIR``, else in ``/tmp/nightcrew-UID``."""
    if explicit := os.environ.get("NIGHTCREW_SUPERVISOR_SOCKET"):
        return Path(explicit)
    runtime = os.environ.get("XDG_RUNTIME_DIR")
    base = Path(runtime) / "nightcrew" if runtime else Path(f"/tmp/nightcrew-{os.getuid()}")
    return base / "supervisor.sock"


Handler = Callable[[dict[str, Any]], Awaitable[dict[str, Any]]]


class ControlServer:
    """Serves requests on ``path`` with ``handler`` until :meth:`close`."""

    def __init__(self, path: Path, handler: Handler) -> None:
        self._path = path
        self._handler = handler
        self._server: asyncio.Server | None = None

    async def open(self) -> None:
        # A directory we make is private; one that exists (e.g. /tmp for --socket /tmp/x.sock) is left
        # as it is: the socket's own mode (0600, below) is what keeps others out.
        self._path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        if self._path.parent.stat().st_uid != os.getuid():
            raise SupervisorError(f"{self._path.parent} belongs to another user")
        if self._path.exists():
            if await _answers(self._path):
                raise SupervisorError(f"a supervisor already listens on {self._path}")
            self._path.unlink()  # left by a supervisor that was killed
        old_umask = os.umask(0o177)
        try:
            self._server = await asyncio.start_unix_server(self._serve, path=str(self._path))
        finally:
            os.umask(old_umask)

    async def close(self) -> None:
        if self._server is not None:
            self._server.close()
            await self._server.wait_closed()
            self._server = None
            self._path.unlink(missing_ok=True)

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            sock = writer.get_extra_info("socket")
            creds = sock.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, struct.calcsize("3i"))
            _, uid, _ = struct.unpack("3i", creds)
            if uid != os.getuid():
                reply: dict[str, Any] = {"ok": False, "error": "not the supervisor's user"}
            else:
                reply = await self._reply(await reader.readline())
            writer.write(json.dumps(reply).encode() + b"\n")
            await writer.drain()
        except (ConnectionError, asyncio.IncompleteReadError):
            pass
        finally:
            writer.close()

    async def _reply(self, line: bytes) -> dict[str, Any]:
        try:
            request = json.loads(line[:_MAX_REQUEST])
            if not isinstance(request, dict):
                raise ValueError("not an object")
        except ValueError as exc:
            return {"ok": False, "error": f"bad request: {exc}"}
        try:
            return {"ok": True, **await self._handler(request)}
        except NightcrewError as exc:
            return {"ok": False, "error": str(exc)}


async def send_request(path: Path, request: dict[str, Any]) -> dict[str, Any]:
    """Send ``request`` to the supervisor at ``path``; its reply, or SupervisorError."""
    try:
        reader, writer = await asyncio.open_unix_connection(str(path))
    except (FileNotFoundError, ConnectionRefusedError):
        raise SupervisorError(
            f"no supervisor is running (no answer on {path}; start one with nightcrew up DIR)"
        ) from None
    try:
        writer.write(json.dumps(request).encode() + b"\n")
        await writer.drain()
        line = await asyncio.wait_for(reader.readline(), _REPLY_TIMEOUT)
    finally:
        writer.close()
    reply: dict[str, Any] = (
        json.loads(line) if line else {"ok": False, "error": "supervisor closed the connection"}
    )
    if not reply.get("ok"):
        raise SupervisorError(str(reply.get("error", "request refused")))
    return reply


async def _answers(path: Path) -> bool:
    try:
        _, writer = await asyncio.open_unix_connection(str(path))
    except OSError:
        return False
    writer.close()
    return True
