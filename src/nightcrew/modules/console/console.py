"""The web console: the observatory in a browser - module pages, shell, events, status, log, the night.

A module like any other: it joins the network, learns of modules as they come and go, and relays
what happens (events, log records, state changes, new frames) to the browsers over a WebSocket;
it calls methods for the logged-in user through proxies. The HTTP and WebSocket API is described
in docs/console-api.md; the pages are static files in ``static/`` of this package.
"""

from __future__ import annotations

import asyncio
import logging
from collections import deque
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from aiohttp import web

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import (
    BadWeatherEvent,
    Event,
    GoodWeatherEvent,
    LogEvent,
    ModuleClosedEvent,
    ModuleOpenedEvent,
    ModuleStateChangedEvent,
    NewImageEvent,
    TaskFailedEvent,
    TaskFinishedEvent,
    TaskStartedEvent,
)
from nightcrew.events.base import event_by_name, event_names
from nightcrew.interfaces import IWeather, ModuleState
from nightcrew.interfaces.quantities import Period
from nightcrew.log import current_module
from nightcrew.modules.console._api import build_app
from nightcrew.modules.console._auth import Account, LoginThrottle, Sessions, accounts_from_config
from nightcrew.modules.console._describe import to_json
from nightcrew.modules.console._directory import ModuleDirectory, ModuleEntry
from nightcrew.modules.console._images import Frame, View, frame_from_hdul, render_png
from nightcrew.modules.console._relay import Relay
from nightcrew.modules.console._robotic import WeatherVerdicts, robotic_view
from nightcrew.modules.console._tasks import EditableTaskArchive, build_task_archive
from nightcrew.modules.module import Module

__all__ = ["STATIC_DIR", "WebConsole"]

log = logging.getLogger(__name__)

STATIC_DIR = Path(__file__).parent / "static"
#: Events shown elsewhere than in the event list (log pane, module list).
_NOT_LISTED = frozenset(
    {LogEvent.event_name(), ModuleOpenedEvent.event_name(), ModuleClosedEvent.event_name()}
)
_HISTORY = 1000


class WebConsole(Module):
    """Serves the browser console.

    Args:
        host: Address to listen on; 127.0.0.1 (this machine only) by default - put a TLS proxy in
            front of it to reach it from elsewhere.
        port: Port; 0 picks a free one (see :attr:`port` after opening).
        accounts: ``{user: {password_hash: ..., role: viewer|operator}}``; make a hash with
            ``nightcrew console --hash-password``.
        title: Shown in the browser's title bar and on the login page.
        show_shell, show_events, show_status: Whether the pages offer the shell, the event list,
            the status page.
        show_modules: True (a page for every module), False (none), or the module names to show.
        widgets: ``{module: {title: ..., file: page.html}}``: a page of the observatory's own shown
            on that module's page.
        session_lifetime: Wall seconds a session lives after its last use.
        cookie_secure: Mark the session cookie Secure (HTTPS only): set it behind a TLS proxy.
        login_attempts, login_window: At most this many failed logins per user name and client
            address (four times as many per client address) within this many wall seconds.
        trusted_proxies: Addresses or networks (``10.0.0.0/8``) of the reverse proxies in front of
            the console: only from them is ``X-Forwarded-For`` believed for the client address.
        status_interval: Wall seconds between two polls of module states and the robotic status.
        weather_interval: Clock seconds between two polls of the weather modules.
        tasks: The task archive for the Tasks page (e.g. ``{class:
            nightcrew.robotic.archives.SqliteTaskArchive, path: tasks.sqlite}``), opened and closed
            by the console; None: no Tasks page.
        **kwargs: Module options (``site`` for the Sun and Moon, ``vfs`` to read the cameras' frames).
    """

    def __init__(
        self,
        *,
        host: str = "127.0.0.1",
        port: int = 37180,
        accounts: dict[str, Any] | None = None,
        title: str = "nightcrew",
        show_shell: bool = True,
        show_events: bool = True,
        show_status: bool = True,
        show_modules: bool | list[str] = True,
        widgets: dict[str, dict[str, str]] | None = None,
        session_lifetime: float = 12 * 3600.0,
        cookie_secure: bool = False,
        login_attempts: int = 5,
        login_window: float = 300.0,
        trusted_proxies: list[str] | None = None,
        status_interval: Period = 2.0,
        weather_interval: Period = 60.0,
        tasks: EditableTaskArchive | dict[str, Any] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not 0 <= port < 65536:
            raise ConfigError(f"must be a port number (0 picks a free one), got {port}", key="port")
        for key, value in (
            ("session_lifetime", session_lifetime),
            ("login_window", login_window),
            ("status_interval", status_interval),
            ("weather_interval", weather_interval),
        ):
            if not value > 0:
                raise ConfigError(f"must be > 0 seconds, got {value}", key=key)
        if not login_attempts >= 1:
            raise ConfigError(f"must be >= 1, got {login_attempts}", key="login_attempts")
        if not isinstance(show_modules, bool | list):
            raise ConfigError("must be true, false or a list of module names", key="show_modules")
        self.accounts: dict[str, Account] = accounts_from_config(accounts or {})
        self.widgets = _checked_widgets(widgets or {})
        self.task_archive = build_task_archive(tasks, self.clock) if tasks is not None else None
        self.page_config: dict[str, Any] = {
            "title": title,
            "show_shell": show_shell,
            "show_events": show_events,
            "show_status": show_status,
            "show_modules": show_modules,
            "show_tasks": self.task_archive is not None,
            "widgets": {
                m: {"title": w["title"], "url": f"/api/widgets/{m}"} for m, w in self.widgets.items()
            },
        }
        self._host, self._port = host, port
        self.sessions = Sessions(session_lifetime)
        self.cookie_secure = cookie_secure
        self.login_throttle = LoginThrottle(login_attempts, login_window, trusted_proxies or [])
        self.relay = Relay()
        self.events: deque[dict[str, Any]] = deque(maxlen=_HISTORY)
        self.log_records: deque[dict[str, Any]] = deque(maxlen=_HISTORY)
        self.frames: dict[str, Frame] = {}
        self.weather_history: dict[str, deque[dict[str, Any]]] = {}
        self.weather_verdicts = WeatherVerdicts()
        self.task_names: dict[str, str] = {}
        self._frame_ids = 0
        self._default_png: dict[str, tuple[int, bytes]] = {}  # module -> (frame id, PNG of View())
        self._next_frame: dict[str, str | None] = {}  # module -> frame to load next, while loading
        self._status_interval, self._weather_interval = float(status_interval), float(weather_interval)
        self._runner: web.AppRunner | None = None
        self.directory = ModuleDirectory(self.comm)
        self.add_background_task(self._status_loop, name="status loop")
        self.add_background_task(self._weather_loop, name="weather loop")

    @property
    def port(self) -> int:
        """The port the server listens on (the real one when configured as 0)."""
        return self._port

    @property
    def url(self) -> str:
        return f"http://{self._host}:{self._port}/"

    # --- life cycle ----------------------------------------------------------------------------

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        if self.task_archive is not None:
            await self.task_archive.open()
        try:
            await self._start_server()
            try:
                await super().open()
            except BaseException:
                await self._stop_server()
                raise
        except BaseException:
            await self._close_task_archive()
            raise
        comm = self.comm
        await comm.register_event(ModuleOpenedEvent, self.on_module_opened)
        await comm.register_event(ModuleClosedEvent, self.on_module_closed)
        for name in event_names():
            event_type = event_by_name(name)
            if event_type is not None:  # all of them: on_event sorts them out
                await comm.register_event(event_type, self.on_event)
        await asyncio.gather(*(self.directory.add(name, at_start=True) for name in comm.clients))

    async def close(self) -> None:
        await self._stop_server()  # first: no request meets a module half closed
        try:
            await super().close()
        finally:
            await self._close_task_archive()

    async def _close_task_archive(self) -> None:
        if self.task_archive is not None:
            await self.task_archive.close()

    async def _start_server(self) -> None:
        runner = web.AppRunner(build_app(self, STATIC_DIR), access_log=None)
        await runner.setup()
        # The server's tasks inherit the context it starts in: in the console's, so that what a
        # request handler logs is the console's (log pane, bus) like its other tasks' records.
        token = current_module.set(self.name)
        try:
            await web.TCPSite(runner, self._host, self._port).start()
        except OSError as exc:
            await runner.cleanup()
            raise ConfigError(f"cannot listen on {self._host}:{self._port}: {exc}", key="port") from exc
        finally:
            current_module.reset(token)
        self._runner = runner
        self._port = runner.addresses[0][1]
        log.info("%s: the console is at %s", self.name, self.url)

    async def _stop_server(self) -> None:
        runner, self._runner = self._runner, None
        if runner is not None:
            await runner.shutdown()  # closes the WebSockets
            await runner.cleanup()

    # --- modules coming and going --------------------------------------------------------------

    async def on_module_opened(self, event: ModuleOpenedEvent, sender: str) -> None:
        entry = await self.directory.add(sender)
        if entry is not None:
            self.relay.send({"type": "module_joined", "module": entry.describe()})

    async def on_module_closed(self, event: ModuleClosedEvent, sender: str) -> None:
        if self.directory.remove(sender):
            self.relay.send({"type": "module_left", "name": sender})

    # --- events and log records ----------------------------------------------------------------

    async def announce(self, event: Event) -> None:
        """Send ``event`` as the console, and list it (the bus does not echo it back)."""
        await self.comm.send_event(event)
        await self.on_event(event, self.name)

    async def on_event(self, event: Event, sender: str) -> None:
        if isinstance(event, LogEvent):
            self._log_record(event, sender)
            return
        if event.event_name() in _NOT_LISTED:
            return
        message = {
            "type": "event",
            "time": self.clock.now().isoformat(),
            "sender": sender,
            "event": event.event_name(),
            "fields": to_json(event.to_dict()),
        }
        self.events.append(message)
        self.relay.send(message)
        if isinstance(event, TaskStartedEvent | TaskFinishedEvent | TaskFailedEvent):
            self.task_names[event.id] = event.name
        elif isinstance(event, GoodWeatherEvent):
            self.weather_verdicts.add(self.clock.now(), True)
        elif isinstance(event, BadWeatherEvent):
            self.weather_verdicts.add(self.clock.now(), False, event.reason)
        elif isinstance(event, NewImageEvent):
            await self._show_frame(sender, event.filename)
        elif isinstance(event, ModuleStateChangedEvent):
            self._state_heard(sender, event)

    def _state_heard(self, sender: str, event: ModuleStateChangedEvent) -> None:
        """A module said its state changed: shown at once (the poll would find it later)."""
        entry = self.directory.get(sender)
        if entry is not None and (entry.state, entry.error) != (str(event.current), event.error):
            entry.state, entry.error = str(event.current), event.error
            self._send_state(entry)

    def _send_state(self, entry: ModuleEntry) -> None:
        self.relay.send(
            {"type": "module_state", "name": entry.name, "state": entry.state, "error": entry.error}
        )

    def _log_record(self, event: LogEvent, sender: str) -> None:
        message = {
            "type": "log",
            "time": event.time.isoformat(),
            "module": sender,
            "level": event.level,
            "logger": event.logger,
            "message": event.message,
        }
        self.log_records.append(message)
        self.relay.send(message)

    def _forward_log(self, record: logging.LogRecord) -> None:
        """The console's own records go to the bus like any module's, and to its own log pane."""
        super()._forward_log(record)
        created = datetime.fromtimestamp(record.created, UTC)
        own = LogEvent(time=created, level=record.levelname, logger=record.name, message=record.getMessage())
        self._log_record(own, self.name)

    # --- frames --------------------------------------------------------------------------------

    async def _show_frame(self, module: str, filename: str) -> None:
        """Load the newest frame of ``module``: one load per camera at a time, frames that arrive
        meanwhile replace each other (a fast camera cannot pile up work, the newest one is shown)."""
        first = module not in self._next_frame
        self._next_frame[module] = filename
        if not first:
            return  # the running load takes it next
        try:
            while (latest := self._next_frame.get(module)) is not None:
                self._next_frame[module] = None
                await self._load_frame(module, latest)
        finally:
            del self._next_frame[module]

    async def _load_frame(self, module: str, filename: str) -> None:
        self._frame_ids += 1
        frame_id = self._frame_ids
        try:
            hdul = await self.vfs.read_fits(filename)
            frame = await asyncio.to_thread(
                frame_from_hdul, hdul, module=module, id=frame_id, filename=filename, time=self.clock.now()
            )
            png = await asyncio.to_thread(render_png, frame, View())
        except Exception as exc:  # a frame it cannot show must not count against the console
            log.warning("%s: cannot show %s from %s: %s", self.name, filename, module, exc)
            return
        self.frames[module] = frame
        self._default_png[module] = (frame_id, png)
        self.relay.send({"type": "image", "module": module, "id": frame_id, "filename": filename})

    async def frame_png(self, module: str, view: View) -> bytes | None:
        """The PNG of ``module``'s last frame as ``view`` asks; None without a frame."""
        frame = self.frames.get(module)
        if frame is None:
            return None
        cached = self._default_png.get(module)
        if view == View() and cached is not None and cached[0] == frame.id:
            return cached[1]
        return await asyncio.to_thread(render_png, frame, view)

    # --- polling -------------------------------------------------------------------------------

    async def _status_loop(self) -> None:
        while True:
            await asyncio.sleep(self._status_interval)  # wall time: a display's refresh
            for entry in await self.directory.refresh_states():
                self._send_state(entry)
            if self.relay.clients:
                self.relay.send({"type": "robotic", **await self.robotic()})

    async def robotic(self) -> dict[str, Any]:
        return await robotic_view(
            self.comm,
            self.directory,
            now=self.clock.now(),
            site=self.site,
            task_names=self.task_names,
            weather=self.weather_verdicts,
        )

    async def _weather_loop(self) -> None:
        while True:
            for entry in self.directory.entries:
                if entry.offers(IWeather):
                    await self._poll_weather(entry.name)
            await self.clock.sleep(self._weather_interval)

    async def _poll_weather(self, module: str) -> None:
        try:
            weather = await self.comm.proxy(module, IWeather)
            report = await weather.get_current_weather()
        except NightcrewError as exc:
            log.debug("%s: no weather from %s: %s", self.name, module, exc)
            return
        history = self.weather_history.setdefault(module, deque(maxlen=2000))
        history.append(
            {"time": report.time.isoformat(), "good": report.good, "sensors": to_json(report.sensors)}
        )
        self.weather_verdicts.add(self.clock.now(), report.good)


def _checked_widgets(widgets: dict[str, Any]) -> dict[str, dict[str, str]]:
    checked = {}
    for module, widget in widgets.items():
        key = f"widgets.{module}"
        if not isinstance(widget, dict) or not isinstance(widget.get("file"), str):
            raise ConfigError("expected {title: ..., file: page.html}", key=key)
        if not Path(widget["file"]).is_file():
            raise ConfigError(f"no such file: {widget['file']}", key=f"{key}.file")
        checked[str(module)] = {"title": str(widget.get("title", module)), "file": widget["file"]}
    return checked
