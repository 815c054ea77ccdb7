"""The console's routes (docs/console-api.md): login, modules, calls, events, log, images, the night."""

from __future__ import annotations

import asyncio
import contextlib
import logging
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

from aiohttp import WSCloseCode, web

from nightcrew.errors import InvalidArgumentError
from nightcrew.events.base import event_by_name
from nightcrew.modules.console._auth import Session, check_login, is_read_method
from nightcrew.modules.console._calls import MAX_READS, call_json, call_many, parse_shell_line
from nightcrew.modules.console._describe import describe_event_types, to_json
from nightcrew.modules.console._http import (
    COOKIE,
    ApiError,
    check_origin,
    error_middleware,
    field_of,
    json_body,
    require_call_right,
    require_operator,
    require_session,
    set_sessions,
)
from nightcrew.modules.console._images import View
from nightcrew.modules.console._relay import Client
from nightcrew.modules.console._sky import sky_now
from nightcrew.modules.console._tasks_api import add_task_routes

if TYPE_CHECKING:
    from nightcrew.modules.console.console import WebConsole

__all__ = ["build_app"]

log = logging.getLogger(__name__)

#: Longest shell line taken (a literal nested deep enough crashes the parser).
_MAX_LINE = 10_000
#: WebSocket close code telling the page that its session ended.
SESSION_ENDED = 4401


def build_app(console: WebConsole, static_dir: Path) -> web.Application:
    """The aiohttp application of ``console``."""
    app = web.Application(middlewares=[error_middleware], client_max_size=1024**2)
    set_sessions(app, console.sessions)
    routes = _Routes(console)
    app.router.add_get("/", routes.index)
    app.router.add_static("/static/", static_dir)
    add = app.router.add_route
    for method, path, handler in (
        ("POST", "/api/login", routes.login),
        ("POST", "/api/logout", routes.logout),
        ("GET", "/api/session", routes.session),
        ("GET", "/api/config", routes.config),
        ("GET", "/api/modules", routes.modules),
        ("GET", "/api/modules/{name}", routes.module),
        ("POST", "/api/call", routes.call),
        ("POST", "/api/shell", routes.shell),
        ("POST", "/api/read", routes.read),
        ("GET", "/api/events/types", routes.event_types),
        ("GET", "/api/events/recent", routes.recent_events),
        ("POST", "/api/events", routes.send_event),
        ("GET", "/api/log", routes.log),
        ("GET", "/api/ws", routes.websocket),
        ("GET", "/api/images", routes.images),
        ("GET", "/api/images/{module}/latest.png", routes.image_png),
        ("GET", "/api/images/{module}/latest.json", routes.image_json),
        ("GET", "/api/robotic", routes.robotic),
        ("GET", "/api/sky", routes.sky),
        ("GET", "/api/weather/{module}/history", routes.weather_history),
        ("GET", "/api/widgets/{module}", routes.widget),
    ):
        add(method, path, handler)
    add_task_routes(app, console)
    app.on_shutdown.append(routes.close_sockets)
    return app


class _Routes:
    def __init__(self, console: WebConsole) -> None:
        self.console = console
        self.sockets: dict[Client, web.WebSocketResponse] = {}
        self.static_index = Path(__file__).parent / "static" / "index.html"

    async def index(self, request: web.Request) -> web.StreamResponse:
        return web.FileResponse(self.static_index, headers={"Cache-Control": "no-cache"})

    # --- sessions ------------------------------------------------------------------------------

    async def login(self, request: web.Request) -> web.Response:
        check_origin(request)
        body = await json_body(request)
        user, password = field_of(body, "user", str), field_of(body, "password", str)
        throttle = self.console.login_throttle
        client = throttle.client_address(request.remote, request.headers.getall("X-Forwarded-For", []))
        wait = throttle.retry_after(user, client)
        if wait > 0:
            raise ApiError(
                429,
                "RateLimitedError",
                f"too many failed logins; try again in {wait:.0f} s",
                headers={"Retry-After": str(int(wait) + 1)},
            )
        account = await asyncio.to_thread(check_login, self.console.accounts, user, password)
        if account is None:
            # Not the name tried: people type their password into the wrong field.
            log.warning("%s: failed login from %s", self.console.name, client)
            throttle.failed(user, client)
            raise ApiError(401, "LoginError", "wrong user name or password")
        session = self.console.sessions.create(account)
        who = (self.console.name, account.user, account.role.value, client)
        log.info("%s: %s logged in (%s) from %s", *who)
        response = web.json_response(self._session_body(session))
        response.set_cookie(
            COOKIE,
            session.token,
            httponly=True,
            samesite="Strict",
            path="/",
            secure=self.console.cookie_secure,
        )
        return response

    async def logout(self, request: web.Request) -> web.Response:
        session = require_session(request)
        self.console.sessions.end(session.token)
        log.info("%s: %s logged out", self.console.name, session.user)
        for client, socket in list(self.sockets.items()):
            if client.session_token == session.token:
                await socket.close(code=SESSION_ENDED, message=b"logged out")
        response = web.json_response({"ok": True})
        response.del_cookie(COOKIE, path="/")
        return response

    async def session(self, request: web.Request) -> web.Response:
        return web.json_response(self._session_body(require_session(request)))

    def _session_body(self, session: Any) -> dict[str, Any]:
        expires = datetime.fromtimestamp(session.expires, UTC)
        return {
            "user": session.user,
            "role": session.role.value,
            "csrf_token": session.csrf_token,
            "expires_wall": expires.isoformat(),
        }

    async def config(self, request: web.Request) -> web.Response:
        return web.json_response(self.console.page_config)

    # --- modules and calls ---------------------------------------------------------------------

    async def modules(self, request: web.Request) -> web.Response:
        require_session(request)
        return web.json_response({"modules": self._module_list()})

    def _module_list(self) -> list[dict[str, Any]]:
        return [entry.describe() for entry in self.console.directory.entries]

    async def module(self, request: web.Request) -> web.Response:
        require_session(request)
        entry = self.console.directory.get(request.match_info["name"])
        if entry is None:
            raise ApiError(404, "RemoteError", f"module '{request.match_info['name']}' is not online")
        return web.json_response(entry.describe())

    async def call(self, request: web.Request) -> web.Response:
        session = require_session(request)
        body = await json_body(request)
        module, method = field_of(body, "module", str), field_of(body, "method", str)
        args = body.get("args", [])
        if not isinstance(args, list | dict):
            raise ApiError(400, "InvalidArgumentError", "field 'args' must be a list or an object")
        require_call_right(session, method, self._policy_decides)
        result = await self._call(session, module, method, args)
        return web.json_response({"result": result})

    async def shell(self, request: web.Request) -> web.Response:
        session = require_session(request)
        line = field_of(await json_body(request), "line", str)
        if len(line) > _MAX_LINE:
            raise ApiError(400, "InvalidArgumentError", f"the line is longer than {_MAX_LINE} characters")
        try:
            module, method, args = parse_shell_line(line)
        except (RecursionError, MemoryError):
            raise ApiError(400, "InvalidArgumentError", "the line is nested too deeply") from None
        require_call_right(session, method, self._policy_decides)
        result = await self._call(session, module, method, args)
        return web.json_response(
            {"module": module, "method": method, "args": to_json(args), "result": result}
        )

    @property
    def _policy_decides(self) -> bool:
        """Whether an access policy checks the console's calls at the callee (then the page does not:
        one place decides, and a viewer's state-changing call is refused by the module itself)."""
        return self.console.comm.policy is not None

    async def _call(self, session: Session, module: str, method: str, args: Any) -> Any:
        if not is_read_method(method):  # who changed what, for the record
            log.info("%s: %s calls %s.%s()", self.console.name, session.user, module, method)
        # Made as `console:viewer` / `console:operator`: the callee checks the role's rights.
        with self.console.comm.acting_as(session.role.value):
            return await call_json(self.console.comm, self.console.directory, module, method, args)

    async def read(self, request: web.Request) -> web.Response:
        session = require_session(request)
        calls = field_of(await json_body(request), "calls", list)
        if len(calls) > MAX_READS:
            raise ApiError(
                400, "InvalidArgumentError", f"at most {MAX_READS} calls at once, got {len(calls)}"
            )
        for index, call in enumerate(calls):
            if not isinstance(call, dict) or not isinstance(call.get("module"), str):
                raise ApiError(400, "InvalidArgumentError", f"calls[{index}] needs a module")
            method = call.get("method")
            if not isinstance(method, str) or not isinstance(call.get("args", []), list | dict):
                raise ApiError(400, "InvalidArgumentError", f"calls[{index}] needs a method and args")
            if not is_read_method(method):
                raise ApiError(403, "ForbiddenError", f"/api/read takes read methods only, not {method}()")
        with self.console.comm.acting_as(session.role.value):
            results = await call_many(self.console.comm, self.console.directory, calls)
        return web.json_response({"results": results})

    # --- events and log ------------------------------------------------------------------------

    async def event_types(self, request: web.Request) -> web.Response:
        require_session(request)
        return web.json_response({"types": describe_event_types()})

    async def recent_events(self, request: web.Request) -> web.Response:
        require_session(request)
        types = set(request.query.getall("type", []))
        sender = request.query.get("sender")
        limit = _limit(request)
        found = [
            e
            for e in self.console.events
            if (not types or e["event"] in types) and (sender is None or e["sender"] == sender)
        ]
        return web.json_response({"events": found[-limit:]})

    async def send_event(self, request: web.Request) -> web.Response:
        session = require_session(request)
        require_operator(session, "send events")
        body = await json_body(request)
        name, fields = field_of(body, "type", str), body.get("fields", {})
        if not isinstance(fields, dict):
            raise ApiError(400, "InvalidArgumentError", "field 'fields' must be an object")
        event_type = event_by_name(name)
        if event_type is None:
            raise ApiError(404, "InvalidArgumentError", f"unknown event type '{name}'")
        try:
            event = event_type.from_dict(fields)
        except TypeError as exc:  # a missing field
            raise InvalidArgumentError(f"{name}: {exc}") from None
        await self.console.announce(event)
        return web.json_response({"ok": True})

    async def log(self, request: web.Request) -> web.Response:
        require_session(request)
        minimum = level_number(request.query.get("level", "INFO"))
        modules = set(request.query.getall("module", []))
        found = [
            r
            for r in self.console.log_records
            if level_number(r["level"]) >= minimum and (not modules or r["module"] in modules)
        ]
        return web.json_response({"records": found[-_limit(request) :]})

    # --- the WebSocket -------------------------------------------------------------------------

    async def websocket(self, request: web.Request) -> web.WebSocketResponse:
        session = require_session(request)
        check_origin(request)
        # A short close timeout: a browser that does not answer must not hold up the console's close.
        socket = web.WebSocketResponse(heartbeat=20.0, timeout=2.0)
        await socket.prepare(request)
        client = Client(session.token)
        # Relayed from now on (queued until the pump starts), so nothing falls between hello and the pump.
        self.console.relay.add(client)
        self.sockets[client] = socket
        hello = {
            "type": "hello",
            "user": session.user,
            "role": session.role.value,
            "modules": self._module_list(),
            "time": self.console.clock.now().isoformat(),
        }
        try:
            await socket.send_json(hello)
            pump = asyncio.create_task(client.pump(socket.send_str), name="websocket pump")
            try:
                async for _ in socket:  # the client sends nothing we use; this waits for the close
                    pass
            finally:
                pump.cancel()
                with contextlib.suppress(asyncio.CancelledError, ConnectionError):
                    await pump
        except ConnectionError:
            pass  # the browser went away; nothing to tell it
        finally:
            self.console.relay.remove(client)
            self.sockets.pop(client, None)
        return socket

    async def close_sockets(self, app: web.Application) -> None:
        for socket in list(self.sockets.values()):
            await socket.close(code=WSCloseCode.GOING_AWAY, message=b"console closing")

    # --- images, the night, widgets ------------------------------------------------------------

    async def images(self, request: web.Request) -> web.Response:
        require_session(request)
        frames = sorted(self.console.frames.values(), key=lambda f: f.module)
        return web.json_response({"images": [f.describe() for f in frames]})

    async def image_png(self, request: web.Request) -> web.Response:
        require_session(request)
        module = request.match_info["module"]
        view = View.from_query(request.query)
        png = await self.console.frame_png(module, view)
        frame = self.console.frames.get(module)
        if png is None or frame is None:
            raise ApiError(404, "InvalidArgumentError", f"no frame from '{module}' yet")
        headers = {
            "Cache-Control": "no-cache",
            "X-Image-Id": str(frame.id),
            "X-Image-Width": str(frame.width),
            "X-Image-Height": str(frame.height),
        }
        return web.Response(body=png, content_type="image/png", headers=headers)

    async def image_json(self, request: web.Request) -> web.Response:
        require_session(request)
        module = request.match_info["module"]
        frame = self.console.frames.get(module)
        if frame is None:
            raise ApiError(404, "InvalidArgumentError", f"no frame from '{module}' yet")
        header = [{"key": k, "value": v, "comment": c} for k, v, c in frame.header]
        return web.json_response({**frame.describe(), "header": header})

    async def robotic(self, request: web.Request) -> web.Response:
        require_session(request)
        return web.json_response(await self.console.robotic())

    async def sky(self, request: web.Request) -> web.Response:
        require_session(request)
        site = self.console.site
        if site is None:
            raise ApiError(404, "ConfigError", "the console has no site configured")
        return web.json_response(sky_now(site, self.console.clock.now()))

    async def weather_history(self, request: web.Request) -> web.Response:
        require_session(request)
        module = request.match_info["module"]
        history = self.console.weather_history.get(module)
        if history is None:
            raise ApiError(
                404, "InvalidArgumentError", f"no weather from '{module}' (not an IWeather module?)"
            )
        return web.json_response({"samples": list(history)})

    async def widget(self, request: web.Request) -> web.StreamResponse:
        require_session(request)
        widget = self.console.widgets.get(request.match_info["module"])
        if widget is None:
            raise ApiError(404, "InvalidArgumentError", f"no widget for '{request.match_info['module']}'")
        return web.FileResponse(widget["file"], headers={"Content-Type": "text/html; charset=utf-8"})


def _limit(request: web.Request, default: int = 200) -> int:
    text = request.query.get("limit", str(default))
    try:
        limit = int(text)
    except ValueError:
        raise ApiError(400, "InvalidArgumentError", f"limit must be a whole number, got {text!r}") from None
    if limit < 1:
        raise ApiError(400, "InvalidArgumentError", f"limit must be >= 1, got {limit}")
    return limit


def level_number(name: str) -> int:
    """The number of logging level ``name`` (``INFO`` ...); ApiError 400 for an unknown one."""
    number = logging.getLevelName(name.upper())
    if not isinstance(number, int):
        raise ApiError(
            400, "InvalidArgumentError", f"unknown log level {name!r} (DEBUG, INFO, WARNING, ERROR)"
        )
    return number
