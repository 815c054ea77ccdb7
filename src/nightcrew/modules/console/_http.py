"""The console's HTTP plumbing: one error shape, the one place exceptions become responses, sessions.

Every failed ``/api/`` request answers ``{"error": {"class", "message", "module"}}`` with a status
saying whose fault it was (see docs/console-api.md). :func:`error_middleware` is the only place
where exceptions turn into responses; an unexpected one is logged with its traceback and answered
500, and the console carries on.
"""

from __future__ import annotations

import hmac
import json
import logging
from collections.abc import Awaitable, Callable
from typing import Any
from urllib.parse import urlsplit

from aiohttp import web

from nightcrew.errors import (
    CodecError,
    ForbiddenError,
    InterfaceError,
    InvalidArgumentError,
    NightcrewError,
    RemoteTimeoutError,
)
from nightcrew.modules.console._auth import Role, Session, Sessions, is_read_method

__all__ = [
    "COOKIE",
    "CSRF_HEADER",
    "ApiError",
    "check_origin",
    "error_middleware",
    "json_body",
    "require_call_right",
    "require_session",
    "status_of",
]

log = logging.getLogger(__name__)

COOKIE = "nightcrew_session"
CSRF_HEADER = "X-CSRF-Token"
_SESSION_KEY = web.AppKey("sessions", Sessions)
_UNSAFE_METHODS = frozenset({"POST", "PUT", "PATCH", "DELETE"})

Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]


class ApiError(Exception):
    """A request the console refuses, with its HTTP status and error class."""

    def __init__(
        self,
        status: int,
        error_class: str,
        message: str,
        *,
        headers: dict[str, str] | None = None,
        details: dict[str, Any] | None = None,
    ):
        super().__init__(message)
        self.status = status
        self.error_class = error_class
        self.message = message
        self.headers = headers or {}
        #: More fields of the error body (e.g. ``problems``: every field of a request group at fault).
        self.details = details or {}


def status_of(exc: NightcrewError) -> int:
    """The HTTP status of a nightcrew error: the caller's fault (4xx) or the module's (5xx)."""
    if isinstance(exc, RemoteTimeoutError):
        return 504
    if isinstance(exc, ForbiddenError):  # the callee's access policy refused the session's role
        return 403
    if exc.module is None:  # raised here, before anything was sent
        if isinstance(exc, InvalidArgumentError | CodecError):
            return 400
        if isinstance(exc, InterfaceError):
            return 404
    return 502


def error_body(
    error_class: str, message: str, module: str | None = None, details: dict[str, Any] | None = None
) -> dict[str, Any]:
    return {"error": {"class": error_class, "message": message, "module": module, **(details or {})}}


def _error_response(status: int, body: dict[str, Any], headers: dict[str, str] | None = None) -> web.Response:
    return web.json_response(body, status=status, headers=headers)


@web.middleware
async def error_middleware(request: web.Request, handler: Handler) -> web.StreamResponse:
    try:
        return await handler(request)
    except ApiError as exc:
        body = error_body(exc.error_class, exc.message, details=exc.details)
        return _error_response(exc.status, body, exc.headers)
    except NightcrewError as exc:
        return _error_response(status_of(exc), error_body(type(exc).__name__, exc.message, exc.module))
    except web.HTTPException as exc:
        if not request.path.startswith("/api/") or exc.status < 400:
            raise
        return _error_response(exc.status, error_body("HTTPError", f"{exc.reason}: {request.path}"))
    except Exception:
        log.exception("console: %s %s failed", request.method, request.path)
        return _error_response(500, error_body("InternalError", "the console failed; see its log"))


def set_sessions(app: web.Application, sessions: Sessions) -> None:
    app[_SESSION_KEY] = sessions


def current_session(request: web.Request) -> Session | None:
    return request.app[_SESSION_KEY].get(request.cookies.get(COOKIE))


def check_origin(request: web.Request) -> None:
    """Refuse a request that a page of another site made (its browser names that site in Origin)."""
    origin = request.headers.get("Origin")
    if origin is not None and urlsplit(origin).netloc != request.host:
        raise ApiError(403, "CsrfError", f"cross-site request from {origin} refused")


def require_session(request: web.Request) -> Session:
    """The request's session; for unsafe methods also its CSRF token and origin checked."""
    session = current_session(request)
    if session is None:
        raise ApiError(401, "NotLoggedInError", "not logged in (or the session expired)")
    if request.method in _UNSAFE_METHODS:
        check_origin(request)
        token = request.headers.get(CSRF_HEADER, "")
        if not hmac.compare_digest(token.encode(), session.csrf_token.encode()):
            raise ApiError(403, "CsrfError", f"missing or wrong {CSRF_HEADER} header")
    return session


def require_call_right(session: Session, method: str, policy_decides: bool = False) -> None:
    """Refuse a viewer's state-changing call here, unless an access policy decides at the callee."""
    if policy_decides:
        return
    if session.role is not Role.OPERATOR and not is_read_method(method):
        raise ApiError(
            403, "ForbiddenError", f"a {session.role.value} may only call read methods, not {method}()"
        )


def require_operator(session: Session, what: str) -> None:
    if session.role is not Role.OPERATOR:
        raise ApiError(403, "ForbiddenError", f"a {session.role.value} may not {what}")


async def json_body(request: web.Request) -> dict[str, Any]:
    """The request's JSON object; ApiError 400 when it is not one."""
    if request.content_type != "application/json":
        raise ApiError(400, "InvalidArgumentError", "expected Content-Type: application/json")
    try:
        body = json.loads(await request.text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ApiError(400, "InvalidArgumentError", f"the body is not JSON: {exc}") from None
    if not isinstance(body, dict):
        raise ApiError(400, "InvalidArgumentError", f"expected a JSON object, got {type(body).__name__}")
    return body


def field_of(body: dict[str, Any], key: str, kind: type | tuple[type, ...]) -> Any:
    """``body[key]`` checked to be of ``kind``; ApiError 400 naming the key otherwise."""
    if key not in body:
        raise ApiError(400, "InvalidArgumentError", f"missing field '{key}'")
    value = body[key]
    if not isinstance(value, kind) or (isinstance(value, bool) and bool not in _as_tuple(kind)):
        names = " or ".join(k.__name__ for k in _as_tuple(kind))
        raise ApiError(
            400, "InvalidArgumentError", f"field '{key}' must be {names}, got {type(value).__name__}"
        )
    return value


def _as_tuple(kind: type | tuple[type, ...]) -> tuple[type, ...]:
    return kind if isinstance(kind, tuple) else (kind,)
