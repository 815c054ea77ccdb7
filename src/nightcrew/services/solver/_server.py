"""The plate-solving service on HTTP (aiohttp): ``POST /solve`` (the JSON API of
:mod:`nightcrew.images.astrometry._remote`) and ``GET /health``.

Answers: 200 with ``{"solved": true, "wcs": {...}, "log_odds": ..., "seconds": ...}`` or
``{"solved": false, "message": ...}``; 400 for a request that is not JSON or not a valid request
(the message names the field), 413 for a body over the size limit, 503 when the service is busy
past its queue limit. Errors are ``{"error": "..."}``. Solves run one at a time per worker thread,
so a burst of requests queues instead of thrashing the CPU.
"""

from __future__ import annotations

import asyncio
import json
import logging
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any

from aiohttp import web

from nightcrew.images.astrometry import API_VERSION
from nightcrew.services.solver._request import SolveRequestError, parse_request
from nightcrew.services.solver._worker import SolverProcess

__all__ = ["MAX_BODY_BYTES", "SolverService"]

log = logging.getLogger(__name__)

MAX_BODY_BYTES = 1_000_000
"""Largest request body: 5000 stars as JSON take ~300 kB."""


class SolverService:
    """Serves a :class:`SolverProcess` on ``host``:``port`` (0: any free port, see :attr:`port`).

    Args:
        solver: The solver (its index files are loaded in :meth:`start`).
        host: Address to listen on.
        port: TCP port; 0 picks a free one.
        max_queue: Requests waiting at most; more get HTTP 503.
    """

    def __init__(
        self, solver: SolverProcess, *, host: str = "127.0.0.1", port: int = 0, max_queue: int = 16
    ) -> None:
        if not 0 <= port <= 65535:
            raise ValueError(f"port must be within 0..65535, got {port}")
        if max_queue < 1:
            raise ValueError(f"max_queue must be >= 1, got {max_queue}")
        self.solver = solver
        self.host = host
        self.max_queue = max_queue
        self._requested_port = port
        self._runner: web.AppRunner | None = None
        self._executor: ThreadPoolExecutor | None = None
        self._waiting = 0
        self.port = 0

    @property
    def url(self) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{host}:{self.port}"

    def application(self) -> web.Application:
        app = web.Application(client_max_size=MAX_BODY_BYTES)
        app.router.add_post("/solve", self.handle_solve)
        app.router.add_get("/health", self.handle_health)
        return app

    async def start(self) -> None:
        """Load the indexes and listen."""
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="solver")
        await asyncio.get_running_loop().run_in_executor(self._executor, self.solver.blocking_open)
        self._runner = web.AppRunner(self.application(), access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, self.host, self._requested_port)
        await site.start()
        server = site._server  # aiohttp keeps the bound socket here; port 0 needs the real one
        assert server is not None
        self.port = int(server.sockets[0].getsockname()[1])  # type: ignore[attr-defined]
        log.info("plate-solving service on %s (%d index files)", self.url, len(self.solver.indexes))

    async def close(self) -> None:
        """Stop listening and unload the indexes; safe to call twice."""
        if self._runner is not None:
            await self._runner.cleanup()
            self._runner = None
        if self._executor is not None:
            self._executor.shutdown(wait=True)
            self._executor = None
        await asyncio.get_running_loop().run_in_executor(None, self.solver.close)

    async def handle_health(self, request: web.Request) -> web.Response:
        return web.json_response(
            {"version": API_VERSION, "indexes": len(self.solver.indexes), "waiting": self._waiting}
        )

    async def handle_solve(self, request: web.Request) -> web.Response:
        try:
            text = await request.text()
        except web.HTTPRequestEntityTooLarge:
            return _error(413, f"request body over {MAX_BODY_BYTES} bytes; send fewer stars")
        try:
            body: Any = json.loads(text)
        except json.JSONDecodeError as exc:
            return _error(400, f"the request is not valid JSON: {exc}")
        try:
            solve_request = parse_request(body)
            self.solver.checker.check_scale(solve_request)
        except SolveRequestError as exc:
            return _error(400, str(exc))
        if self._waiting >= self.max_queue:
            return _error(503, f"busy: {self._waiting} requests waiting; try again later")
        assert self._executor is not None
        self._waiting += 1
        started = time.perf_counter()
        try:
            outcome = await asyncio.get_running_loop().run_in_executor(
                self._executor, self.solver.blocking_solve, solve_request
            )
        finally:
            self._waiting -= 1
        seconds = round(time.perf_counter() - started, 4)
        if outcome.cards is None:
            return web.json_response({"solved": False, "message": outcome.message, "seconds": seconds})
        return web.json_response(
            {"solved": True, "wcs": outcome.cards, "log_odds": outcome.log_odds, "seconds": seconds}
        )


def _error(status: int, message: str) -> web.Response:
    return web.json_response({"error": message}, status=status)
