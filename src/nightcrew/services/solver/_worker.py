"""An :class:`IndexSolver` in a child process, so a solve can be given a hard time limit.

astrometry.net's search cannot be interrupted from outside once it runs, and on a field with too
few index stars it searches for minutes. The service therefore solves in a worker process and,
when the limit passes, kills it and carries on with a spare one that has loaded meanwhile.
"""

from __future__ import annotations

import logging
import multiprocessing
import threading
from multiprocessing.connection import Connection
from multiprocessing.process import BaseProcess
from typing import Any

from nightcrew.services.solver._engine import IndexScale, IndexSolver, SolveOutcome
from nightcrew.services.solver._request import SolveRequest

__all__ = ["SolverProcess"]

_LOAD_TIMEOUT_S = 120.0  # a spawned worker imports astropy and maps the indexes: seconds on a busy machine

log = logging.getLogger(__name__)


def _serve(connection: Connection, indexes: list[IndexScale], options: dict[str, Any]) -> None:
    solver = IndexSolver(indexes, **options)
    solver.blocking_open()
    connection.send("ready")
    while True:
        try:
            request = connection.recv()
        except EOFError:
            return
        connection.send(solver.blocking_solve(request))


class _Worker:
    """A started worker process and its end of the pipe; ``ready`` once its indexes are loaded."""

    def __init__(self, process: BaseProcess, connection: Connection) -> None:
        self.process, self.connection, self.ready = process, connection, False

    def wait_ready(self) -> None:
        if not self.ready:
            if not self.connection.poll(_LOAD_TIMEOUT_S) or self.connection.recv() != "ready":
                self.stop()
                raise RuntimeError(
                    f"the solver worker did not load the index files within {_LOAD_TIMEOUT_S:g} s"
                )
            self.ready = True

    def stop(self) -> None:
        self.connection.close()
        self.process.kill()
        self.process.join()


class SolverProcess:
    """Solves in a child process with a time limit per solve (blocking calls: use a worker thread).

    A spare worker is kept loading in the background, so the one after a timeout is ready at once.

    Args:
        indexes: Index files.
        time_limit_s: Longest solve; after it the answer is "no solution" and the worker is replaced.
        **options: Options of :class:`IndexSolver`.
    """

    def __init__(self, indexes: list[IndexScale], *, time_limit_s: float = 10.0, **options: Any) -> None:
        if time_limit_s <= 0:
            raise ValueError(f"time_limit_s must be positive, got {time_limit_s}")
        self.checker = IndexSolver(indexes, **options)  # validates options; checks scales in-process
        self.indexes = indexes
        self.time_limit_s = time_limit_s
        self._options = options
        self._context = multiprocessing.get_context("spawn")  # no fork of a threaded server
        self._worker: _Worker | None = None
        self._spare: _Worker | None = None
        self._lock = threading.Lock()

    def _launch(self) -> _Worker:
        parent, child = self._context.Pipe()
        process = self._context.Process(
            target=_serve,
            args=(child, self.indexes, self._options),
            name="nightcrew-solver-worker",
            daemon=True,
        )
        process.start()
        child.close()
        return _Worker(process, parent)

    def blocking_open(self) -> None:
        """Start the worker and a spare; return once the worker has loaded the indexes."""
        with self._lock:
            if self._worker is None:
                self._worker, self._spare = self._launch(), self._launch()
            self._worker.wait_ready()

    def close(self) -> None:
        """Stop the workers; safe to call twice."""
        with self._lock:
            for worker in (self._worker, self._spare):
                if worker is not None:
                    worker.stop()
            self._worker = self._spare = None

    def blocking_solve(self, request: SolveRequest) -> SolveOutcome:
        """Solve ``request`` within the time limit (one solve at a time)."""
        self.checker.check_scale(request)
        with self._lock:
            if self._worker is None:
                raise RuntimeError("the solver is closed")
            worker = self._worker
            worker.wait_ready()
            worker.connection.send(request)
            if worker.connection.poll(self.time_limit_s):
                outcome: SolveOutcome = worker.connection.recv()
                return outcome
            log.info("no solution within %g s; switching to the spare worker", self.time_limit_s)
            worker.stop()
            self._worker, self._spare = self._spare or self._launch(), self._launch()
        return SolveOutcome(None, f"no solution within the time limit of {self.time_limit_s:g} s")
