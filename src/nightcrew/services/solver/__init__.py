"""The plate-solving service (``nightcrew solver``): astrometry.net with its indexes kept loaded,
behind a small JSON API over HTTP.

:class:`IndexSolver` solves (blocking) against index files found by :func:`find_index_files`;
:class:`SolverProcess` runs it in a child process with a time limit per solve;
:class:`SolverService` serves that (see :mod:`._server` for the answers); :func:`parse_request`
checks a request. The client is :class:`nightcrew.images.astrometry.RemoteSolver`, whose module
documents the API.
"""

from nightcrew.services.solver._engine import (
    DEFAULT_INDEX_DIR,
    IndexScale,
    IndexSolver,
    SolveOutcome,
    find_index_files,
)
from nightcrew.services.solver._request import (
    MIN_STARS,
    SolveRequest,
    SolveRequestError,
    parse_request,
)
from nightcrew.services.solver._server import MAX_BODY_BYTES, SolverService
from nightcrew.services.solver._worker import SolverProcess

__all__ = [
    "DEFAULT_INDEX_DIR",
    "MAX_BODY_BYTES",
    "MIN_STARS",
    "IndexScale",
    "IndexSolver",
    "SolveOutcome",
    "SolveRequest",
    "SolveRequestError",
    "SolverProcess",
    "SolverService",
    "find_index_files",
    "parse_request",
]
